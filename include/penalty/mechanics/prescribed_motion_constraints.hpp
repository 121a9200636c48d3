#pragma once
/// @file
/// SOFA's projective constraints that prescribe a motion in time or restrict rotations:
/// LinearMovementProjectiveConstraint, ParabolicProjectiveConstraint (Vec3d and Rigid3d) and
/// FixedRotationProjectiveConstraint (Rigid3d). The time they read is the ContextClock's: SOFA's
/// getContext()->getTime(), the start of the step while it is solved and projected, so a
/// prescribed position lags one step behind the time the step reaches (as in SOFA).

#include "penalty/mechanics/force_field.hpp"

#include <type_traits>
#include <vector>

namespace penalty {

/// The zero derivative of a data type (Eigen's Vec3 is not zeroed by value-initialisation).
template <class Deriv>
[[nodiscard]] Deriv zero_deriv() {
    if constexpr (std::is_same_v<Deriv, Vec3>) return Vec3::Zero();
    else return Deriv{};
}

/// LinearMovementProjectiveConstraint: the listed DOFs follow a piecewise linear motion through
/// key movements m_k at key times t_k (ascending). At time t with t_0 ≤ t ≤ t_last, between
/// prev = the last key with t_k ≤ t and next = the first with t_k > t (LinearMovement::findKeyTimes;
/// none when t is the last key, so the motion then stops):
///   position: x = x0 + m (relative, x0 the position at the first projection) or x = m, with
///             m = m_prev + (m_next − m_prev)·s, s = (t − t_prev)/(t_next − t_prev); Rigid3d: the
///             centre so, the orientation x0's times the slerp (Quat::slerp2) of the keys'
///             Euler-angle rotations (createQuaterFromEuler of the angular part);
///   velocity: (m_next − m_prev)·(1/(t_next − t_prev)) (both parts for Rigid3d);
///   response: zero at the listed DOFs while a segment is found.
/// An assembled system discards every row of the listed DOFs at any time.
template <class DataTypes>
class LinearMovementProjectiveConstraint final : public BaseProjectiveConstraint {
public:
    using Coord = typename DataTypes::Coord;
    using Deriv = typename DataTypes::Deriv;
    LinearMovementProjectiveConstraint(MechanicalObject<DataTypes>& state, std::vector<Index> indices,
                                       std::vector<double> key_times, std::vector<Deriv> movements, bool relative,
                                       ContextClock clock);
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override;
    void project_position() override;
    [[nodiscard]] bool projects_positions() const override { return true; }
    [[nodiscard]] bool list_discarded_rows(std::vector<Index>& rows) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }
    /// New indices (a topological change: SOFA's TopologySubsetIndices d_indices). x0 is kept
    /// as it is, indexed by point (SOFA's x0 is not a topology data): a point renamed into a
    /// removed point's index moves from that point's initial position.
    void set_indices(std::vector<Index> indices) { indices_ = std::move(indices); }
    /// SOFA's x0: the positions taken at the first projection, indexed by point (empty before).
    [[nodiscard]] const std::vector<Coord>& initial_positions() const { return x0_; }

private:
    struct Segment {
        bool found = false;
        double prev_t = 0, next_t = 0;
        Deriv prev_m = zero_deriv<Deriv>(), next_m = zero_deriv<Deriv>();
    };
    /// LinearMovementProjectiveConstraint::findKeyTimes at time t.
    [[nodiscard]] Segment segment_at(double t) const;
    MechanicalObject<DataTypes>* state_;
    std::vector<Index> indices_;
    std::vector<double> key_times_;
    std::vector<Deriv> movements_;
    bool relative_;
    ContextClock clock_;
    std::vector<Coord> x0_;  ///< positions at the first projection (listed DOFs; SOFA's x0)
};

