#include "penalty/mechanics/prescribed_motion_constraints.hpp"

#include "penalty/mechanics/projective_constraints.hpp"
#include "sofa_quaternion.hpp"
#include "sofa_vector_ops.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

namespace {

// Deriv arithmetic, component by component as SOFA's Vec and RigidDeriv operators.
using sofa_vec::minus;
RigidDeriv minus(const RigidDeriv& a, const RigidDeriv& b) { return {a.linear - b.linear, a.angular - b.angular}; }
using sofa_vec::plus;
RigidDeriv plus(const RigidDeriv& a, const RigidDeriv& b) { return {a.linear + b.linear, a.angular + b.angular}; }
using sofa_vec::times;
RigidDeriv times(const RigidDeriv& a, double s) { return {a.linear * s, a.angular * s}; }

/// LinearMovement's interpolated position of one DOF (interpolatePosition), Vec3d.
Vec3 moved(const Vec3& x0, const Vec3& m, const Vec3& /*prev*/, const Vec3& /*next*/, double /*s*/, bool relative) {
    return relative ? Vec3(x0 + m) : m;
}
/// Rigid3d: the centre as Vec3d; the orientation x0's (relative) times slerp2 of the keys'
/// createQuaterFromEuler(angular part).
RigidFrame moved(const RigidFrame& x0, const RigidDeriv& m, const RigidDeriv& prev, const RigidDeriv& next, double s,
                 bool relative) {
    const Quat from = sofa_quat::from_euler_zyx(prev.angular);
    const Quat to = sofa_quat::from_euler_zyx(next.angular);
    const Quat turn = sofa_quat::slerp2(from, to, s);
    RigidFrame x;
    x.center = relative ? Vec3(x0.center + m.linear) : m.linear;
    x.orientation = relative ? sofa_quat::product(x0.orientation, turn) : turn;
    return x;
}

}  // namespace

// ---- LinearMovementProjectiveConstraint -------------------------------------------------------
template <class DataTypes>
LinearMovementProjectiveConstraint<DataTypes>::LinearMovementProjectiveConstraint(MechanicalObject<DataTypes>& state,
                                                                                  std::vector<Index> indices,
                                                                                  std::vector<double> key_times,
                                                                                  std::vector<Deriv> movements,
                                                                                  bool relative, ContextClock clock)
    : state_(&state),
      indices_(std::move(indices)),
      key_times_(std::move(key_times)),
      movements_(std::move(movements)),
      relative_(relative),
      clock_(std::move(clock)) {}

template <class DataTypes>
void LinearMovementProjectiveConstraint<DataTypes>::init() {
    check_constraint_indices("LinearMovementProjectiveConstraint", indices_, state_->num_dofs());
    if (movements_.size() < key_times_.size())
        throw_invalid_argument("LinearMovementProjectiveConstraint: ", key_times_.size(), " key times but ",
                               movements_.size(), " movements");
    x0_.clear();  // SOFA's init: x0 is taken again at the next projection
}

template <class DataTypes>
auto LinearMovementProjectiveConstraint<DataTypes>::segment_at(double t) const -> Segment {
    Segment s;
    if (key_times_.empty() || !(t >= key_times_.front() && t <= key_times_.back())) return s;
    s.next_t = s.prev_t = key_times_.front();
    for (std::size_t k = 0; k < key_times_.size() && !s.found; ++k) {
        if (key_times_[k] <= t) {
            s.prev_t = key_times_[k];
            s.prev_m = movements_[k];
        } else {
            s.next_t = key_times_[k];
            s.next_m = movements_[k];
            s.found = true;
        }
    }
    return s;
}

template <class DataTypes>
void LinearMovementProjectiveConstraint<DataTypes>::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    const Segment s = segment_at(clock_());
    if (!s.found || s.next_t == s.prev_t) return;
    const std::span<Deriv> u = as_derivs<DataTypes>(v);
    for (Index i : indices_) u[static_cast<std::size_t>(i)] = zero_deriv<Deriv>();
}

template <class DataTypes>
void LinearMovementProjectiveConstraint<DataTypes>::project_velocity() {
    const Segment s = segment_at(clock_());
    if (!s.found || s.next_t == s.prev_t) return;
    const Deriv velocity = times(minus(s.next_m, s.prev_m), 1.0 / (s.next_t - s.prev_t));
    for (Index i : indices_) state_->velocity[static_cast<std::size_t>(i)] = velocity;
}

