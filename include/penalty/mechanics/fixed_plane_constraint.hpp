#pragma once
/// @file
/// SOFA's FixedPlaneProjectiveConstraint: removes the component along `direction` of the
/// responses of chosen DOFs (Vec3d, or the linear part of Rigid3d).

#include "penalty/mechanics/followed_indices.hpp"
#include "penalty/mechanics/force_field.hpp"

#include <span>
#include <vector>

namespace penalty {

/// For each listed DOF i, projected vectors (the solver's b, q = A p, Δv) get
/// u_i ← u_i − d (u_i·d), d = `direction` as written (SOFA does not normalise it: with |d| ≠ 1
/// this is not a projection). Positions and velocities are not altered
/// (FixedPlaneProjectiveConstraint::projectPosition / projectVelocity do nothing). An index listed
/// twice is projected twice, as in SOFA. The indices may follow an engine's output while the
/// scene runs (followed_indices.hpp; SOFA reads d_indices at each projection).
class FixedPlaneProjectiveConstraint final : public BaseProjectiveConstraint, public FollowedIndices {
public:
    FixedPlaneProjectiveConstraint(BaseState& state, const Vec3& direction) : state_(&state), direction_(direction) {}
    void set_indices(std::vector<Index> indices) { indices_ = std::move(indices); }
    /// The indices as of their last read (the index source is not called).
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }
    [[nodiscard]] const Vec3& direction() const { return direction_; }

    /// Checks the indices against the state size (std::invalid_argument when out of range).
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override {}
    /// The components c of each listed DOF with direction[c] ≠ 0
    /// (FixedPlaneProjectiveConstraint::applyConstraint: the matrix loses the whole component, so
    /// a direction off the axes fixes more than the projection does).
    [[nodiscard]] bool list_discarded_rows(std::vector<Index>& rows) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }

private:
    BaseState* state_;
    Vec3 direction_;
    mutable std::vector<Index> indices_;
};

/// FixedPlaneProjectiveConstraint::selectVerticesAlongPlane: the indices of the points with
/// dmin < p·d < dmax (strict), increasing.
[[nodiscard]] std::vector<Index> points_between_planes(std::span<const Vec3> points, const Vec3& direction, double dmin,
                                                       double dmax);

}  // namespace penalty
