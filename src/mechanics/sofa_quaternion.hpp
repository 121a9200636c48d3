#pragma once
// Quaternion operations with SOFA's type::Quat operation order (Quat.h, Quat.inl), so that rotated
// points and integrated orientations agree with SOFA's to the last bit: createQuaterFromEuler
// (ZYX, SOFA's default order), rotate, operator*, normalize. Quaternions are Eigen's (w, x, y, z);
// SOFA stores (x, y, z, w).
#include "penalty/core/types.hpp"

#include <cmath>

namespace penalty::sofa_quat {

/// Quat::createQuaterFromEuler(angles) with EulerOrder::ZYX: c_i = cos(a_i / 2), s_i = sin(a_i / 2),
/// products left to right (angles in radians, already computed by the caller's own formula).
inline Quat from_euler_radians(const Vec3& a) {
    const double c1 = std::cos(a[0] / 2), c2 = std::cos(a[1] / 2), c3 = std::cos(a[2] / 2);
    const double s1 = std::sin(a[0] / 2), s2 = std::sin(a[1] / 2), s3 = std::sin(a[2] / 2);
    const double x = s1 * c2 * c3 - c1 * s2 * s3;
    const double y = c1 * s2 * c3 + s1 * c2 * s3;
    const double z = c1 * c2 * s3 - s1 * s2 * c3;
    const double w = c1 * c2 * c3 + s1 * s2 * s3;
    return Quat(w, x, y, z);
}

/// SOFA's Vec3::cross, component by component.
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return Vec3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}

/// Quat::rotate(v): t = 2 (q × v), v' = v + w t + q × t (q = vector part).
inline Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 qv(q.x(), q.y(), q.z());
    const Vec3 t = cross(qv, v) * 2.0;
    const Vec3 wt(q.w() * t[0], q.w() * t[1], q.w() * t[2]);
    const Vec3 c = cross(qv, t);
    return Vec3(v[0] + wt[0] + c[0], v[1] + wt[1] + c[1], v[2] + wt[2] + c[2]);
}

/// Quat::inverseRotate(v): rotate(v) with the vector part negated.
inline Vec3 inverse_rotate(const Quat& q, const Vec3& v) { return rotate(Quat(q.w(), -q.x(), -q.y(), -q.z()), v); }

/// Quat::toMatrix (computeRotationMatrix), entry by entry.
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

/// Quat::operator*(q1) (this = a, q1 = b), component by component.
inline Quat product(const Quat& a, const Quat& b) {
    const double w = a.w() * b.w() - (a.x() * b.x() + a.y() * b.y() + a.z() * b.z());
    const double x = a.w() * b.x() + a.x() * b.w() + a.y() * b.z() - a.z() * b.y();
    const double y = a.w() * b.y() + a.y() * b.w() + a.z() * b.x() - a.x() * b.z();
    const double z = a.w() * b.z() + a.z() * b.w() + a.x() * b.y() - a.y() * b.x();
    return Quat(w, x, y, z);
}

/// Quat::normalize: scaled by 1/√(x² + y² + z² + w²) only when that sum is more than 1e-10 away
/// from 1 (w = 1 when it is 0).
inline Quat normalized(const Quat& q) {
    const double mag = q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w();
    if (!(std::abs(mag - 1.0) > 1.0e-10)) return q;
    if (mag == 0.0) return Quat(1.0, q.x(), q.y(), q.z());
    const double scale = 1.0 / std::sqrt(mag);
    return Quat(q.w() * scale, q.x() * scale, q.y() * scale, q.z() * scale);
}

/// Quat::inverse(): (−x, −y, −z, w)·(1/|q|), |q| = √(x² + y² + z² + w²); q itself when |q| = 0.
inline Quat inverse(const Quat& q) {
    double norm = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w());
    if (norm == 0.0) return q;
    norm = 1.0 / norm;
    return Quat(q.w() * norm, -q.x() * norm, -q.y() * norm, -q.z() * norm);
}

}  // namespace penalty::sofa_quat
