#pragma once
/// @file
/// One tetrahedron of SOFA's corotational methods large, polar and svd, in SOFA's floating-point
/// operations and order (private to the mechanics stage). Polar and svd differ from large only
/// in their frame (polar_rotation of the edge rows; svd's own choice for a flat or inverted
/// element) and their rest coordinates (each vertex rotated, not relative to vertex 0:
/// TetrahedronFEMForceField::initPolar, initSVD, accumulateForcePolar, accumulateForceSVD); their
/// product is large's (applyStiffnessCorotational). SOFA writes large's arithmetic twice:
/// TetrahedronFEMForceField (initLarge, computeMaterialStiffness, computeStrainDisplacement,
/// accumulateForceLarge, computeForce, applyStiffnessCorotational) and
/// TetrahedralCorotationalFEMForceField (initLarge, computeMaterialStiffness,
/// computeStrainDisplacement, accumulateForceLarge, computeForce, applyStiffnessLarge): the
/// same frame, rest coordinates, J, D/(36V) and sparse products. Both penalty fields use these
/// functions, so a scene of either matches SOFA's trajectory to the last bit.
#include "kernels/mechanics/tetrahedron_large.hpp"
#include "sofa_vector_ops.hpp"

#include "penalty/core/types.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/topology.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <span>

namespace penalty::detail {

/// δ and F of one element: vertex k's components at 3k … 3k+2.
using TetrahedronDisplacement = Eigen::Matrix<double, 12, 1>;
/// D/(36V), Pa/m³. (J, the 12×6 strain-displacement matrix of cofactors, is kept as its twelve
/// distinct values in the lane blocks: tetrahedron_large_blocks.hpp, store_large_element.)
using TetrahedronMaterial = Eigen::Matrix<double, 6, 6>;

/// Rows (x̂, ŷ, ẑ): x̂ = (b − a)/|b − a|, ẑ = (x̂ × (c − a))/|x̂ × (c − a)|, ŷ = ẑ × x̂
/// (computeRotationLarge; x̂ is normalised before the cross product).
inline Mat3 large_frame(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 x_axis = sofa_vec::normalized(b - a);
    const Vec3 z_axis = sofa_vec::normalized(sofa_vec::cross(x_axis, c - a));
    Mat3 r;
    r.row(0) = x_axis;
    r.row(1) = sofa_vec::cross(z_axis, x_axis);
    r.row(2) = z_axis;
    return r;
}

/// The 2×2 minors' combination u₁v₂ − v₁u₂ − u₀v₂ + v₀u₂ + u₀v₁ − v₀u₁ of the rows u, v of a
/// 2×3 matrix, summed left to right (peudo_determinant_for_coef).
inline double minor_sum(const Vec3& u, const Vec3& v) {
    return u[1] * v[2] - v[1] * u[2] - u[0] * v[2] + v[0] * u[2] + u[0] * v[1] - v[0] * u[1];
}

/// D/(36V) (computeMaterialStiffness): the matrix with 1 on the normal diagonal, ν/(1−ν) off it
/// and (1−2ν)/(2(1−ν)) on the shear diagonal, times E(1−ν)/((1+ν)(1−2ν)), then divided by 36·V,
/// V = |(x1−x0) × (x2−x0) · (x3−x0)|/6 at rest (geometry::Tetrahedron::volume of the world
/// rest positions x).
inline TetrahedronMaterial material_over_volume(double young, double poisson, const std::array<Vec3, 4>& x) {
    TetrahedronMaterial d = TetrahedronMaterial::Zero();
    const double coupling = poisson / (1 - poisson);
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) d(i, k) = i == k ? 1.0 : coupling;
        d(i + 3, i + 3) = (1 - 2 * poisson) / (2 * (1 - poisson));
    }
    d *= (young * (1 - poisson)) / ((1 + poisson) * (1 - 2 * poisson));
    const double volume = std::abs(sofa_vec::dot3(sofa_vec::cross(x[1] - x[0], x[2] - x[0]), x[3] - x[0]) / 6);
    d /= volume * 36;
    return d;
}

/// Rest local coordinates R₀x⁰_k − R₀x⁰_0 of the rest positions x (initLarge: each vertex
/// rotated, then the differences), with their frame R₀ in `frame`.
inline std::array<Vec3, 4> large_rest_local(const std::array<Vec3, 4>& x, Mat3& frame) {
    frame = large_frame(x[0], x[1], x[2]);
    std::array<Vec3, 4> local;
    for (std::size_t k = 0; k < 4; ++k) local[k] = sofa_vec::times(frame, x[k]);
    for (std::size_t k = 1; k < 4; ++k) local[k] -= local[0];
    local[0].setZero();
    return local;
}

/// Rows p1 − p0, p2 − p0, p3 − p0 of positions p (the matrix A of initPolar and
/// accumulateForcePolar).
inline Mat3 edge_rows(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
    Mat3 a;
    a.row(0) = sofa_vec::minus(p1, p0);
    a.row(1) = sofa_vec::minus(p2, p0);
    a.row(2) = sofa_vec::minus(p3, p0);
    return a;
}

