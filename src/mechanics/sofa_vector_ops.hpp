#pragma once
// 3-vector and 3×3 products with SOFA's type::Vec / type::Mat operation order: every sum runs
// left to right from its first product (Vec::operator* (dot), Vec::norm2, Mat::operator*(Vec)),
// and nothing is fused or reassociated (Eigen's reductions may sum in another order). Used where
// penalty reproduces SOFA's trajectories to the last bit (docs/sofa-compatibility.md,
// "Step-by-step fidelity").
#include "penalty/core/types.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace penalty::sofa_vec {

/// a·b = a₀b₀ + a₁b₁ + a₂b₂ (type::Vec::operator*).
[[gnu::always_inline]] inline double dot3(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
/// a·s component by component (type::Vec::mulscalar).
[[gnu::always_inline]] inline Vec3 scaled(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
[[gnu::always_inline]] inline Vec3 times(const Vec3& a, double s) { return scaled(a, s); }
/// a + b and a − b component by component (type::Vec::operator+, operator−).
[[gnu::always_inline]] inline Vec3 plus(const Vec3& a, const Vec3& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
[[gnu::always_inline]] inline Vec3 minus(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
/// [v]×: the matrix of w ↦ v × w (type::crossProductMatrix).
inline Mat3 cross_matrix(const Vec3& v) {
    Mat3 m;
    m << 0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0;
    return m;
}
/// Element i's value of a per-element list, or the first when the list is shorter (SOFA's lists
/// of Young's moduli, thicknesses, ... given once for all elements).
inline double in_element(const std::vector<double>& values, std::size_t i) {
    return i < values.size() ? values[i] : values.front();
}
/// M·v, row i = M(i,0)v₀ + M(i,1)v₁ + M(i,2)v₂ (type::Mat::operator*(Vec)). M: a Mat3, or any
/// m(i, k) (an element's lane of TetrahedronFEMForceField's blocks).
template <class Matrix>
[[gnu::always_inline]] inline Vec3 times(const Matrix& m, const Vec3& v) {
    return {m(0, 0) * v[0] + m(0, 1) * v[1] + m(0, 2) * v[2], m(1, 0) * v[0] + m(1, 1) * v[1] + m(1, 2) * v[2],
            m(2, 0) * v[0] + m(2, 1) * v[1] + m(2, 2) * v[2]};
}
/// Mᵀ·v, row i = M(0,i)v₀ + M(1,i)v₁ + M(2,i)v₂ (type::Mat::multTranspose); M as for times.
template <class Matrix>
[[gnu::always_inline]] inline Vec3 transpose_times(const Matrix& m, const Vec3& v) {
    return {m(0, 0) * v[0] + m(1, 0) * v[1] + m(2, 0) * v[2], m(0, 1) * v[0] + m(1, 1) * v[1] + m(2, 1) * v[2],
            m(0, 2) * v[0] + m(1, 2) * v[1] + m(2, 2) * v[2]};
}
/// |v| = √(v·v) (type::Vec::norm).
inline double norm(const Vec3& v) { return std::sqrt(dot3(v, v)); }
/// a / s component by component (type::Vec::operator/).
inline Vec3 divided(const Vec3& a, double s) { return {a[0] / s, a[1] / s, a[2] / s}; }
/// a × b (type::cross).
[[gnu::always_inline]] inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
/// det M = m00·m11·m22 + m10·m21·m02 + m20·m01·m12 − m00·m21·m12 − m10·m01·m22 − m20·m11·m02,
/// summed left to right (type::determinant of a Mat<3,3>).
inline double determinant(const Mat3& m) {
    return m(0, 0) * m(1, 1) * m(2, 2) + m(1, 0) * m(2, 1) * m(0, 2) + m(2, 0) * m(0, 1) * m(1, 2) -
           m(0, 0) * m(2, 1) * m(1, 2) - m(1, 0) * m(0, 1) * m(2, 2) - m(2, 0) * m(1, 1) * m(0, 2);
}
/// M⁻¹ as type::invertMatrix(Mat<3,3>): each entry a 2×2 cofactor difference divided by det M
/// (not multiplied by 1/det, as Eigen's inverse()). M must be invertible.
inline Mat3 inverse(const Mat3& m) {
    const double det = determinant(m);
    Mat3 r;
    r(0, 0) = (m(1, 1) * m(2, 2) - m(2, 1) * m(1, 2)) / det;
    r(1, 0) = (m(1, 2) * m(2, 0) - m(2, 2) * m(1, 0)) / det;
    r(2, 0) = (m(1, 0) * m(2, 1) - m(2, 0) * m(1, 1)) / det;
    r(0, 1) = (m(2, 1) * m(0, 2) - m(0, 1) * m(2, 2)) / det;
    r(1, 1) = (m(2, 2) * m(0, 0) - m(0, 2) * m(2, 0)) / det;
    r(2, 1) = (m(2, 0) * m(0, 1) - m(0, 0) * m(2, 1)) / det;
    r(0, 2) = (m(0, 1) * m(1, 2) - m(1, 1) * m(0, 2)) / det;
    r(1, 2) = (m(0, 2) * m(1, 0) - m(1, 2) * m(0, 0)) / det;
    r(2, 2) = (m(0, 0) * m(1, 1) - m(1, 0) * m(0, 1)) / det;
    return r;
}
/// v / |v|, each component divided by |v| = √(v·v); v itself when |v| ≤ machine epsilon
/// (type::Vec::normalized → normalizeWithNorm).
inline Vec3 normalized(const Vec3& v) {
    const double length = norm(v);
    if (!(length > std::numeric_limits<double>::epsilon())) return v;
    return divided(v, length);
}

}  // namespace penalty::sofa_vec
