#pragma once
/// @file
/// SOFA's geometric projective constraints on one state (Constraint/Projective): points kept on a
/// line, a plane, a direction through their initial position, at a point, or fixed along some
/// axes. Each projects the solver's vectors (project_response), the velocity and the positions as
/// SOFA's class does (docs/components/projective_constraints.md cites the methods).
///
/// Indices: SOFA's d_indices in the order written; init() refuses an index past the state's size
/// (SOFA drops it with an error message). Line, Plane and Direction build SOFA's block-diagonal
/// jacobian from the indices sorted: an index written twice leaves the indices after it
/// unprojected in the responses (the jacobian's insertion loop stops matching), reproduced.

#include "penalty/mechanics/followed_indices.hpp"
#include "penalty/mechanics/force_field.hpp"

#include <array>
#include <vector>

namespace penalty {

/// Line, Plane and Direction: the response and velocity of each constrained point are multiplied
/// by a 3×3 block P (P² = P): n nᵀ (onto the line or direction n), I − n nᵀ (onto the plane of
/// normal n); the other points keep theirs. The product per point is SOFA's sparse product: row
/// r of the result = P(r,0)u₀ + P(r,1)u₁ + P(r,2)u₂, left to right, P(r,c) = n_r·n_c rounded
/// once. Vec3d states only (SOFA's Vec2/Vec1 variants have no penalty state).
class BlockProjectionConstraint : public BaseProjectiveConstraint {
public:
    BlockProjectionConstraint(Vec3Object& state, std::vector<Index> indices, const char* component)
        : state_(&state), indices_(std::move(indices)), component_(component) {}
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }
    /// New indices (a topological change: TopologySubsetIndices), and the block projection built
    /// again for them, as SOFA's projectResponse rebuilds its jacobian when the state's size changed.
    void set_indices(std::vector<Index> indices) {
        indices_ = std::move(indices);
        following_topology_ = true;
        if (!keeps_projection_on_topology_change()) init();
    }
    /// The 3×3 block applied to a constrained point (after init).
    [[nodiscard]] const Mat3& block() const { return block_; }
    /// The points the responses are projected at (sorted; see the file comment for duplicates).
    [[nodiscard]] const std::vector<Index>& projected_points() const { return projected_; }
    [[nodiscard]] const Vec3& unit_direction() const { return n_; }

    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override;
    [[nodiscard]] bool projects_positions() const override { return true; }
    [[nodiscard]] BaseState* state() const override { return state_; }

protected:
    /// n from the written vector (each class's normalisation rule) and the block from n.
    virtual void make_block() = 0;
    /// Set once the indices followed a topological change (set_indices).
    bool following_topology_ = false;
    /// True when a topological change leaves the block projection as init made it (SOFA's
    /// DirectionProjectiveConstraint: its jacobian is made by reinit only).
    [[nodiscard]] virtual bool keeps_projection_on_topology_change() const { return false; }
    Vec3Object* state_;
    std::vector<Index> indices_;
    const char* component_;  ///< SOFA's class name, for errors
    Vec3 n_ = Vec3::Zero();
    Mat3 block_ = Mat3::Identity();
    std::vector<Index> projected_;
};

/// LineProjectiveConstraint: points on the line through `origin` along `direction` (normalised;
/// a zero direction becomes (1, 0, 0)). P = n nᵀ; position x ← o + n ((x − o)·n).
class LineProjectiveConstraint final : public BlockProjectionConstraint {
public:
    LineProjectiveConstraint(Vec3Object& state, std::vector<Index> indices, const Vec3& origin, const Vec3& direction)
        : BlockProjectionConstraint(state, std::move(indices), "LineProjectiveConstraint"),
          origin_(origin),
          direction_(direction) {}
    void project_position() override;

private:
    void make_block() override;
    Vec3 origin_, direction_;
};

/// PlaneProjectiveConstraint: points on the plane through `origin` of normal `normal`
/// (normalised; a zero normal stays zero, so the "projection" is the identity, as in SOFA).
/// P = I − n nᵀ; position x ← x − n ((x − o)·n).
class PlaneProjectiveConstraint final : public BlockProjectionConstraint {
public:
    PlaneProjectiveConstraint(Vec3Object& state, std::vector<Index> indices, const Vec3& origin, const Vec3& normal)
        : BlockProjectionConstraint(state, std::move(indices), "PlaneProjectiveConstraint"),
          origin_(origin),
          normal_(normal) {}
    void project_position() override;

private:
    void make_block() override;
    Vec3 origin_, normal_;
};

