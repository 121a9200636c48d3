#include "penalty/mechanics/mapping.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

namespace penalty {

namespace {
Mat3 cross_matrix(const Vec3& a) {
    Mat3 m;
    m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return m;
}
}  // namespace

// ---- IdentityMapping --------------------------------------------------------------------------
void IdentityMapping::apply(std::span<Vec3> out, std::span<const Vec3> in) {
    PENALTY_DEMAND(out.size() == in.size());
    std::copy(in.begin(), in.end(), out.begin());
}
void IdentityMapping::apply_j(std::span<Vec3> out, std::span<const Vec3> in) const {
    PENALTY_DEMAND(out.size() == in.size());
    std::copy(in.begin(), in.end(), out.begin());
}
void IdentityMapping::apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) in[i] += out[i];
}
void IdentityMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (Index i = 0; i < static_cast<Index>(3 * in_->num_dofs()); ++i) t.emplace_back(ro + i, co + i, 1.0);
}

// ---- Rigid3 -> Vec3 identity ------------------------------------------------------------------
void RigidCenterIdentityMapping::apply(std::span<Vec3> out, std::span<const RigidFrame> in) {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = in[i].center;
}
void RigidCenterIdentityMapping::apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = in[i].linear;
}
void RigidCenterIdentityMapping::apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) in[i].linear += out[i];
}
void RigidCenterIdentityMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (Index i = 0; i < static_cast<Index>(in_->num_dofs()); ++i)
        for (Index a = 0; a < 3; ++a) t.emplace_back(ro + 3 * i + a, co + 6 * i + a, 1.0);
}

// ---- RigidMapping -----------------------------------------------------------------------------
void RigidMapping::set_points(std::vector<Vec3> local_points, std::vector<Index> frame_index) {
    for (std::size_t i = 0; i < local_points.size(); ++i)
        if (!local_points[i].allFinite()) throw_invalid_argument("RigidMapping: local point ", i, " is not finite");
    if (!frame_index.empty() && frame_index.size() != local_points.size())
        throw_invalid_argument("RigidMapping: ", frame_index.size(), " frame indices for ", local_points.size(), " points");
    for (const Index r : frame_index)
        if (r < 0) throw_invalid_argument("RigidMapping: negative frame index ", r);
    local_ = std::move(local_points);
    frame_ = std::move(frame_index);
    rotated_.assign(local_.size(), Vec3::Zero());
}

void RigidMapping::set_points_from_world(std::span<const Vec3> world, std::vector<Index> frame_index) {
    if (in_->num_dofs() == 0) throw_invalid_argument("RigidMapping: input state has no frame");
    std::vector<Vec3> local(world.size());
    for (std::size_t i = 0; i < world.size(); ++i) {
        const std::size_t r = frame_index.empty() ? 0 : static_cast<std::size_t>(frame_index[i]);
        if (r >= in_->num_dofs()) throw_invalid_argument("RigidMapping: frame index ", r, " out of range");
        const RigidFrame& f = in_->position[r];
        local[i] = f.orientation.conjugate() * (world[i] - f.center);
    }
    set_points(std::move(local), std::move(frame_index));
}

void RigidMapping::init() {
    for (std::size_t i = 0; i < local_.size(); ++i)
        if (frame_of(i) >= in_->num_dofs())
            throw_invalid_argument("RigidMapping: point ", i, " uses frame ", frame_of(i), " out of range (", in_->num_dofs(), " frames)");
    Mapping::init();
}

std::size_t RigidMapping::frame_of(std::size_t i) const { return frame_.empty() ? 0 : static_cast<std::size_t>(frame_[i]); }