/// Rest coordinates of methods polar and svd (initPolar, initSVD): R₀ = polar_rotation(A₀) of the rest positions x,
/// returned in `frame`, and R₀x⁰_k for each vertex (not relative to vertex 0).
inline std::array<Vec3, 4> polar_rest(const std::array<Vec3, 4>& x, Mat3& frame) {
    frame = polar_rotation(edge_rows(x[0], x[1], x[2], x[3]));
    std::array<Vec3, 4> rest;
    for (std::size_t k = 0; k < 4; ++k) rest[k] = sofa_vec::times(frame, x[k]);
    return rest;
}

/// An element's rest coordinates and frame by its method, as SOFA's init stores them: initSmall's
/// world rest positions (frame the identity), initLarge's local coordinates (large_rest_local),
/// initPolar's and initSVD's rotated positions (polar_rest).
inline std::array<Vec3, 4> rest_coordinates(FemMethod method, const std::array<Vec3, 4>& x, Mat3& frame) {
    if (method == FemMethod::Small) {
        frame = Mat3::Identity();
        return x;
    }
    return method == FemMethod::Large ? large_rest_local(x, frame) : polar_rest(x, frame);
}

/// The four vertices of an element as indices into a state.
inline std::array<std::size_t, 4> large_vertices(const Tetrahedron& element) {
    return {static_cast<std::size_t>(element[0]), static_cast<std::size_t>(element[1]),
            static_cast<std::size_t>(element[2]), static_cast<std::size_t>(element[3])};
}

/// element_force_of for one element: F = J·(factor·(M·(Jᵀ·δ))). j(r, c) and m(i, k) give J's
/// and D/(36V)'s entries (Eigen matrices, or one lane of a block: LaneStrainDisplacement,
/// LaneMaterial).
template <class StrainDisplacementEntries, class MaterialEntries>
[[gnu::always_inline]] inline TetrahedronDisplacement large_element_force(const StrainDisplacementEntries& j,
                                                                          const MaterialEntries& m,
                                                                          const TetrahedronDisplacement& delta,
                                                                          std::optional<double> factor) {
    double in[12];
    for (int r = 0; r < 12; ++r) in[r] = delta[r];
    double out[12];
    element_force_of<double>(j, m, in, factor ? &*factor : nullptr, out);
    TetrahedronDisplacement force;
    for (int r = 0; r < 12; ++r) force[r] = out[r];
    return force;
}

/// accumulateForceLarge of one element with vertices `vertex`: its current frame (into r), the
/// vertices rotated one by one, δ = rest − current local coordinates (only the entries J couples:
/// vertex 0 is the origin, vertex 1 lies on x̂, vertex 2 in the x̂ŷ plane), F = J·M·Jᵀ·δ, and
/// the terms Rᵀ·F_k (returned) of f[vertex k] += Rᵀ·F_k. `energy` gets ½ δᵀF (beyond SOFA: its
/// energy report).
template <class StrainDisplacementEntries, class MaterialEntries>
std::array<Vec3, 4> large_element_force_terms(const std::array<std::size_t, 4>& vertex, const std::array<Vec3, 4>& rest,
                                              const StrainDisplacementEntries& j, const MaterialEntries& m,
                                              std::span<const Vec3> x, double& energy, Mat3& r) {
    r = large_frame(x[vertex[0]], x[vertex[1]], x[vertex[2]]);
    std::array<Vec3, 4> deformed;
    for (std::size_t k = 0; k < 4; ++k) deformed[k] = sofa_vec::times(r, x[vertex[k]]);
    TetrahedronDisplacement delta = TetrahedronDisplacement::Zero();
    delta[3] = rest[1][0] - (deformed[1][0] - deformed[0][0]);
    delta[6] = rest[2][0] - (deformed[2][0] - deformed[0][0]);
    delta[7] = rest[2][1] - (deformed[2][1] - deformed[0][1]);
    for (int c = 0; c < 3; ++c) delta[9 + c] = rest[3][c] - (deformed[3][c] - deformed[0][c]);
    const TetrahedronDisplacement force = large_element_force(j, m, delta, std::nullopt);
    large_element_energy(delta, force, energy);
    std::array<Vec3, 4> terms;
    for (std::size_t k = 0; k < 4; ++k)
        terms[k] = sofa_vec::transpose_times(r, force.segment<3>(3 * static_cast<Index>(k)));
    return terms;
}