/// DirectionProjectiveConstraint: each point moves only along `direction` (normalised; zero stays
/// zero: the points are then fixed at their initial positions) through its position at init.
/// P = n nᵀ; position x_k ← o_k + n ((x_k − o_k)·n), o_k the k-th index's position at init.
/// After a topological change the origins stay in their slots (SOFA's m_origin is filled by
/// reinit only, not a topology data): o_k is still the initial position of the point that was
/// k-th at init, whichever point the k-th index now names. The responses and velocities keep the
/// projection of init too (SOFA's jacobian, made by reinit only, applied to the changed state:
/// its blocks at the points init constrained, those past the state's end ignored).
class DirectionProjectiveConstraint final : public BlockProjectionConstraint {
public:
    DirectionProjectiveConstraint(Vec3Object& state, std::vector<Index> indices, const Vec3& direction)
        : BlockProjectionConstraint(state, std::move(indices), "DirectionProjectiveConstraint"),
          direction_(direction) {}
    void project_position() override;
    [[nodiscard]] const std::vector<Vec3>& origins() const { return origins_; }

private:
    void make_block() override;
    [[nodiscard]] bool keeps_projection_on_topology_change() const override { return true; }
    Vec3 direction_;
    std::vector<Vec3> origins_;
};

/// PointProjectiveConstraint (Vec3d): the listed points (all with `fix_all`) are put at `point`,
/// with zero velocity and response. An assembled system discards their three rows.
class PointProjectiveConstraint final : public BaseProjectiveConstraint {
public:
    PointProjectiveConstraint(Vec3Object& state, std::vector<Index> indices, const Vec3& point, bool fix_all)
        : state_(&state), indices_(std::move(indices)), point_(point), fix_all_(fix_all) {}
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override;
    void project_position() override;
    [[nodiscard]] bool projects_positions() const override { return true; }
    [[nodiscard]] bool list_discarded_rows(std::vector<Index>& rows) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }
    /// New indices (a topological change: TopologySubsetIndices).
    void set_indices(std::vector<Index> indices) { indices_ = std::move(indices); }

private:
    Vec3Object* state_;
    std::vector<Index> indices_;
    Vec3 point_;
    bool fix_all_;
};

/// PartialFixedProjectiveConstraint (Vec3d, Rigid3d): the components c of the listed DOFs (all
/// with `fix_all`) with fixed_directions[c] get a zero response; their velocity too only with
/// `project_velocity` (SOFA's d_projectVelocity, default false); positions are left. Rigid3d:
/// six directions, linear then angular. An assembled system discards those rows. The indices may
/// follow an engine's output while the scene runs (followed_indices.hpp).
class PartialFixedProjectiveConstraint final : public BaseProjectiveConstraint, public FollowedIndices {
public:
    PartialFixedProjectiveConstraint(BaseState& state, std::vector<Index> indices, bool fix_all,
                                     std::vector<bool> fixed_directions, bool project_velocity)
        : state_(&state),
          indices_(std::move(indices)),
          fix_all_(fix_all),
          fixed_(std::move(fixed_directions)),
          project_velocity_(project_velocity) {}
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override;
    [[nodiscard]] bool list_discarded_rows(std::vector<Index>& rows) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    /// FixedProjectiveConstraint's d_indices (a TopologySubsetIndices), which it inherits, as of
    /// their last read (the index source is not called).
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }
    void set_indices(std::vector<Index> indices) { indices_ = std::move(indices); }

private:
    BaseState* state_;
    mutable std::vector<Index> indices_;
    bool fix_all_;
    std::vector<bool> fixed_;  ///< one per scalar of a Deriv
    bool project_velocity_;
};

/// Checks every index against the state's size: std::invalid_argument naming `component` and
/// the first index out of range.
void check_constraint_indices(const char* component, std::span<const Index> indices, std::size_t dofs);

}  // namespace penalty
