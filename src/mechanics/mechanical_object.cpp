#include "penalty/mechanics/mechanical_object.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace penalty {

namespace {

/// SOFA's Quat<double>::createQuaterFromEuler(Vec3(rx, ry, rz) * M_PI / 180.0) with its default
/// order (EulerOrder::ZYX), operation by operation: angles a = (deg·π)/180, half angles a/2,
/// products left to right. Returned as Eigen's (w, x, y, z).
Quat sofa_quaternion_from_euler_degrees(const Vec3& degrees) {
    const double a0 = degrees.x() * std::numbers::pi / 180.0;
    const double a1 = degrees.y() * std::numbers::pi / 180.0;
    const double a2 = degrees.z() * std::numbers::pi / 180.0;
    const double c1 = std::cos(a0 / 2), c2 = std::cos(a1 / 2), c3 = std::cos(a2 / 2);
    const double s1 = std::sin(a0 / 2), s2 = std::sin(a1 / 2), s3 = std::sin(a2 / 2);
    const double x = s1 * c2 * c3 - c1 * s2 * s3;
    const double y = c1 * s2 * c3 + s1 * c2 * s3;
    const double z = c1 * c2 * s3 - s1 * s2 * c3;
    const double w = c1 * c2 * c3 + s1 * s2 * s3;
    return Quat(w, x, y, z);
}

/// SOFA's Vec3::cross, component by component.
Vec3 sofa_cross(const Vec3& a, const Vec3& b) {
    return Vec3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}

/// SOFA's Quat::rotate(v): t = 2 (q × v), v' = v + w t + q × t (q = vector part).
Vec3 sofa_rotate(const Quat& q, const Vec3& v) {
    const Vec3 qv(q.x(), q.y(), q.z());
    const Vec3 t = sofa_cross(qv, v) * 2.0;
    const Vec3 wt(q.w() * t[0], q.w() * t[1], q.w() * t[2]);
    const Vec3 c = sofa_cross(qv, t);
    return Vec3(v[0] + wt[0] + c[0], v[1] + wt[1] + c[1], v[2] + wt[2] + c[2]);
}

/// SOFA's Quat::operator*(q1) (this = a, q1 = b), component by component.
Quat sofa_quaternion_product(const Quat& a, const Quat& b) {
    const double w = a.w() * b.w() - (a.x() * b.x() + a.y() * b.y() + a.z() * b.z());
    const double x = a.w() * b.x() + a.x() * b.w() + a.y() * b.z() - a.z() * b.y();
    const double y = a.w() * b.y() + a.y() * b.w() + a.z() * b.x() - a.x() * b.z();
    const double z = a.w() * b.z() + a.z() * b.w() + a.x() * b.y() - a.y() * b.x();
    return Quat(w, x, y, z);
}

/// SOFA's MechanicalObject::reinit on one point: applyScale (x·s per component), applyRotation
/// (Quat::rotate), applyTranslation (x += t), each rounded in turn.
Vec3 sofa_transform_point(const InitialTransform& tr, const Quat& q, const Vec3& p) {
    const Vec3 scaled(p[0] * tr.scale3d[0], p[1] * tr.scale3d[1], p[2] * tr.scale3d[2]);
    const Vec3 rotated = sofa_rotate(q, scaled);
    return Vec3(rotated[0] + tr.translation[0], rotated[1] + tr.translation[1], rotated[2] + tr.translation[2]);
}

}  // namespace

Quat InitialTransform::rotation() const { return sofa_quaternion_from_euler_degrees(rotation_deg); }

RigidFrame rigid_add(const RigidFrame& x, const RigidDeriv& v, double h) {
    // vOp(r, x, v, h): the Deriv v·h first, then Coord += Deriv (RigidCoord::operator+=).
    const Vec3 linear(v.linear[0] * h, v.linear[1] * h, v.linear[2] * h);
    RigidFrame out;
    out.center = Vec3(x.center[0] + linear[0], x.center[1] + linear[1], x.center[2] + linear[2]);
    const Vec3 omega(v.angular[0] * h / 2, v.angular[1] * h / 2, v.angular[2] * h / 2);
    const double theta = std::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    Quat exp;
    if (theta < std::numeric_limits<double>::epsilon()) {
        // SOFA's fallback, the gnomonic projection: (ω/2, 1) normalised (Quat::normalize)
        exp = Quat(1.0, omega[0], omega[1], omega[2]);
        const double mag = omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2] + 1.0;
        if (std::abs(mag - 1.0) > 1.0e-10) {
            const double s = 1.0 / std::sqrt(mag);
            exp = Quat(s, omega[0] * s, omega[1] * s, omega[2] * s);
        }
    } else {
        const double sinc = std::sin(theta) / theta;
        exp = Quat(std::cos(theta), sinc * omega[0], sinc * omega[1], sinc * omega[2]);
    }
    // Quat::operator* (SOFA's order of operations)
    const Quat& q = x.orientation;
    out.orientation = Quat(exp.w() * q.w() - (exp.x() * q.x() + exp.y() * q.y() + exp.z() * q.z()),
                           exp.w() * q.x() + exp.x() * q.w() + exp.y() * q.z() - exp.z() * q.y(),
                           exp.w() * q.y() + exp.y() * q.w() + exp.z() * q.x() - exp.x() * q.z(),
                           exp.w() * q.z() + exp.z() * q.w() + exp.x() * q.y() - exp.y() * q.x());
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
        throw_invalid_argument("MechanicalObject '", s.name, "': ", s.velocity.size(), " velocities for ", n, " positions");
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
        position[i].orientation.normalize();
    }
    if (!transform.is_identity() && !initialized_) {
        const Quat q = transform.rotation();
        // MechanicalObject<Rigid3Types>::applyRotation: centre rotated, orientation q * o.
        auto apply = [&](RigidFrame& p) {
            p.center = sofa_transform_point(transform, q, p.center);
            p.orientation = sofa_quaternion_product(q, p.orientation);
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


}  // namespace penalty
