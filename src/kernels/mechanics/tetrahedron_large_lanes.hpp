#pragma once
/// @file
/// TetrahedronFEMForceField's method-large kernels in vector lanes (KernelPath::avx: four elements
/// an instruction; avx512: eight, for the product only), on detail::TetrahedronLargeLanes. Each
/// lane does the scalar reference's operations (tetrahedron_large.hpp, and
/// TetrahedronFEMForceField's scalar loops) in their order, with IEEE lane-wise operations and no
/// fused multiply-add, so each result has the scalar loop's bits; the sums into f and df run
/// element by element, vertex by vertex, in the scalar order
/// (tests/kernels/test_tetrahedron_large_lanes.cpp). Internal (namespace detail).
#include "kernels/lanes.hpp"
#include "kernels/mechanics/tetrahedron_large.hpp"
#include "penalty/core/types.hpp"
#include "penalty/mechanics/fem.hpp"

#include <array>
#include <span>

#ifdef PENALTY_HAS_AVX_LANES
namespace penalty::detail {

/// TetrahedronFEMForceField::addForce (method large) on the elements of `range` (as
/// large_dforce_avx's), four at a time (a four-lane block, or half an eight-lane one): each
/// element's frame R (into its lane of `blocks`), δ from the rotated vertices and `rest_local`,
/// F = J·M·Jᵀ·δ, then f += Rᵀ·F element by element, but for the terms `deferred` marks, which
/// are stored. Returns the elements' energy ½ δᵀF summed in element order, or 0 with each
/// element's energy into energies[e] when `energies` is not null.
template <std::size_t W>
double large_add_force_avx(std::span<TetrahedronLargeLanes<W>> blocks, std::span<const std::array<Vec3, 4>> rest_local,
                           std::span<const std::array<PointId, 4>> elements, ElementRange range, const Vec3* x, Vec3* f,
                           const DeferredTerms& deferred, double* energies);

/// TetrahedronFEMForceField::applyStiffnessCorotational (method large): df −= Rᵀ·F(R·dx, k_factor)
/// for the elements of `range` (its first a multiple of the width, its end too or the element
/// count), four (large_dforce_avx) or eight (large_dforce_avx512) an instruction; the terms
/// `deferred` marks are stored instead (the product on several threads, OrderedScatter).
void large_dforce_avx(const TetrahedronLargeLanes<4>* blocks, std::span<const std::array<PointId, 4>> elements,
                      ElementRange range, Vec3* df, const Vec3* dx, double k_factor, const DeferredTerms& deferred);
void large_dforce_avx512(const TetrahedronLargeLanes<8>* blocks, std::span<const std::array<PointId, 4>> elements,
                         ElementRange range, Vec3* df, const Vec3* dx, double k_factor, const DeferredTerms& deferred);

}  // namespace penalty::detail
#endif
