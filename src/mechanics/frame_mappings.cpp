#include "penalty/mechanics/frame_mappings.hpp"

#include "sofa_vector_ops.hpp"

#include "sofa_quaternion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty {

namespace {

using sofa_vec::minus;
using sofa_vec::plus;
using sofa_vec::times;
/// Mat·v, rows summed left to right (type::Mat::operator*(Vec)).
Vec3 product(const Mat3& m, const Vec3& v) {
    return {m(0, 0) * v[0] + m(0, 1) * v[1] + m(0, 2) * v[2], m(1, 0) * v[0] + m(1, 1) * v[1] + m(1, 2) * v[2],
            m(2, 0) * v[0] + m(2, 1) * v[1] + m(2, 2) * v[2]};
}
/// J's entries of ω ↦ ω × p (−[p]×) at rows first_row.., columns col.. .
void add_cross_block(TripletList& t, Index first_row, Index col, const Vec3& p, double scale) {
    // ω × p = (ω1 p2 − ω2 p1, ω2 p0 − ω0 p2, ω0 p1 − ω1 p0)
    t.emplace_back(first_row + 0, col + 1, scale * p[2]);
    t.emplace_back(first_row + 0, col + 2, -scale * p[1]);
    t.emplace_back(first_row + 1, col + 0, -scale * p[2]);
    t.emplace_back(first_row + 1, col + 2, scale * p[0]);
    t.emplace_back(first_row + 2, col + 0, scale * p[1]);
    t.emplace_back(first_row + 2, col + 1, -scale * p[0]);
}

}  // namespace

// ---- SkinningMapping ------------------------------------------------------------------------

std::size_t SkinningMapping::nb_ref_of(std::size_t point) const {
    // SkinningMapping: nbRef[i] when nbRef has one value per point, else nbRef[0]; penalty never
    // reads past a point's influences (SOFA would)
    const std::size_t n = nb_ref_.size() == influences_.size() && nb_ref_.size() > 1 ? std::size_t(nb_ref_[point])
                                                                                     : std::size_t(nb_ref_.at(0));
    return std::min(n, influences_[point].weights.size());
}

void SkinningMapping::compute_weights(std::span<const RigidFrame> frames) {
    // SkinningMapping::updateWeights: 1/d² to each frame (the largest double at d = 0), the
    // nb_ref largest kept by insertion (a new weight goes before equal ones), then normalised
    const std::size_t nb_ref = std::size_t(nb_ref_.at(0));
    influences_.assign(initial_points_.size(), {});
    for (std::size_t i = 0; i < initial_points_.size(); ++i) {
        Influences& in = influences_[i];
        in.frames.assign(nb_ref, 0);
        in.weights.assign(nb_ref, 0.0);
        const Vec3& x = initial_points_[i];
        for (std::size_t j = 0; j < frames.size(); ++j) {
            const Vec3 d = minus(x, frames[j].center);
            double w = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            w = w != 0 ? 1.0 / w : std::numeric_limits<double>::max();
            std::size_t m = 0;
            while (m != nb_ref && in.weights[m] > w) ++m;
            if (m == nb_ref) continue;
            for (std::size_t k = nb_ref - 1; k > m; --k) {
                in.weights[k] = in.weights[k - 1];
                in.frames[k] = in.frames[k - 1];
            }
            in.weights[m] = w;
            in.frames[m] = Index(j);
        }
        double sum = 0;
        for (const double w : in.weights) sum += w;
        if (sum != 0)
            for (double& w : in.weights) w /= sum;
    }
}

void SkinningMapping::init() {
    if (initial_points_.empty()) initial_points_ = out_->position;
    if (nb_ref_.empty()) throw_invalid_argument("SkinningMapping: nbRef is empty");
    for (const int n : nb_ref_)
        if (n < 1) throw_invalid_argument("SkinningMapping: nbRef must be >= 1, got ", n);
    const std::vector<RigidFrame>& frames = from_position_ ? in_->position : in_->rest_position;
    if (influences_.size() != initial_points_.size()) compute_weights(frames);
    for (std::size_t i = 0; i < influences_.size(); ++i) {
        const Influences& in = influences_[i];
        if (in.frames.size() != in.weights.size())
            throw_invalid_argument("SkinningMapping: point ", i, " has ", in.frames.size(), " frames and ",
                                   in.weights.size(), " weights");
        for (const Index f : in.frames)
            if (f < 0 || std::size_t(f) >= frames.size())
                throw_invalid_argument("SkinningMapping: point ", i, " uses frame ", f, " but the input has ",
                                       frames.size(), " frames");
    }
    // SkinningMapping::reinit: the weights normalised again, the weighted local points
    local_.assign(initial_points_.size(), {});
    rotated_.assign(initial_points_.size(), {});
    for (std::size_t i = 0; i < initial_points_.size(); ++i) {
        Influences& in = influences_[i];
        const std::size_t nb_ref = nb_ref_of(i);
        double sum = 0;
        for (std::size_t j = 0; j < nb_ref; ++j) sum += in.weights[j];
        if (sum != 0)
            for (std::size_t j = 0; j < nb_ref; ++j) in.weights[j] /= sum;
        for (std::size_t j = 0; j < nb_ref; ++j) {
            const RigidFrame& f = frames[std::size_t(in.frames[j])];
            const Vec3 from_center = minus(initial_points_[i], f.center);
            local_[i].push_back(times(sofa_quat::inverse_rotate(f.orientation, from_center), in.weights[j]));
            rotated_[i].push_back(times(from_center, in.weights[j]));
        }
    }
    Mapping::init();
}

