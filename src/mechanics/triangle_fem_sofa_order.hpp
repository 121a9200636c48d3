#pragma once
// SOFA's TriangleFEMForceField (the older triangle membrane, flavor TriangleFEM of
// TriangularFEMForceField) with SOFA's own operations, in SOFA's order, so that a scene's
// trajectory agrees with SOFA's to the last bit: TriangleFEMUtils::computeRotationLarge,
// computeDisplacementLarge/Small, computeStrainDisplacementLocal, computeStrain, computeStress and
// computeForceLarge as TriangleFEMForceField::initLarge, accumulateForceLarge/Small and
// applyStiffnessLarge/Small call them (fullMethod false for "large", true for "small"). The
// mathematics is that of triangular_fem.hpp; only the rounding differs.
#include "penalty/core/types.hpp"
#include "sofa_vector_ops.hpp"

#include <Eigen/Core>

#include <array>

namespace penalty::triangle_fem_sofa {

using StrainDisplacement = Eigen::Matrix<double, 6, 3>;  ///< J: 6 nodal components × 3 strains
using Displacement = Eigen::Matrix<double, 6, 1>;        ///< (x_a, y_a, x_b, y_b, x_c, y_c)

/// computeRotationLarge: rows x̂ = (b − a)/|b − a|, ẑ = (x̂ × (c − a))/|…|, ŷ = ẑ × x̂.
Mat3 rotation(const Vec3& a, const Vec3& b, const Vec3& c);
/// initLarge: R·a, R·b, R·c with R the rest rotation, then b − a and c − a of those (local a = 0).
std::array<Vec3, 2> rest_local_large(const Mat3& rest_rotation, const Vec3& a, const Vec3& b, const Vec3& c);
/// computeStrainDisplacementLocal(b, c): false when |b_x·c_y| < machine epsilon (SOFA throws).
bool strain_displacement_local(StrainDisplacement& j, const Vec3& b, const Vec3& c);
/// ½·|(b − a) × (c − a)| (sofa::geometry::Triangle::area).
double area(const Vec3& a, const Vec3& b, const Vec3& c);

/// The local nodal forces F of one element (large: accumulateForceLarge; small:
/// accumulateForceSmall): displacement from the rest local edges `rest` and the current local
/// (large) or world (small) edges `db`, `dc`, J of the current edges, strain, stress, F = J·σ.
/// Returns false for a degenerate current triangle; `j` receives J, `strain` and `stress` ε, σ.
bool element_forces(bool large, const std::array<Vec3, 2>& rest, const Vec3& db, const Vec3& dc, const Mat3& material,
                    StrainDisplacement& j, Vec3& strain, Vec3& stress, Displacement& forces);
namespace detail {

/// computeStrain: fullMethod (small) Jᵀ·D summed over the six rows in order (Mat::multTranspose);
/// else the non-zero terms only, as SOFA lists them.
[[gnu::always_inline]] inline Vec3 strain_of(bool full, const StrainDisplacement& j, const Displacement& d) {
    if (full) {
        Vec3 s;
        for (int i = 0; i < 3; ++i) {
            double r = j(0, i) * d[0];
            for (int k = 1; k < 6; ++k) r += j(k, i) * d[k];
            s[i] = r;
        }
        return s;
    }
    return {j(0, 0) * d[0] + j(2, 0) * d[2], j(1, 1) * d[1] + j(3, 1) * d[3] + j(5, 1) * d[5],
            j(0, 2) * d[0] + j(1, 2) * d[1] + j(2, 2) * d[2] + j(3, 2) * d[3] + j(4, 2) * d[4]};
}

/// computeStress: fullMethod K·ε (Mat::operator*(Vec)); else the non-zero terms.
[[gnu::always_inline]] inline Vec3 stress_of(bool full, const Mat3& k, const Vec3& e) {
    if (full) return sofa_vec::times(k, e);
    return {k(0, 0) * e[0] + k(0, 1) * e[1], k(1, 0) * e[0] + k(1, 1) * e[1], k(2, 2) * e[2]};
}

/// large: computeForceLarge (the non-zero terms of J·σ); small: J·σ (Mat::operator*(Vec)).
[[gnu::always_inline]] inline Displacement forces_of(bool large, const StrainDisplacement& j, const Vec3& s) {
    Displacement f;
    if (large) {
        f << j(0, 0) * s[0] + j(0, 2) * s[2], j(1, 1) * s[1] + j(1, 2) * s[2], j(2, 0) * s[0] + j(2, 2) * s[2],
            j(3, 1) * s[1] + j(3, 2) * s[2], j(4, 2) * s[2], j(5, 1) * s[1];
        return f;
    }
    for (int k = 0; k < 6; ++k) f[k] = j(k, 0) * s[0] + j(k, 1) * s[1] + j(k, 2) * s[2];
    return f;
}

}  // namespace detail

/// The local nodal force changes of applyStiffnessLarge/Small for the local (large: R_0_2·dx;
/// small: world) x, y components `dx` of the three vertices, J and the material of the element.
[[gnu::always_inline]] inline Displacement stiffness_forces(bool large, const StrainDisplacement& j,
                                                            const Mat3& material, const Displacement& dx) {
    const Vec3 strain = detail::strain_of(!large, j, dx);
    const Vec3 stress = detail::stress_of(!large, material, strain);
    return detail::forces_of(large, j, stress);
}

}  // namespace penalty::triangle_fem_sofa
