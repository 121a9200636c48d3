#pragma once
// Quaternion operations with SOFA's type::Quat operation order (Quat.h / Quat.inl), for the
// components that reproduce SOFA's rigid-body arithmetic to the last bit (JointSpringForceField,
// BeamFEMForceField, the rigid projective constraints, RigidMapping onto Rigid3 frames). Eigen's
// Quaterniond stores (x, y, z, w) as SOFA's _q[0..3]; every function here reads and writes those
// four numbers in SOFA's order of operations, never Eigen's own quaternion products.
#include "penalty/core/types.hpp"
#include "sofa_vector_ops.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace penalty::sofa_quat {

/// a ⊗ b (Quat::operator*(Quat)), component by component.
inline Quat product(const Quat& a, const Quat& b) {
    const double w = a.w() * b.w() - (a.x() * b.x() + a.y() * b.y() + a.z() * b.z());
    const double x = a.w() * b.x() + a.x() * b.w() + a.y() * b.z() - a.z() * b.y();
    const double y = a.w() * b.y() + a.y() * b.w() + a.z() * b.x() - a.x() * b.z();
    const double z = a.w() * b.z() + a.z() * b.w() + a.x() * b.y() - a.y() * b.x();
    return Quat(w, x, y, z);
}

/// Quat::normalize: scaled by 1/√(q·q) when |q·q − 1| > 1e-10; (0, 0, 0, 1) when q·q = 0.
inline Quat normalized(Quat q) {
    const double mag = q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w();
    if (std::abs(mag - 1.0) > 1.0e-10) {
        if (mag != 0) {
            const double s = 1.0 / std::sqrt(mag);
            q = Quat(q.w() * s, q.x() * s, q.y() * s, q.z() * s);
        } else {
            q.w() = 1;
        }
    }
    return q;
}

/// Quat::inverse: (−x, −y, −z, w)/|q|, zero for a zero quaternion.
inline Quat inverse(const Quat& q) {
    double norm = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w());
    if (norm == 0.0) return Quat(0, 0, 0, 0);
    norm = 1.0 / norm;
    return Quat(q.w() * norm, -q.x() * norm, -q.y() * norm, -q.z() * norm);
}

/// Quat::rotate: t = 2 (q⃗ × v), v + w t + q⃗ × t.
inline Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 qv(q.x(), q.y(), q.z());
    const Vec3 c = sofa_vec::cross(qv, v);
    const Vec3 t(c[0] * 2, c[1] * 2, c[2] * 2);
    const Vec3 ct = sofa_vec::cross(qv, t);
    return {v[0] + q.w() * t[0] + ct[0], v[1] + q.w() * t[1] + ct[1], v[2] + q.w() * t[2] + ct[2]};
}

/// Quat::inverseRotate: rotate with q⃗ negated.
inline Vec3 inverse_rotate(const Quat& q, const Vec3& v) {
    const Vec3 qv(-q.x(), -q.y(), -q.z());
    const Vec3 c = sofa_vec::cross(qv, v);
    const Vec3 t(c[0] * 2, c[1] * 2, c[2] * 2);
    const Vec3 ct = sofa_vec::cross(qv, t);
    return {v[0] + q.w() * t[0] + ct[0], v[1] + q.w() * t[1] + ct[1], v[2] + q.w() * t[2] + ct[2]};
}

/// Quat::toMatrix (computeRotationMatrix).
inline Mat3 to_matrix(const Quat& q) {
    const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
    Mat3 m;
    m(0, 0) = 1 - 2 * (y * y + z * z);
    m(0, 1) = 2 * (x * y - z * w);
    m(0, 2) = 2 * (z * x + y * w);
    m(1, 0) = 2 * (x * y + z * w);
    m(1, 1) = 1 - 2 * (z * z + x * x);
    m(1, 2) = 2 * (y * z - x * w);
    m(2, 0) = 2 * (z * x - y * w);
    m(2, 1) = 2 * (y * z + x * w);
    m(2, 2) = 1 - 2 * (y * y + x * x);
    return m;
}

/// Quat::fromMatrix (m(i, j): row i, column j; SOFA's m.x().y() is m(0, 1)).
inline Quat from_matrix(const Mat3& m) {
    double x, y, z, w;
    const double tr = m(0, 0) + m(1, 1) + m(2, 2);
    if (tr > 0) {
        double s = std::sqrt(tr + 1);
        w = s * 0.5;
        s = 0.5 / s;
        x = (m(2, 1) - m(1, 2)) * s;
        y = (m(0, 2) - m(2, 0)) * s;
        z = (m(1, 0) - m(0, 1)) * s;
    } else if (m(1, 1) > m(0, 0) && m(2, 2) <= m(1, 1)) {
        double s = std::sqrt((m(1, 1) - (m(2, 2) + m(0, 0))) + 1.0);
        y = s * 0.5;
        if (s != 0.0) s = 0.5 / s;
        z = (m(1, 2) + m(2, 1)) * s;
        x = (m(0, 1) + m(1, 0)) * s;
        w = (m(0, 2) - m(2, 0)) * s;
    } else if ((m(1, 1) <= m(0, 0) && m(2, 2) > m(0, 0)) || (m(2, 2) > m(1, 1))) {
        double s = std::sqrt((m(2, 2) - (m(0, 0) + m(1, 1))) + 1.0);
        z = s * 0.5;
        if (s != 0.0) s = 0.5 / s;
        x = (m(2, 0) + m(0, 2)) * s;
        y = (m(1, 2) + m(2, 1)) * s;
        w = (m(1, 0) - m(0, 1)) * s;
    } else {
        double s = std::sqrt((m(0, 0) - (m(1, 1) + m(2, 2))) + 1.0);
        x = s * 0.5;
        if (s != 0.0) s = 0.5 / s;
        y = (m(0, 1) + m(1, 0)) * s;
        z = (m(2, 0) + m(0, 2)) * s;
        w = (m(2, 1) - m(1, 2)) * s;
    }
    return Quat(w, x, y, z);
}