void SkinningMapping::apply(std::span<Vec3> out, std::span<const RigidFrame> in) {
    for (std::size_t i = 0; i < out.size(); ++i) {
        Vec3 x = Vec3::Zero();
        const Influences& inf = influences_[i];
        for (std::size_t j = 0; j < local_[i].size() && inf.weights[j] > 0.; ++j) {
            const RigidFrame& f = in[std::size_t(inf.frames[j])];
            rotated_[i][j] = sofa_quat::rotate(f.orientation, local_[i][j]);
            x = plus(x, plus(times(f.center, inf.weights[j]), rotated_[i][j]));
        }
        out[i] = x;
    }
}

void SkinningMapping::apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const {
    for (std::size_t i = 0; i < out.size(); ++i) {
        Vec3 v = Vec3::Zero();
        const Influences& inf = influences_[i];
        for (std::size_t j = 0; j < local_[i].size() && inf.weights[j] > 0.; ++j) {
            const RigidDeriv& d = in[std::size_t(inf.frames[j])];
            v = plus(v, plus(times(d.linear, inf.weights[j]), sofa_vec::cross(d.angular, rotated_[i][j])));
        }
        out[i] = v;
    }
}

void SkinningMapping::apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const {
    for (std::size_t i = 0; i < out.size(); ++i) {
        const Influences& inf = influences_[i];
        for (std::size_t j = 0; j < local_[i].size() && inf.weights[j] > 0.; ++j) {
            RigidDeriv& d = in[std::size_t(inf.frames[j])];
            d.linear = plus(d.linear, times(out[i], inf.weights[j]));
            d.angular = plus(d.angular, sofa_vec::cross(rotated_[i][j], out[i]));
        }
    }
}

void SkinningMapping::add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const {
    for (std::size_t i = 0; i < local_.size(); ++i) {
        const Influences& inf = influences_[i];
        const Index row = row_offset + 3 * Index(i);
        for (std::size_t j = 0; j < local_[i].size() && inf.weights[j] > 0.; ++j) {
            const Index col = col_offset + 6 * inf.frames[j];
            for (Index a = 0; a < 3; ++a) t.emplace_back(row + a, col + a, inf.weights[j]);
            add_cross_block(t, row, col + 3, rotated_[i][j], 1.0);
        }
    }
}

// ---- DeformableOnRigidFrameMapping ----------------------------------------------------------

DeformableOnRigidFrameMapping::DeformableOnRigidFrameMapping(Vec3Object& deformable, Rigid3Object& frames,
                                                             Vec3Object& to, Index index, bool index_from_end,
                                                             std::vector<unsigned> repartition)
    : Mapping(deformable, to),
      frames_(&frames),
      index_(index),
      index_from_end_(index_from_end),
      repartition_(std::move(repartition)) {}

std::vector<Index> DeformableOnRigidFrameMapping::point_frames(std::size_t frame_count) const {
    const std::size_t points = in_->num_dofs();
    if (frame_count == 0) throw_invalid_argument("DeformableOnRigidFrameMapping: the frame input has no frame");
    const auto frame_index = [&] {
        if (index_ < 0 || std::size_t(index_) >= frame_count)
            throw_invalid_argument("DeformableOnRigidFrameMapping: index ", index_, " but the frame input has ",
                                   frame_count, " frames");
        return index_from_end_ ? Index(frame_count) - 1 - index_ : index_;
    };
    std::vector<Index> out;
    if (repartition_.empty()) {
        out.assign(points, frame_index());
    } else if (repartition_.size() == 1) {
        for (std::size_t f = 0; f < frame_count; ++f) out.insert(out.end(), repartition_[0], Index(f));
    } else {
        if (repartition_.size() != frame_count)
            throw_invalid_argument("DeformableOnRigidFrameMapping: repartition has ", repartition_.size(),
                                   " entries for ", frame_count, " frames");
        for (std::size_t f = 0; f < frame_count; ++f) out.insert(out.end(), repartition_[f], Index(f));
    }
    if (out.size() != points)
        throw_invalid_argument("DeformableOnRigidFrameMapping: the repartition places ", out.size(),
                               " points, the input has ", points);
    return out;
}

