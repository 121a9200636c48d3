#pragma once
/// @file
/// SOFA's RigidMapping<Rigid3d, Rigid3d>: output frames rigidly attached to input frames. Output
/// frame i, attached to input frame r with the local frame (L_i, q_i) (SOFA's initialPoints):
///   x_out = (c_r + q_r·L_i, q_r ⊗ q_i)              (RigidCoord::mult, Quat::rotate);
///   v_out = (v_r + ω_r × p_i, ω_r), p_i = q_r·L_i at the last apply (velocityAtRotatedPoint);
///   Jᵀ:     f_r += f_i, τ_r += τ_i + p_i × f_i      (RigidMapping<Rigid3,Rigid3>::updateOmega),
/// every operation in SOFA's order. No geometric stiffness (SOFA's default, geometricStiffness 0).
/// Frame of each output: SOFA's getRigidIndex, rigidIndexPerPoint[i] when it has one entry per
/// output frame, else `index` for all.

#include "penalty/mechanics/mapping.hpp"

#include <vector>

namespace penalty {

class RigidFrameMapping final : public Mapping<Rigid3Types, Rigid3Types> {
public:
    RigidFrameMapping(Rigid3Object& from, Rigid3Object& to) : Mapping(from, to) {}
    /// Local frames in their input frames, and the input frame of each (same length).
    void set_frames(std::vector<RigidFrame> local, std::vector<Index> frame_index);
    [[nodiscard]] const std::vector<RigidFrame>& local_frames() const { return local_; }
    [[nodiscard]] const std::vector<Index>& frame_indices() const { return frame_; }
    /// Checks the frame indices against the input size, then sizes and computes the output.
    void init() override;

    void apply(std::span<RigidFrame> out, std::span<const RigidFrame> in) override;
    void apply_j(std::span<RigidDeriv> out, std::span<const RigidDeriv> in) const override;
    void apply_jt(std::span<RigidDeriv> in, std::span<const RigidDeriv> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return local_.size(); }

private:
    std::vector<RigidFrame> local_;
    std::vector<Index> frame_;
    std::vector<Vec3> rotated_;  ///< p_i = q_r·L_i at the last apply (SOFA's m_rotatedPoints)
};

}  // namespace penalty
