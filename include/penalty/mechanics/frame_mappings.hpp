#pragma once
/// @file
/// SOFA's mappings on rigid frames beyond RigidMapping, and the distance mapping:
///   - SkinningMapping Rigid3 → Vec3 (linear blend skinning): x_i = Σ_j (w_ij·c_j + R_j·L_ij), with
///     L_ij = w_ij·R_j0ᵀ(x_i0 − c_j0) the weighted local point of frame j at rest and w_ij the
///     normalised 1/d² weights of the `nbRef` nearest frames (or given weights);
///     J: v_i = Σ_j (w_ij·v_j + ω_j × p_ij), p_ij = R_j·L_ij; Jᵀ: f_j += w_ij·f_i, τ_j += p_ij × f_i.
///   - DeformableOnRigidFrameMapping (Vec3, Rigid3) → Vec3: a deformable body expressed in a moving
///     frame, x_i = R·u_i + c (u the deformable input, (c, R) the frame);
///     J: v_i = ω × (R·u_i) + R·u̇_i + v_c; Jᵀ: f_u_i += Rᵀ·f_i, f_c += Σ f_i, τ += Σ (R·u_i) × f_i.
///     No geometric stiffness (SOFA's applyDJT is empty).
///   - DistanceFromTargetMapping Vec3 → Vec1: d_i = |x_{k_i} − t_i| − L_i (t the targets, L the rest
///     lengths); J: ḋ_i = u_i·ẋ_{k_i}, u = (x − t)/|x − t| (the x axis when |x − t| ≤ 1e-10);
///     geometric stiffness (applyDJT, "Stabilized", SOFA's default): df_k += k·(f_i/|x − t|)·(I − uuᵀ)·dx_k
///     for the outputs pulled apart (f_i < 0).
/// Each follows SOFA's operation order (SkinningMapping.inl, DeformableOnRigidFrameMapping.inl,
/// DistanceFromTargetMapping.inl), so a mapped state agrees with SOFA's to the last bit.

#include "penalty/mechanics/mapping.hpp"

#include <optional>
#include <vector>

namespace penalty {

/// SkinningMapping Rigid3 → Vec3.
class SkinningMapping final : public Mapping<Rigid3Types, Vec3Types> {
public:
    /// Per output point: the frames and their weights (given in a scene, else computed at init).
    struct Influences {
        std::vector<Index> frames;
        std::vector<double> weights;
    };
    SkinningMapping(Rigid3Object& from, Vec3Object& to) : Mapping(from, to) {}

    /// The `nbRef` nearest frames per point (one value for all, or one per point; SOFA's default 4).
    void set_nb_ref(std::vector<int> nb_ref) { nb_ref_ = std::move(nb_ref); }
    /// Given influences (SOFA's `indices` and `weight`), one entry per output point.
    void set_influences(std::vector<Influences> influences) { influences_ = std::move(influences); }
    /// Weights from the frames' positions instead of their rest positions (computeWeightsFromPosition).
    void set_weights_from_position(bool from_position) { from_position_ = from_position; }
    /// The points' initial world positions (SOFA's `initPos`; default: the output's positions).
    void set_initial_points(std::vector<Vec3> points) { initial_points_ = std::move(points); }
    /// Computes the weights (when not given), normalises them and the local points, then maps.
    void init() override;

    void apply(std::span<Vec3> out, std::span<const RigidFrame> in) override;
    void apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const override;
    void apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return initial_points_.size(); }
    [[nodiscard]] const std::vector<Influences>& influences() const { return influences_; }

private:
    [[nodiscard]] std::size_t nb_ref_of(std::size_t point) const;
    void compute_weights(std::span<const RigidFrame> frames);
    std::vector<int> nb_ref_{4};
    std::vector<Influences> influences_;
    bool from_position_ = false;
    std::vector<Vec3> initial_points_;
    std::vector<std::vector<Vec3>> local_;    ///< w·Rᵀ(x0 − c), per point and influence
    std::vector<std::vector<Vec3>> rotated_;  ///< R·local at the last apply
};