void DeformableOnRigidFrameMapping::init() {
    if (frames_->num_dofs() == 0) throw_invalid_argument("DeformableOnRigidFrameMapping: the frame input has no frame");
    (void)point_frames(frames_->num_dofs());  // checks index and repartition
    Mapping::init();
}

void DeformableOnRigidFrameMapping::apply_both(std::span<Vec3> out, std::span<const Vec3> in,
                                               std::span<const RigidFrame> frames) {
    point_frame_ = point_frames(frames.size());
    rotated_.resize(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
        const RigidFrame& f = frames[std::size_t(point_frame_[i])];
        root_ = f;
        // x = R·u (writeRotationMatrix, Mat·Vec) then += c
        rotated_[i] = product(sofa_quat::to_matrix(f.orientation), in[i]);
        out[i] = plus(rotated_[i], f.center);
    }
}

void DeformableOnRigidFrameMapping::apply_j_both(std::span<Vec3> out, std::span<const Vec3> in,
                                                 std::span<const RigidDeriv> frames) const {
    // SOFA's applyJ takes the velocity of frame `index` for every point (whatever the repartition)
    const std::size_t root = index_from_end_ ? frames.size() - 1 - std::size_t(index_) : std::size_t(index_);
    const Vec3& v = frames[root].linear;
    const Vec3& omega = frames[root].angular;
    for (std::size_t i = 0; i < in.size(); ++i)
        out[i] = plus(plus(sofa_vec::cross(omega, rotated_[i]), sofa_quat::rotate(root_.orientation, in[i])), v);
}

void DeformableOnRigidFrameMapping::apply_jt_both(std::span<Vec3> in, std::span<RigidDeriv> frames,
                                                  std::span<const Vec3> out) const {
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    for (std::size_t i = 0; i < out.size(); ++i) {
        force = plus(force, out[i]);
        torque = plus(torque, sofa_vec::cross(rotated_[i], out[i]));
    }
    RigidDeriv& root = frames[index_from_end_ ? frames.size() - 1 - std::size_t(index_) : std::size_t(index_)];
    root.linear = plus(root.linear, force);
    root.angular = plus(root.angular, torque);
    for (std::size_t i = 0; i < out.size(); ++i)
        in[i] = plus(in[i], sofa_quat::inverse_rotate(root_.orientation, out[i]));
}

void DeformableOnRigidFrameMapping::apply_j(std::span<Vec3> out, std::span<const Vec3> in) const {
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = sofa_quat::rotate(root_.orientation, in[i]);
}

void DeformableOnRigidFrameMapping::apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const {
    for (std::size_t i = 0; i < out.size(); ++i)
        in[i] = plus(in[i], sofa_quat::inverse_rotate(root_.orientation, out[i]));
}

void DeformableOnRigidFrameMapping::add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const {
    const Mat3 r = sofa_quat::to_matrix(root_.orientation);
    for (std::size_t i = 0; i < rotated_.size(); ++i)
        for (Index a = 0; a < 3; ++a)
            for (Index b = 0; b < 3; ++b)
                t.emplace_back(row_offset + 3 * Index(i) + a, col_offset + 3 * Index(i) + b, r(a, b));
}

void DeformableOnRigidFrameMapping::add_second_input_jacobian_triplets(TripletList& t, Index row_offset,
                                                                       Index col_offset) const {
    const std::size_t frames = frames_->num_dofs();
    const Index root = Index(index_from_end_ ? frames - 1 - std::size_t(index_) : std::size_t(index_));
    for (std::size_t i = 0; i < rotated_.size(); ++i) {
        const Index row = row_offset + 3 * Index(i);
        for (Index a = 0; a < 3; ++a) t.emplace_back(row + a, col_offset + 6 * root + a, 1.0);
        add_cross_block(t, row, col_offset + 6 * root + 3, rotated_[i], 1.0);
    }
}

// ---- DistanceFromTargetMapping --------------------------------------------------------------

