#include "penalty/mechanics/mechanical_object.hpp"

#include "sofa_quaternion.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace penalty {

namespace {

/// SOFA's Quat<double>::createQuaterFromEuler(Vec3(rx, ry, rz) * M_PI / 180.0): angles (deg·π)/180.
Quat sofa_quaternion_from_euler_degrees(const Vec3& degrees) {
    return sofa_quat::from_euler_zyx(Vec3(degrees.x() * std::numbers::pi / 180.0,
                                          degrees.y() * std::numbers::pi / 180.0,
                                          degrees.z() * std::numbers::pi / 180.0));
}

/// SOFA's MechanicalObject::reinit on one point: applyScale (x·s per component), applyRotation
/// (Quat::rotate), applyTranslation (x += t), each rounded in turn.
Vec3 sofa_transform_point(const InitialTransform& tr, const Quat& q, const Vec3& p) {
    const Vec3 scaled(p[0] * tr.scale3d[0], p[1] * tr.scale3d[1], p[2] * tr.scale3d[2]);
    const Vec3 rotated = sofa_quat::rotate(q, scaled);
    return Vec3(rotated[0] + tr.translation[0], rotated[1] + tr.translation[1], rotated[2] + tr.translation[2]);
}

}  // namespace

Quat InitialTransform::rotation() const { return sofa_quaternion_from_euler_degrees(rotation_deg); }

RigidFrame rigid_add(const RigidFrame& x, const RigidDeriv& v, double h) {
    // SOFA HEAD's RigidCoord<3>::operator+=(Deriv) on Deriv·h (RigidDeriv::operator*(real)):
    // the centre moves by v·h; the orientation is premultiplied by exp(½·ω·h), the unit
    // quaternion (sin θ/θ · ω', cos θ) with ω' = (ω·h)/2 and θ = |ω'| (R³ × SO(3) exponential
    // integration), or, when θ < machine epsilon, by (ω', 1) normalised as Quat::normalize does.
    RigidFrame out;
    out.center = Vec3(x.center[0] + v.linear[0] * h, x.center[1] + v.linear[1] * h, x.center[2] + v.linear[2] * h);
    const Vec3 half(v.angular[0] * h / 2, v.angular[1] * h / 2, v.angular[2] * h / 2);
    const double theta = std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]);
    Quat step;
    if (theta < std::numeric_limits<double>::epsilon()) {
        step = sofa_quat::normalized(Quat(1.0, half[0], half[1], half[2]));
    } else {
        const double sinc = std::sin(theta) / theta;
        step = Quat(std::cos(theta), sinc * half[0], sinc * half[1], sinc * half[2]);
    }
    out.orientation = sofa_quat::product(step, x.orientation);
    return out;
}

namespace {
void check_finite(const Vec3& p, std::string_view name, std::size_t i) {
    if (!p.allFinite()) throw_invalid_argument("MechanicalObject '", name, "': position[", i, "] is not finite");
}
}  // namespace

template <>
void MechanicalObject<Vec3Types>::add_to_position(double h, const Eigen::Ref<const Eigen::VectorXd>& v) {
    PENALTY_DEMAND(static_cast<std::size_t>(v.size()) == scalar_size());
    for (std::size_t i = 0; i < position.size(); ++i) position[i] += h * v.segment<3>(static_cast<Eigen::Index>(3 * i));
}

template <>
void MechanicalObject<Rigid3Types>::add_to_position(double h, const Eigen::Ref<const Eigen::VectorXd>& v) {
    PENALTY_DEMAND(static_cast<std::size_t>(v.size()) == scalar_size());
    for (std::size_t i = 0; i < position.size(); ++i) {
        RigidDeriv d;
        d.linear = v.segment<3>(static_cast<Eigen::Index>(6 * i));
        d.angular = v.segment<3>(static_cast<Eigen::Index>(6 * i + 3));
        position[i] = rigid_add(position[i], d, h);
    }
}

namespace {
/// SOFA's size rules: rest positions given without positions become the positions; fewer
/// velocities than positions are completed with the last given one.
template <class State>
void complete_sizes(State& s) {
    if (s.rest_position.size() > s.position.size()) s.position = s.rest_position;
    const std::size_t n = s.position.size();
    if (s.velocity.size() > n)
        throw_invalid_argument("MechanicalObject '", s.name, "': ", s.velocity.size(), " velocities for ", n,
                               " positions");
    if (!s.velocity.empty() && s.velocity.size() < n) s.velocity.resize(n, s.velocity.back());
}
}  // namespace

template <>
void MechanicalObject<Vec3Types>::init() {
    complete_sizes(*this);
    const std::size_t n = position.size();
    for (std::size_t i = 0; i < n; ++i) check_finite(position[i], name, i);
    if (!transform.is_identity() && !initialized_) {
        // SOFA's reinit(): scale, rotation, translation of the positions only; the rest
        // positions are copied from the transformed positions unless given with the right size.
        // SOFA's own floating-point operations (MechanicalObject::applyScale/applyRotation/
        // applyTranslation), so that the initial positions agree to the last bit.
        const Quat q = transform.rotation();
        for (auto& p : position) p = sofa_transform_point(transform, q, p);
    }
    if (rest_position.size() != n) rest_position = position;
    velocity.resize(n, Vec3::Zero());
    force.assign(n, Vec3::Zero());
    external_force.assign(n, Vec3::Zero());
    dx.assign(n, Vec3::Zero());
    df.assign(n, Vec3::Zero());
    initialized_ = true;
}

template <>
void MechanicalObject<Rigid3Types>::init() {
    complete_sizes(*this);
    const std::size_t n = position.size();
    for (std::size_t i = 0; i < n; ++i) {
        check_finite(position[i].center, name, i);
        if (!position[i].orientation.coeffs().allFinite() || position[i].orientation.norm() < 1e-12) {
            throw_invalid_argument("MechanicalObject '", name, "': position[", i, "] has an invalid quaternion");
        }
    }
    if (!transform.is_identity() && !initialized_) {
        const Quat q = transform.rotation();
        // MechanicalObject<Rigid3Types>::applyRotation: centre rotated, orientation q * o.
        auto apply = [&](RigidFrame& p) {
            p.center = sofa_transform_point(transform, q, p.center);
            p.orientation = sofa_quat::product(q, p.orientation);
        };
        for (auto& p : position) apply(p);
    }
    if (rest_position.size() != n) rest_position = position;
    velocity.resize(n);
    force.assign(n, RigidDeriv{});
    external_force.assign(n, RigidDeriv{});
    dx.assign(n, RigidDeriv{});
    df.assign(n, RigidDeriv{});
    initialized_ = true;
}

template <>
void MechanicalObject<Vec1Types>::add_to_position(double h, const Eigen::Ref<const Eigen::VectorXd>& v) {
    PENALTY_DEMAND(static_cast<std::size_t>(v.size()) == scalar_size());
    for (std::size_t i = 0; i < position.size(); ++i) position[i] += h * v[static_cast<Eigen::Index>(i)];
}

template <>
void MechanicalObject<Vec1Types>::init() {
    complete_sizes(*this);
    const std::size_t n = position.size();
    for (std::size_t i = 0; i < n; ++i)
        if (!std::isfinite(position[i]))
            throw_invalid_argument("MechanicalObject '", name, "': position[", i, "] is not finite");
    if (rest_position.size() != n) rest_position = position;
    velocity.resize(n);
    force.assign(n, 0.0);
    external_force.assign(n, 0.0);
    dx.assign(n, 0.0);
    df.assign(n, 0.0);
    initialized_ = true;
}

}  // namespace penalty