void RigidMapping::apply(std::span<Vec3> out, std::span<const RigidFrame> in) {
    PENALTY_DEMAND(out.size() == local_.size());
    rotated_.resize(local_.size());
    for (std::size_t i = 0; i < local_.size(); ++i) {
        const RigidFrame& f = in[frame_of(i)];
        rotated_[i] = f.orientation * local_[i];
        out[i] = f.center + rotated_[i];
    }
}
void RigidMapping::apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const {
    for (std::size_t i = 0; i < local_.size(); ++i) {
        const RigidDeriv& v = in[frame_of(i)];
        out[i] = v.linear + v.angular.cross(rotated_[i]);
    }
}
void RigidMapping::apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const {
    for (std::size_t i = 0; i < local_.size(); ++i) {
        RigidDeriv& f = in[frame_of(i)];
        f.linear += out[i];
        f.angular += rotated_[i].cross(out[i]);
    }
}
void RigidMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (std::size_t i = 0; i < local_.size(); ++i) {
        const Index r = ro + 3 * static_cast<Index>(i);
        const Index c = co + 6 * static_cast<Index>(frame_of(i));
        const Mat3 w = -cross_matrix(rotated_[i]);  // ω × p = −[p]× ω
        for (Index a = 0; a < 3; ++a) {
            t.emplace_back(r + a, c + a, 1.0);
            for (Index b = 0; b < 3; ++b) t.emplace_back(r + a, c + 3 + b, w(a, b));
        }
    }
}

// ---- BarycentricMapping -----------------------------------------------------------------------
std::array<double, 8> trilinear_weights(const Vec3& p) {
    const double u = p.x(), v = p.y(), w = p.z();
    return {(1 - u) * (1 - v) * (1 - w), u * (1 - v) * (1 - w), u * v * (1 - w), (1 - u) * v * (1 - w),
            (1 - u) * (1 - v) * w,       u * (1 - v) * w,       u * v * w,       (1 - u) * v * w};
}

void BarycentricMapping::set_weights(std::vector<std::vector<Entry>> rows) {
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (const Entry& e : rows[i]) {
            if (e.index < 0) throw_invalid_argument("BarycentricMapping: point ", i, " uses a negative input index ", e.index);
            if (!std::isfinite(e.weight)) throw_invalid_argument("BarycentricMapping: point ", i, " has a non-finite weight");
        }
    rows_ = std::move(rows);
}

void BarycentricMapping::init() {
    for (std::size_t i = 0; i < rows_.size(); ++i)
        for (const Entry& e : rows_[i])
            if (static_cast<std::size_t>(e.index) >= in_->num_dofs())
                throw_invalid_argument("BarycentricMapping: point ", i, " uses input index ", e.index, " out of range (",
                                       in_->num_dofs(), " input DOFs)");
    Mapping::init();
}

void BarycentricMapping::map_on_tetrahedra(const MeshTopology& topo, std::span<const Vec3> x, std::span<const Vec3> points) {
    const auto& tetras = topo.tetrahedra();
    if (tetras.empty()) throw_invalid_argument("BarycentricMapping: topology has no tetrahedron");
    std::vector<Mat3> inv(tetras.size());
    for (std::size_t t = 0; t < tetras.size(); ++t) {
        for (const PointId p : tetras[t])
            if (static_cast<std::size_t>(p) >= x.size()) throw_invalid_argument("BarycentricMapping: tetrahedron ", t, " vertex out of range");
        const Vec3& x0 = x[static_cast<std::size_t>(tetras[t][0])];
        Mat3 m;
        for (int k = 0; k < 3; ++k) m.col(k) = x[static_cast<std::size_t>(tetras[t][static_cast<std::size_t>(k + 1)])] - x0;
        if (std::abs(m.determinant()) < 1e-300) throw_invalid_argument("BarycentricMapping: tetrahedron ", t, " is degenerate");
        inv[t] = m.inverse();
    }
    std::vector<std::vector<Entry>> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t t = 0; t < tetras.size(); ++t) {
            const Vec3 b = inv[t] * (points[i] - x[static_cast<std::size_t>(tetras[t][0])]);
            const double d = std::max(std::max(-b[0], -b[1]), std::max(-b[2], b.sum() - 1.0));
            if (d < best) {
                best = d;
                rows[i] = {{tetras[t][0], 1.0 - b.sum()}, {tetras[t][1], b[0]}, {tetras[t][2], b[1]}, {tetras[t][3], b[2]}};
            }
        }
    }
    set_weights(std::move(rows));
}