/// DeformableOnRigidFrameMapping (Vec3, Rigid3) → Vec3; from() is the deformable input,
/// second_from() the frames.
class DeformableOnRigidFrameMapping final : public Mapping<Vec3Types, Vec3Types> {
public:
    /// `repartition`: SOFA's d_repartition (empty: every point on frame `index`; one value n: n
    /// points per frame in turn; one value per frame: that many points each).
    DeformableOnRigidFrameMapping(Vec3Object& deformable, Rigid3Object& frames, Vec3Object& to, Index index = 0,
                                  bool index_from_end = false, std::vector<unsigned> repartition = {});

    [[nodiscard]] BaseState* second_from() const override { return frames_; }
    void init() override;
    void apply_position() override { apply_both(out_->position, in_->position, frames_->position); }
    void apply_velocity() override { apply_j_both(out_->velocity, in_->velocity, frames_->velocity); }
    void apply_dx() override { apply_j_both(out_->dx, in_->dx, frames_->dx); }
    void apply_jt_force() override { apply_jt_both(in_->force, frames_->force, out_->force); }
    void apply_jt_df() override { apply_jt_both(in_->df, frames_->df, out_->df); }
    void add_second_input_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;

    /// x = R·u + c for the frames' positions `frames` (records R·u and the frame for J).
    void apply_both(std::span<Vec3> out, std::span<const Vec3> in, std::span<const RigidFrame> frames);
    /// J·(u̇, frame velocities).
    void apply_j_both(std::span<Vec3> out, std::span<const Vec3> in, std::span<const RigidDeriv> frames) const;
    /// Jᵀ: in += Rᵀ f, frames += (Σ f, Σ R·u × f).
    void apply_jt_both(std::span<Vec3> in, std::span<RigidDeriv> frames, std::span<const Vec3> out) const;

    // The single-input interface: the deformable input's block of J (the frame fixed).
    void apply(std::span<Vec3> out, std::span<const Vec3> in) override { apply_both(out, in, frames_->position); }
    void apply_j(std::span<Vec3> out, std::span<const Vec3> in) const override;
    void apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return in_->num_dofs(); }

private:
    /// The frame each output point follows, for `frame_count` frames (SOFA's repartition).
    [[nodiscard]] std::vector<Index> point_frames(std::size_t frame_count) const;
    Rigid3Object* frames_;
    Index index_;
    bool index_from_end_;
    std::vector<unsigned> repartition_;
    std::vector<Vec3> rotated_;       ///< R·u_i at the last apply
    std::vector<Index> point_frame_;  ///< frame of each point at the last apply
    RigidFrame root_;                 ///< SOFA's rootX: the last frame used by apply
};

/// DistanceFromTargetMapping Vec3 → Vec1.
class DistanceFromTargetMapping final : public Mapping<Vec3Types, Vec1Types> {
public:
    /// `indices`: the input points (empty: 0 .. targets − 1, SOFA's init); `rest_lengths` padded
    /// with 0; `geometric_stiffness`: 0 none, 1 exact, 2 stabilized (SOFA's default).
    DistanceFromTargetMapping(Vec3Object& from, Vec1Object& to, std::vector<Index> indices, std::vector<Vec3> targets,
                              std::vector<double> rest_lengths, int geometric_stiffness = 2);
    void init() override;
    void apply(std::span<double> out, std::span<const Vec3> in) override;
    void apply_j(std::span<double> out, std::span<const Vec3> in) const override;
    void apply_jt(std::span<Vec3> in, std::span<const double> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return indices_.size(); }
    /// from.df += k·Σ_i (f_i/l_i)(I − u_i u_iᵀ)·dx_{k_i} for f = to.force (SOFA's matrixFreeApplyDJT).
    void apply_djt(double k_factor) override;
    /// The same geometric stiffness for an output force `force`, into `df` from `dx` (tests).
    void add_geometric_stiffness(std::span<Vec3> df, std::span<const Vec3> dx, std::span<const double> force,
                                 double k_factor) const;

private:
    std::vector<Index> indices_;
    std::vector<Vec3> targets_;
    std::vector<double> rest_lengths_;
    int geometric_stiffness_mode_;
    std::vector<Vec3> directions_;         ///< u at the last apply
    std::vector<double> inverse_lengths_;  ///< 1/|x − t| (0 below 1e-10)
};

}  // namespace penalty
