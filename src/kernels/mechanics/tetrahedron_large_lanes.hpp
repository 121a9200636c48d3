#pragma once
/// @file
/// TetrahedronFEMForceField's method-large kernels in vector lanes (KernelPath::avx: four elements
/// an instruction; avx512: eight, for the product only). Each lane does the scalar reference's
/// operations (tetrahedron_large.hpp, and TetrahedronFEMForceField's scalar loops) in their order,
/// with IEEE lane-wise operations and no fused multiply-add, so each result has the scalar loop's
/// bits; the sums into f and df run element by element, vertex by vertex, in the scalar order
/// (tests/kernels/test_tetrahedron_large_lanes.cpp). Internal (namespace detail).
#include "kernels/lanes.hpp"
#include "penalty/core/types.hpp"
#include "penalty/mechanics/fem.hpp"

#include <array>
#include <span>

#ifdef PENALTY_HAS_AVX_LANES
namespace penalty::detail {

/// TetrahedronFEMForceField::addForce (method large) on every element, four to a block: each
/// element's frame R (into `rotation`, `blocks` and, when not empty, `blocks8`), δ from the
/// rotated vertices and `rest_local`, F = J·M·Jᵀδ, then f += Rᵀ·F element by element. Returns the
/// elements' energy ½ δᵀF summed in element order.
double large_add_force_avx(std::span<TetrahedronLargeBlock> blocks, std::span<TetrahedronLargeBlock8> blocks8,
                           std::span<const std::array<Vec3, 4>> rest_local,
                           std::span<const std::array<PointId, 4>> elements, std::span<Mat3> rotation, const Vec3* x,
                           Vec3* f);

/// TetrahedronFEMForceField::applyStiffnessCorotational (method large): df −= Rᵀ·F(R·dx, k_factor)
/// for `element_count` elements, four (large_dforce_avx) or eight (large_dforce_avx512) a block.
void large_dforce_avx(const TetrahedronLargeBlock* blocks, std::size_t element_count, Vec3* df, const Vec3* dx,
                      double k_factor);
void large_dforce_avx512(const TetrahedronLargeBlock8* blocks, std::size_t element_count, Vec3* df, const Vec3* dx,
                         double k_factor);

}  // namespace penalty::detail
#endif