void BarycentricMapping::map_on_hexahedra(const MeshTopology& topo, std::span<const Vec3> x, std::span<const Vec3> points) {
    const auto& hexas = topo.hexahedra();
    if (hexas.empty()) throw_invalid_argument("BarycentricMapping: topology has no hexahedron");
    std::vector<std::vector<Entry>> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t h = 0; h < hexas.size(); ++h) {
            std::array<Vec3, 8> c;
            for (std::size_t k = 0; k < 8; ++k) {
                const auto p = static_cast<std::size_t>(hexas[h][k]);
                if (p >= x.size()) throw_invalid_argument("BarycentricMapping: hexahedron ", h, " vertex out of range");
                c[k] = x[p];
            }
            // Newton on φ(u) = Σ w_k(u) c_k − p, from the centre.
            Vec3 u(0.5, 0.5, 0.5);
            for (int it = 0; it < 20; ++it) {
                const auto w = trilinear_weights(u);
                Vec3 r = -points[i];
                for (std::size_t k = 0; k < 8; ++k) r += w[k] * c[k];
                const double uu = u.x(), vv = u.y(), ww = u.z();
                const Vec3 du = (1 - vv) * (1 - ww) * (c[1] - c[0]) + vv * (1 - ww) * (c[2] - c[3]) +
                                (1 - vv) * ww * (c[5] - c[4]) + vv * ww * (c[6] - c[7]);
                const Vec3 dv = (1 - uu) * (1 - ww) * (c[3] - c[0]) + uu * (1 - ww) * (c[2] - c[1]) +
                                (1 - uu) * ww * (c[7] - c[4]) + uu * ww * (c[6] - c[5]);
                const Vec3 dw = (1 - uu) * (1 - vv) * (c[4] - c[0]) + uu * (1 - vv) * (c[5] - c[1]) +
                                uu * vv * (c[6] - c[2]) + (1 - uu) * vv * (c[7] - c[3]);
                Mat3 jac;
                jac << du, dv, dw;
                if (std::abs(jac.determinant()) < 1e-300) throw_invalid_argument("BarycentricMapping: hexahedron ", h, " is degenerate");
                const Vec3 step = jac.lu().solve(r);
                u -= step;
                if (step.norm() < 1e-15) break;
            }
            const double d = std::max({-u.x(), -u.y(), -u.z(), u.x() - 1, u.y() - 1, u.z() - 1});
            if (d < best) {
                best = d;
                const auto w = trilinear_weights(u);
                rows[i].clear();
                for (std::size_t k = 0; k < 8; ++k) rows[i].push_back({hexas[h][k], w[k]});
            }
        }
    }
    set_weights(std::move(rows));
}

void BarycentricMapping::apply(std::span<Vec3> out, std::span<const Vec3> in) {
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        Vec3 s = Vec3::Zero();
        for (const Entry& e : rows_[i]) s += e.weight * in[static_cast<std::size_t>(e.index)];
        out[i] = s;
    }
}
void BarycentricMapping::apply_j(std::span<Vec3> out, std::span<const Vec3> in) const {
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        Vec3 s = Vec3::Zero();
        for (const Entry& e : rows_[i]) s += e.weight * in[static_cast<std::size_t>(e.index)];
        out[i] = s;
    }
}
void BarycentricMapping::apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const {
    for (std::size_t i = 0; i < rows_.size(); ++i)
        for (const Entry& e : rows_[i]) in[static_cast<std::size_t>(e.index)] += e.weight * out[i];
}
void BarycentricMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (std::size_t i = 0; i < rows_.size(); ++i)
        for (const Entry& e : rows_[i])
            for (Index a = 0; a < 3; ++a) t.emplace_back(ro + 3 * static_cast<Index>(i) + a, co + 3 * e.index + a, e.weight);
}

}  // namespace penalty
