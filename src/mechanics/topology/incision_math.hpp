#pragma once
// Vector arithmetic in SOFA's type::Vec order of operations (dot: ((x0 y0 + x1 y1) + x2 y2);
// cross: (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0); division element by element), so that the
// incision's tests (inside a triangle, crossing an edge, snapping) decide as SOFA's do on the
// same doubles.
#include "mechanics/sofa_vector_ops.hpp"
#include "penalty/core/types.hpp"

#include <cmath>

namespace penalty::incision_math {

// The same operations as sofa_vec's (one definition each), under the names the incision uses.
using sofa_vec::cross;
using sofa_vec::divided;
using sofa_vec::norm;
inline double dot(const Vec3& a, const Vec3& b) { return sofa_vec::dot3(a, b); }
inline double norm2(const Vec3& a) { return sofa_vec::dot3(a, a); }
/// Vec::normalize: divided by the norm when it exceeds the machine epsilon.
inline void normalize(Vec3& a) {
    const double n = norm(a);
    if (n > 2.220446049250313e-16) a = divided(a, n);
}
/// SOFA's type::Vec EQUALITY_THRESHOLD.
inline constexpr double kEqualityThreshold = 1e-6;

}  // namespace penalty::incision_math