template <class DataTypes>
void LinearMovementProjectiveConstraint<DataTypes>::project_position() {
    const double t = clock_();
    if (x0_.empty()) {
        x0_.resize(state_->num_dofs());
        for (Index i : indices_) x0_[static_cast<std::size_t>(i)] = state_->position[static_cast<std::size_t>(i)];
    }
    const Segment s = segment_at(t);
    if (!s.found || s.next_t == s.prev_t) return;
    const double fraction = (t - s.prev_t) / (s.next_t - s.prev_t);
    const Deriv m = plus(s.prev_m, times(minus(s.next_m, s.prev_m), fraction));
    for (Index i : indices_) {
        const auto k = static_cast<std::size_t>(i);
        state_->position[k] = moved(x0_[k], m, s.prev_m, s.next_m, fraction, relative_);
    }
}

template <class DataTypes>
bool LinearMovementProjectiveConstraint<DataTypes>::list_discarded_rows(std::vector<Index>& rows) const {
    for (Index i : indices_)
        for (Index c = 0; c < DataTypes::kDerivSize; ++c) rows.push_back(DataTypes::kDerivSize * i + c);
    return true;
}

template class LinearMovementProjectiveConstraint<Vec3Types>;
template class LinearMovementProjectiveConstraint<Rigid3Types>;

// ---- ParabolicProjectiveConstraint ------------------------------------------------------------
template <class DataTypes>
ParabolicProjectiveConstraint<DataTypes>::ParabolicProjectiveConstraint(MechanicalObject<DataTypes>& state,
                                                                        std::vector<Index> indices, const Vec3& p1,
                                                                        const Vec3& p2, const Vec3& p3,
                                                                        double begin_time, double end_time,
                                                                        ContextClock clock, ContextClock dt)
    : state_(&state),
      indices_(std::move(indices)),
      p1_(p1),
      p2_(p2),
      p3_(p3),
      begin_(begin_time),
      end_(end_time),
      clock_(std::move(clock)),
      dt_(std::move(dt)) {}

// ParabolicProjectiveConstraint::init: the parabola's frame (x along P1P3, z = P1P3 × P1P2,
// y = z × x, each normalised), its rotation as a normalised quaternion, P2 and P3 in the frame.
template <class DataTypes>
void ParabolicProjectiveConstraint<DataTypes>::init() {
    check_constraint_indices("ParabolicProjectiveConstraint", indices_, state_->num_dofs());
    if (p1_ == p2_ || p1_ == p3_ || p2_ == p3_)
        throw_invalid_argument("ParabolicProjectiveConstraint: P1, P2 and P3 must be three distinct points");
    const Vec3 p1p2 = p2_ - p1_, p1p3 = p3_ - p1_;
    const Vec3 az = sofa_vec::normalized(sofa_vec::cross(p1p3, p1p2));
    const Vec3 ay = sofa_vec::normalized(sofa_vec::cross(sofa_vec::cross(p1p3, p1p2), p1p3));
    const Vec3 ax = sofa_vec::normalized(p1p3);
    Mat3 rotation;  // Mat(ax, ay, az) transposed: the axes as columns
    rotation.col(0) = ax;
    rotation.col(1) = ay;
    rotation.col(2) = az;
    projection_ = sofa_quat::normalized(sofa_quat::from_matrix(rotation));
    loc_p2_ = sofa_quat::inverse_rotate(projection_, p1p2);
    loc_p3_ = sofa_quat::inverse_rotate(projection_, p1p3);
}

template <class DataTypes>
std::pair<double, double> ParabolicProjectiveConstraint<DataTypes>::local_at(double r) const {
    const double x2 = loc_p2_.x(), y2 = loc_p2_.y(), x3 = loc_p3_.x();
    const double px = x3 * r;
    const double py = (-y2 / (x3 * x2 - x2 * x2)) * (px * px) + ((x3 * y2) / (x3 * x2 - x2 * x2)) * px;
    return {px, py};
}

template <class DataTypes>
Vec3 ParabolicProjectiveConstraint<DataTypes>::point_at(double t) const {
    const auto [px, py] = local_at((t - begin_) / (end_ - begin_));
    return p1_ + sofa_quat::rotate(projection_, Vec3(px, py, 0.0));
}