DistanceFromTargetMapping::DistanceFromTargetMapping(Vec3Object& from, Vec1Object& to, std::vector<Index> indices,
                                                     std::vector<Vec3> targets, std::vector<double> rest_lengths,
                                                     int geometric_stiffness)
    : Mapping(from, to),
      indices_(std::move(indices)),
      targets_(std::move(targets)),
      rest_lengths_(std::move(rest_lengths)),
      geometric_stiffness_mode_(geometric_stiffness) {
    if (geometric_stiffness < 0 || geometric_stiffness > 2)
        throw_invalid_argument("DistanceFromTargetMapping: geometricStiffness must be 0, 1 or 2, got ",
                               geometric_stiffness);
    geometric_stiffness_ = geometric_stiffness != 0;
}

void DistanceFromTargetMapping::init() {
    // DistanceFromTargetMapping::init: missing indices are 0, 1, ...; missing rest lengths 0
    for (std::size_t i = indices_.size(); i < targets_.size(); ++i) indices_.push_back(Index(i));
    if (indices_.size() != targets_.size())
        throw_invalid_argument("DistanceFromTargetMapping: ", indices_.size(), " indices for ", targets_.size(),
                               " targets");
    if (rest_lengths_.size() != indices_.size()) rest_lengths_.resize(indices_.size(), 0.0);
    for (const Index i : indices_)
        if (i < 0 || std::size_t(i) >= in_->num_dofs())
            throw_invalid_argument("DistanceFromTargetMapping: index ", i, " but the input has ", in_->num_dofs(),
                                   " points");
    Mapping::init();
}

void DistanceFromTargetMapping::apply(std::span<double> out, std::span<const Vec3> in) {
    directions_.resize(indices_.size());
    inverse_lengths_.resize(indices_.size());
    for (std::size_t i = 0; i < indices_.size(); ++i) {
        Vec3 gap = minus(in[std::size_t(indices_[i])], targets_[i]);
        const double norm = std::sqrt(gap[0] * gap[0] + gap[1] * gap[1] + gap[2] * gap[2]);
        out[i] = norm - rest_lengths_[i];
        if (norm > 1.e-10) {
            inverse_lengths_[i] = 1 / norm;
            gap = times(gap, inverse_lengths_[i]);
        } else {
            inverse_lengths_[i] = 0;
            gap = Vec3(1.0, 0.0, 0.0);
        }
        directions_[i] = gap;
    }
}

void DistanceFromTargetMapping::apply_j(std::span<double> out, std::span<const Vec3> in) const {
    // the Jacobian's rows (CompressedRowSparseMatrix::mult): 0, then += u_k·x_k in column order
    for (std::size_t i = 0; i < indices_.size(); ++i) {
        const Vec3& x = in[std::size_t(indices_[i])];
        double r = 0.0;
        for (int k = 0; k < 3; ++k) r += directions_[i][k] * x[k];
        out[i] = r;
    }
}

void DistanceFromTargetMapping::apply_jt(std::span<Vec3> in, std::span<const double> out) const {
    for (std::size_t i = 0; i < indices_.size(); ++i) {
        Vec3& f = in[std::size_t(indices_[i])];
        for (int k = 0; k < 3; ++k) f[k] += directions_[i][k] * out[i];
    }
}

void DistanceFromTargetMapping::add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const {
    for (std::size_t i = 0; i < indices_.size(); ++i)
        for (Index k = 0; k < 3; ++k)
            t.emplace_back(row_offset + Index(i), col_offset + 3 * indices_[i] + k, directions_[i][k]);
}

void DistanceFromTargetMapping::add_geometric_stiffness(std::span<Vec3> df, std::span<const Vec3> dx,
                                                        std::span<const double> force, double k_factor) const {
    if (geometric_stiffness_mode_ == 0) return;
    for (std::size_t i = 0; i < indices_.size(); ++i) {
        // "Stabilized": only the outputs pulled apart (f < 0); "Exact": all
        if (!(force[i] < 0 || geometric_stiffness_mode_ == 1)) continue;
        const Vec3& u = directions_[i];
        Mat3 b;
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) b(j, k) = 1.0 * (j == k) - u[j] * u[k];
        const double scale = force[i] * inverse_lengths_[i] * k_factor;
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) b(j, k) *= scale;
        const Vec3& d = dx[std::size_t(indices_[i])];
        Vec3 change = Vec3::Zero();
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) change[j] += b(j, k) * d[k];
        Vec3& target = df[std::size_t(indices_[i])];
        target = plus(target, change);
    }
}

void DistanceFromTargetMapping::apply_djt(double k_factor) {
    add_geometric_stiffness(in_->df, in_->dx, out_->force, k_factor);
}

}  // namespace penalty