/// ParabolicProjectiveConstraint: between BeginTime and EndTime (inclusive) the listed DOFs
/// follow the parabola through P1, P2, P3 (distinct), parameterised in its plane (frame: x along
/// P1P3, z along P1P3 × P1P2; the rotation kept as a quaternion, Quat::fromMatrix then normalize):
/// local X = x₃·r, Y = a X² + b X with a = −y₂/(x₃x₂ − x₂²), b = x₃y₂/(x₃x₂ − x₂²),
/// r = (t − t_begin)/(t_end − t_begin);
///   position: P1 + R·(X, Y, 0) (Rigid3d: the centre only);
///   velocity: R·((X, Y)(t + dt) − (X, Y)(t))/dt for the first listed DOF, 0 for the others
///             (SOFA's projectVelocity overwrites r with r(t + dt) inside its loop over the
///             indices; set_every_index_velocity(true) fixes it) (Rigid3d: the linear part only);
///   response: zero at the listed DOFs inside the interval.
template <class DataTypes>
class ParabolicProjectiveConstraint final : public BaseProjectiveConstraint {
public:
    ParabolicProjectiveConstraint(MechanicalObject<DataTypes>& state, std::vector<Index> indices, const Vec3& p1,
                                  const Vec3& p2, const Vec3& p3, double begin_time, double end_time,
                                  ContextClock clock, ContextClock dt);
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override;
    void project_position() override;
    [[nodiscard]] bool projects_positions() const override { return true; }
    [[nodiscard]] BaseState* state() const override { return state_; }
    /// The point of the parabola at time t (m), t in [begin, end].
    [[nodiscard]] Vec3 point_at(double t) const;
    /// SOFA's d_indices, a TopologySubsetIndices (init's createTopologyHandler).
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }
    void set_indices(std::vector<Index> indices) { indices_ = std::move(indices); }
    /// `velocityForEveryIndex` (beyond SOFA): every listed DOF gets the parabola's velocity
    /// (false, SOFA: the first only, the others 0).
    void set_every_index_velocity(bool every) { every_index_velocity_ = every; }

private:
    [[nodiscard]] bool active(double t) const { return t >= begin_ && t <= end_; }
    /// (X, Y) of the parabola in its plane at relative time r.
    [[nodiscard]] std::pair<double, double> local_at(double r) const;
    MechanicalObject<DataTypes>* state_;
    std::vector<Index> indices_;
    Vec3 p1_, p2_, p3_;
    double begin_, end_;
    ContextClock clock_;
    ContextClock dt_;  ///< the node's time step (s), SOFA's getContext()->getDt()
    Quat projection_ = Quat::Identity();
    Vec3 loc_p2_ = Vec3::Zero(), loc_p3_ = Vec3::Zero();
    bool every_index_velocity_ = false;
};

/// FixedRotationProjectiveConstraint (Rigid3d): after each step the orientation of every DOF
/// keeps no twist about the fixed world axes (x, then y, then z): the current orientation's
/// twist about each fixed axis is removed (swing-twist decomposition: twist = (q⃗·a a, w)
/// normalised, swing = q·twist⁻¹) and the twist of the orientation at init about it put back.
/// Velocities and responses are not projected (SOFA's projectVelocity/projectResponse are empty).
class FixedRotationProjectiveConstraint final : public BaseProjectiveConstraint {
public:
    FixedRotationProjectiveConstraint(Rigid3Object& state, bool fixed_x, bool fixed_y, bool fixed_z)
        : state_(&state), fixed_{fixed_x, fixed_y, fixed_z} {}
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> /*v*/) const override {}
    void project_velocity() override {}
    void project_position() override;
    [[nodiscard]] bool projects_positions() const override { return true; }
    [[nodiscard]] BaseState* state() const override { return state_; }

private:
    Rigid3Object* state_;
    std::array<bool, 3> fixed_;
    std::vector<Quat> initial_;  ///< SOFA's previousOrientation (set at init, never updated)
};

extern template class LinearMovementProjectiveConstraint<Vec3Types>;
extern template class LinearMovementProjectiveConstraint<Rigid3Types>;
extern template class ParabolicProjectiveConstraint<Vec3Types>;
extern template class ParabolicProjectiveConstraint<Rigid3Types>;

}  // namespace penalty