/// Quat::axisToQuat(a, φ): (a/|a| sin φ/2, cos φ/2); the identity when |a| < machine epsilon.
inline Quat from_axis_angle(const Vec3& axis, double phi) {
    const double norm = std::sqrt(sofa_vec::dot3(axis, axis));
    if (norm < std::numeric_limits<double>::epsilon()) return Quat::Identity();
    const Vec3 a(axis[0] / norm, axis[1] / norm, axis[2] / norm);
    const double sp = std::sin(phi / 2.0), cp = std::cos(phi / 2.0);
    return Quat(cp, a[0] * sp, a[1] * sp, a[2] * sp);
}

/// Quat::quatToAxis: the rotation's unit axis and angle in [0, 2π] (q with w ≥ 0); axis (0, 1, 0)
/// for a null rotation.
inline void to_axis_angle(Quat q, Vec3& axis, double& angle) {
    if (q.w() < 0) q = Quat(-q.w(), -q.x(), -q.y(), -q.z());
    double sin_half;
    if (q.w() > 0.999) {  // θ < 5°: asin is better conditioned than acos
        sin_half = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
        angle = 2.0 * std::asin(sin_half);
    } else {
        const double half = std::acos(q.w());
        sin_half = std::sin(half);
        angle = 2 * half;
    }
    if (sin_half < std::numeric_limits<double>::epsilon()) axis = Vec3(0.0, 1.0, 0.0);
    else axis = Vec3(q.x() / sin_half, q.y() / sin_half, q.z() / sin_half);
}

/// Quat::quatToRotationVector: axis·angle of normalize(q) (w ≥ 0), zero for a null rotation.
inline Vec3 to_rotation_vector(const Quat& q_in) {
    Quat q = normalized(q_in);
    if (q.w() < 0) q = Quat(-q.w(), -q.x(), -q.y(), -q.z());
    double angle, sin_half;
    if (q.w() > 0.999) {
        sin_half = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
        angle = 2.0 * std::asin(sin_half);
    } else {
        const double half = std::acos(q.w());
        sin_half = std::sin(half);
        angle = 2 * half;
    }
    if (sin_half < std::numeric_limits<double>::epsilon()) return Vec3::Zero();
    return {q.x() / sin_half * angle, q.y() / sin_half * angle, q.z() / sin_half * angle};
}

/// Quat::slerp2(q1, t) from `q0`.
inline Quat slerp2(const Quat& q0, const Quat& q1, double t) {
    const double cos_half = q0.w() * q1.w() + q0.x() * q1.x() + q0.y() * q1.y() + q0.z() * q1.z();
    if (std::abs(cos_half) >= 1.0) return q0;
    const double half = std::acos(cos_half);
    const double sin_half = std::sqrt(1.0 - cos_half * cos_half);
    if (std::abs(sin_half) < 0.001)
        return Quat(q0.w() * 0.5 + q1.w() * 0.5, q0.x() * 0.5 + q1.x() * 0.5, q0.y() * 0.5 + q1.y() * 0.5,
                    q0.z() * 0.5 + q1.z() * 0.5);
    const double ra = std::sin((1 - t) * half) / sin_half;
    const double rb = std::sin(t * half) / sin_half;
    return Quat(q0.w() * ra + q1.w() * rb, q0.x() * ra + q1.x() * rb, q0.y() * ra + q1.y() * rb,
                q0.z() * ra + q1.z() * rb);
}

/// Quat::createQuaterFromEuler(v) in SOFA's default order (ZYX): v = (roll x, pitch y, yaw z), rad.
inline Quat from_euler_zyx(const Vec3& v) {
    const double c1 = std::cos(v[0] / 2), c2 = std::cos(v[1] / 2), c3 = std::cos(v[2] / 2);
    const double s1 = std::sin(v[0] / 2), s2 = std::sin(v[1] / 2), s3 = std::sin(v[2] / 2);
    const double x = s1 * c2 * c3 - c1 * s2 * s3;
    const double y = c1 * s2 * c3 + s1 * c2 * s3;
    const double z = c1 * c2 * s3 - s1 * s2 * c3;
    const double w = c1 * c2 * c3 + s1 * s2 * s3;
    return Quat(w, x, y, z);
}

}  // namespace penalty::sofa_quat
