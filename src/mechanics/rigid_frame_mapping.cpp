#include "penalty/mechanics/rigid_frame_mapping.hpp"

#include "sofa_quaternion.hpp"
#include "sofa_vector_ops.hpp"

namespace penalty {

void RigidFrameMapping::set_frames(std::vector<RigidFrame> local, std::vector<Index> frame_index) {
    if (frame_index.size() != local.size())
        throw_invalid_argument("RigidMapping: ", frame_index.size(), " frame indices for ", local.size(), " frames");
    for (std::size_t i = 0; i < local.size(); ++i) {
        if (!local[i].center.allFinite() || !local[i].orientation.coeffs().allFinite())
            throw_invalid_argument("RigidMapping: local frame ", i, " is not finite");
        if (frame_index[i] < 0) throw_invalid_argument("RigidMapping: negative frame index ", frame_index[i]);
    }
    local_ = std::move(local);
    frame_ = std::move(frame_index);
    rotated_.assign(local_.size(), Vec3::Zero());
}

void RigidFrameMapping::init() {
    for (std::size_t i = 0; i < frame_.size(); ++i)
        if (static_cast<std::size_t>(frame_[i]) >= in_->num_dofs())
            throw_invalid_argument("RigidMapping: frame ", i, " uses input frame ", frame_[i], " out of range (",
                                   in_->num_dofs(), " frames)");
    Mapping::init();
}

// RigidMapping::apply: p_i = q_r·L_i (kept for J), x_i = in[r].mult(local_i).
void RigidFrameMapping::apply(std::span<RigidFrame> out, std::span<const RigidFrame> in) {
    PENALTY_DEMAND(out.size() == local_.size());
    for (std::size_t i = 0; i < local_.size(); ++i) {
        const RigidFrame& f = in[static_cast<std::size_t>(frame_[i])];
        rotated_[i] = sofa_quat::rotate(f.orientation, local_[i].center);
        out[i].center = f.center + sofa_quat::rotate(f.orientation, local_[i].center);
        out[i].orientation = sofa_quat::product(f.orientation, local_[i].orientation);
    }
}

void RigidFrameMapping::apply_j(std::span<RigidDeriv> out, std::span<const RigidDeriv> in) const {
    for (std::size_t i = 0; i < local_.size(); ++i) {
        const RigidDeriv& v = in[static_cast<std::size_t>(frame_[i])];
        out[i].linear = v.linear + sofa_vec::cross(v.angular, rotated_[i]);
        out[i].angular = v.angular;
    }
}

void RigidFrameMapping::apply_jt(std::span<RigidDeriv> in, std::span<const RigidDeriv> out) const {
    for (std::size_t i = 0; i < local_.size(); ++i) {
        RigidDeriv& f = in[static_cast<std::size_t>(frame_[i])];
        f.linear += out[i].linear;
        f.angular += out[i].angular + sofa_vec::cross(rotated_[i], out[i].linear);
    }
}

// Rows 6i..6i+2: I on the input's linear part, −[p]× on its angular part (ω × p = −[p]× ω);
// rows 6i+3..6i+5: I on the angular part.
void RigidFrameMapping::add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const {
    for (std::size_t i = 0; i < local_.size(); ++i) {
        const Index r = row_offset + 6 * static_cast<Index>(i);
        const Index c = col_offset + 6 * frame_[i];
        const Vec3& p = rotated_[i];
        const Mat3 minus_px = -(Mat3() << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0).finished();
        for (Index a = 0; a < 3; ++a) {
            t.emplace_back(r + a, c + a, 1.0);
            t.emplace_back(r + 3 + a, c + 3 + a, 1.0);
            for (Index b = 0; b < 3; ++b) t.emplace_back(r + a, c + 3 + b, minus_px(a, b));
        }
    }
}

}  // namespace penalty
