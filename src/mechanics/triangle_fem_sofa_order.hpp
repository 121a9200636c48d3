#pragma once
// SOFA's TriangleFEMForceField (the older triangle membrane, flavor TriangleFEM of
// TriangularFEMForceField) with SOFA's own operations, in SOFA's order, so that a scene's
// trajectory agrees with SOFA's to the last bit: TriangleFEMUtils::computeRotationLarge,
// computeDisplacementLarge/Small, computeStrainDisplacementLocal, computeStrain, computeStress and
// computeForceLarge as TriangleFEMForceField::initLarge, accumulateForceLarge/Small and
// applyStiffnessLarge/Small call them (fullMethod false for "large", true for "small"). The
// mathematics is that of triangular_fem.hpp; only the rounding differs.
#include "penalty/core/types.hpp"

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
/// The local nodal force changes of applyStiffnessLarge/Small for the local (large: R_0_2·dx;
/// small: world) x, y components `dx` of the three vertices, J and the material of the element.
Displacement stiffness_forces(bool large, const StrainDisplacement& j, const Mat3& material, const Displacement& dx);

}  // namespace penalty::triangle_fem_sofa
