#pragma once
// Vector arithmetic in SOFA's type::Vec order of operations (dot: ((x0 y0 + x1 y1) + x2 y2);
// cross: (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0); division element by element), so that the
// incision's tests (inside a triangle, crossing an edge, snapping) decide as SOFA's do on the
// same doubles.
#include "penalty/core/types.hpp"

#include <cmath>

namespace penalty::incision_math {

inline double dot(const Vec3& a, const Vec3& b) {
    double r = a[0] * b[0];
    r += a[1] * b[1];
    r += a[2] * b[2];
    return r;
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return Vec3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}
inline double norm2(const Vec3& a) { return dot(a, a); }
inline double norm(const Vec3& a) { return std::sqrt(norm2(a)); }
inline Vec3 divided(const Vec3& a, double s) { return Vec3(a[0] / s, a[1] / s, a[2] / s); }
/// Vec::normalize: divided by the norm when it exceeds the machine epsilon.
inline void normalize(Vec3& a) {
    const double n = norm(a);
    if (n > 2.220446049250313e-16) a = divided(a, n);
}
/// SOFA's type::Vec EQUALITY_THRESHOLD.
inline constexpr double kEqualityThreshold = 1e-6;

}  // namespace penalty::incision_math