/// accumulateForcePolar (and accumulateForceSVD) of one element with vertices `vertex` and frame
/// r (polar_rotation(A), or SVD's choice): δ = rest − r·x_k for all twelve entries,
/// F = J·M·Jᵀ·δ, and the terms rᵀ·F_k (returned) of f[vertex k] += rᵀ·F_k. `energy` gets ½ δᵀF
/// summed left to right (beyond SOFA: its energy report).
template <class StrainDisplacementEntries, class MaterialEntries>
std::array<Vec3, 4> polar_element_force_terms(const std::array<std::size_t, 4>& vertex, const std::array<Vec3, 4>& rest,
                                              const Mat3& r, const StrainDisplacementEntries& j,
                                              const MaterialEntries& m, std::span<const Vec3> x, double& energy) {
    TetrahedronDisplacement delta;
    for (std::size_t k = 0; k < 4; ++k) {
        const Vec3 deformed = sofa_vec::times(r, x[vertex[k]]);
        for (std::size_t c = 0; c < 3; ++c) delta[static_cast<Index>(3 * k + c)] = rest[k][c] - deformed[c];
    }
    const TetrahedronDisplacement force = large_element_force(j, m, delta, std::nullopt);
    double work = delta[0] * force[0];
    for (int i = 1; i < 12; ++i) work += delta[i] * force[i];
    energy = 0.5 * work;
    std::array<Vec3, 4> terms;
    for (std::size_t k = 0; k < 4; ++k)
        terms[k] = sofa_vec::transpose_times(r, force.segment<3>(3 * static_cast<Index>(k)));
    return terms;
}

/// TetrahedralCorotationalFEMForceField::accumulateForceSmall of one element with vertices
/// `vertex` and rest positions `rest` (world): δ₀ = 0, δ_k = ((x⁰_k − x⁰_0) − x_k) + x_0 for
/// k = 1 … 3, F = J·M·Jᵀ·δ, and the terms F_k (returned) of f[vertex k] += F_k (no rotation).
/// `energy` gets ½ δᵀF (beyond SOFA).
template <class StrainDisplacementEntries, class MaterialEntries>
std::array<Vec3, 4> small_element_force_terms(const std::array<std::size_t, 4>& vertex, const std::array<Vec3, 4>& rest,
                                              const StrainDisplacementEntries& j, const MaterialEntries& m,
                                              std::span<const Vec3> x, double& energy) {
    TetrahedronDisplacement delta = TetrahedronDisplacement::Zero();
    const Vec3& x0 = x[vertex[0]];
    for (std::size_t k = 1; k < 4; ++k)
        for (std::size_t c = 0; c < 3; ++c)
            delta[static_cast<Index>(3 * k + c)] = rest[k][c] - rest[0][c] - x[vertex[k]][c] + x0[c];
    const TetrahedronDisplacement force = large_element_force(j, m, delta, std::nullopt);
    double work = delta[3] * force[3];
    for (int i = 4; i < 12; ++i) work += delta[i] * force[i];
    energy = 0.5 * work;
    std::array<Vec3, 4> terms;
    for (std::size_t k = 0; k < 4; ++k) terms[k] = force.segment<3>(3 * static_cast<Index>(k));
    return terms;
}

/// TetrahedralCorotationalFEMForceField::applyStiffnessSmall of one element: the terms F_k
/// (returned) of df[vertex k] −= F_k, with F = J·(k·(M·(Jᵀ·dx))).
template <class StrainDisplacementEntries, class MaterialEntries>
std::array<Vec3, 4> small_element_dforce_terms(const std::array<std::size_t, 4>& vertex,
                                               const StrainDisplacementEntries& j, const MaterialEntries& m,
                                               std::span<const Vec3> dx, double k_factor) {
    TetrahedronDisplacement local;
    for (std::size_t k = 0; k < 4; ++k) local.segment<3>(3 * static_cast<Index>(k)) = dx[vertex[k]];
    const TetrahedronDisplacement force = large_element_force(j, m, local, k_factor);
    std::array<Vec3, 4> terms;
    for (std::size_t k = 0; k < 4; ++k) terms[k] = force.segment<3>(3 * static_cast<Index>(k));
    return terms;
}

/// applyStiffnessCorotational / applyStiffnessLarge of one element of frame r (a Mat3, or one
/// lane of a block: LaneRotation): the terms Rᵀ·F_k with F = J·(k·(M·(Jᵀ·(R·dx)))), k = 0 … 3.
template <class Rotation, class StrainDisplacementEntries, class MaterialEntries>
std::array<Vec3, 4> large_element_dforce_terms(const std::array<std::size_t, 4>& vertex, const Rotation& r,
                                               const StrainDisplacementEntries& j, const MaterialEntries& m,
                                               std::span<const Vec3> dx, double k_factor) {
    TetrahedronDisplacement local;
    for (std::size_t k = 0; k < 4; ++k) local.segment<3>(3 * static_cast<Index>(k)) = sofa_vec::times(r, dx[vertex[k]]);
    const TetrahedronDisplacement force = large_element_force(j, m, local, k_factor);
    std::array<Vec3, 4> terms;
    for (std::size_t k = 0; k < 4; ++k)
        terms[k] = sofa_vec::transpose_times(r, force.segment<3>(3 * static_cast<Index>(k)));
    return terms;
}

}  // namespace penalty::detail