template <class DataTypes>
void ParabolicProjectiveConstraint<DataTypes>::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    if (!active(clock_())) return;
    const auto u = as_derivs<DataTypes>(v);
    for (Index i : indices_) u[static_cast<std::size_t>(i)] = zero_deriv<typename DataTypes::Deriv>();
}

namespace {
void set_linear(Vec3& v, const Vec3& value) { v = value; }
void set_linear(RigidDeriv& v, const Vec3& value) { v.linear = value; }
void set_center(Vec3& x, const Vec3& value) { x = value; }
void set_center(RigidFrame& x, const Vec3& value) { x.center = value; }
}  // namespace

// ParabolicProjectiveConstraint::projectVelocity: v = R·((X, Y)(r(t + dt)) − (X, Y)(r(t)))/dt. SOFA
// assigns r = r(t + dt) inside its loop over the indices, so from the second index on both ends
// are r(t + dt): R·(0, 0, 0) = 0 (unless every_index_velocity_).
template <class DataTypes>
void ParabolicProjectiveConstraint<DataTypes>::project_velocity() {
    const double t = clock_(), dt = dt_();
    if (!active(t)) return;
    const auto [xp, yp] = local_at((t - begin_) / (end_ - begin_));
    const auto [xn, yn] = local_at((t + dt - begin_) / (end_ - begin_));
    const Vec3 world = sofa_quat::rotate(projection_, Vec3((xn - xp) / dt, (yn - yp) / dt, 0.0));
    const Vec3 later = every_index_velocity_ ? world : sofa_quat::rotate(projection_, Vec3::Zero());
    for (std::size_t k = 0; k < indices_.size(); ++k)
        set_linear(state_->velocity[static_cast<std::size_t>(indices_[k])], k == 0 ? world : later);
}

template <class DataTypes>
void ParabolicProjectiveConstraint<DataTypes>::project_position() {
    const double t = clock_();
    if (!active(t)) return;
    const Vec3 world = point_at(t);
    for (Index i : indices_) set_center(state_->position[static_cast<std::size_t>(i)], world);
}

template class ParabolicProjectiveConstraint<Vec3Types>;
template class ParabolicProjectiveConstraint<Rigid3Types>;

// ---- FixedRotationProjectiveConstraint --------------------------------------------------------
void FixedRotationProjectiveConstraint::init() {
    initial_.clear();
    for (const RigidFrame& f : state_->position) initial_.push_back(f.orientation);
}

namespace {
/// FixedRotationProjectiveConstraint's decompose_ts: twist of q about the unit axis a
/// (((q⃗·a) a, w), normalised; the identity when all four are zero) and swing = q·twist⁻¹,
/// normalised.
std::pair<Quat, Quat> twist_and_swing(const Quat& q, const Vec3& a) {
    const Vec3 v(q.x(), q.y(), q.z());
    const Vec3 along = sofa_vec::scaled(a, sofa_vec::dot3(v, a));
    Quat twist(q.w(), along[0], along[1], along[2]);
    if (twist.x() == 0 && twist.y() == 0 && twist.z() == 0 && twist.w() == 0) twist = Quat::Identity();
    twist = sofa_quat::normalized(twist);
    const Quat swing = sofa_quat::normalized(sofa_quat::product(q, sofa_quat::inverse(twist)));
    return {twist, swing};
}
}  // namespace

void FixedRotationProjectiveConstraint::project_position() {
    const std::array<Vec3, 3> axes{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    for (std::size_t i = 0; i < state_->position.size() && i < initial_.size(); ++i) {
        Quat remaining = state_->position[i].orientation;
        Quat initial_remaining = initial_[i];
        Quat keep = Quat::Identity();
        for (std::size_t a = 0; a < 3; ++a) {
            if (!fixed_[a]) continue;
            remaining = twist_and_swing(remaining, axes[a]).second;
            const auto [twist, swing] = twist_and_swing(initial_remaining, axes[a]);
            initial_remaining = swing;
            keep = sofa_quat::product(twist, keep);
        }
        state_->position[i].orientation = sofa_quat::product(remaining, keep);
    }
}

}  // namespace penalty
