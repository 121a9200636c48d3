#pragma once
/// @file
/// A linear tetrahedral FEM's element data in lane blocks (detail::TetrahedronLargeBlocks: element
/// e's J, D/(36V) and R in lane e % W of block e / W, W the kernel path's width) and the loops of
/// SOFA's element operations over them, by kernel path (every path the same bits):
/// TetrahedronFEMForceField and TetrahedralCorotationalFEMForceField's SOFA path compute the same
/// element operations (initLarge / initPolar / initSmall, accumulateForce*, applyStiffness*), so
/// both keep their data and run their loops here. Internal (namespace detail).
#include "kernels/mechanics/tetrahedron_large.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "tetrahedron_large_element.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <span>

namespace penalty::detail {

/// Blocks of `path`'s width (eight lanes for avx512, whose product reads a block an instruction;
/// four for avx and scalar) for `count` elements: the elements' data move to that width, the
/// lanes past the last element are zeroed (their vector results are never added).
void resize_large_blocks(TetrahedronLargeBlocks& blocks, std::size_t count, KernelPath path);
/// Whether `blocks` holds `count` elements in blocks of `path`'s width.
[[nodiscard]] bool large_blocks_fit(const TetrahedronLargeBlocks& blocks, std::size_t count, KernelPath path);
/// Element `to`'s lane given element `from`'s data (a swap-and-pop of the elements).
void copy_large_element(TetrahedronLargeBlocks& blocks, std::size_t from, std::size_t to);
/// Element e's R, from its lane.
[[nodiscard]] Mat3 large_block_rotation(const TetrahedronLargeBlocks& blocks, std::size_t e);
/// Element e's lane: D/(36V) `m` (its normal block and shear diagonal), R `r` and J of the rest
/// local coordinates `q` (computeStrainDisplacement: vertex k's rows from the three other vertices
/// in cyclic order k+1, k+2, k+3, sign s = −1 for k = 0, 2 and +1 for k = 1, 3; with g_yz, g_xz,
/// g_xy the minor sums of their (y; z), (x; z), (x; y) coordinates, J(3k, xx) = J(3k+1, xy) =
/// J(3k+2, zx) = s·g_yz, J(3k, xy) = J(3k+1, yy) = J(3k+2, yz) = −s·g_xz, J(3k, zx) = J(3k+1, yz) =
/// J(3k+2, zz) = s·g_xy; the lane keeps the three values of each vertex, kCofactorOfEntry).
void store_large_element(TetrahedronLargeBlocks& blocks, std::size_t e, const TetrahedronMaterial& m,
                         const std::array<Vec3, 4>& q, const Mat3& r);

/// Method large's addForce (accumulateForceLarge) over `range`: each element's frame into its
/// lane, f += Rᵀ·F but for the terms `deferred` marks (stored); returns the energy summed in
/// element order, or 0 with element e's into energies[e] (not null). avx and avx512 run four
/// elements at a time (large_add_force_avx), scalar one (tetrahedron_large_element.hpp).
double large_blocks_force(TetrahedronLargeBlocks& blocks, KernelPath path,
                          std::span<const std::array<Vec3, 4>> rest_local, std::span<const Tetrahedron> elements,
                          ElementRange range, std::span<Vec3> f, std::span<const Vec3> x, const DeferredTerms& deferred,
                          double* energies);

/// R of an element of methods polar and svd from its current vertices and its index.
using ElementRotationOf = std::function<Mat3(const std::array<Vec3, 4>&, std::size_t)>;

/// addForce of methods small and polar (accumulateForceSmall, accumulateForcePolar; svd through
/// `rotation_of`, else polar_rotation of the edge rows) over `range`, element by element: polar's
/// frame into the element's lane; the energy as large_blocks_force.
double per_element_blocks_force(TetrahedronLargeBlocks& blocks, FemMethod method,
                                std::span<const std::array<Vec3, 4>> rest_local, std::span<const Tetrahedron> elements,
                                ElementRange range, std::span<Vec3> f, std::span<const Vec3> x,
                                const DeferredTerms& deferred, double* energies, const ElementRotationOf* rotation_of);

/// df −= Rᵀ·F(R·dx, k_factor) (applyStiffnessCorotational, applyStiffnessLarge / Polar) over
/// `range` (its first a multiple of eight), by the kernel path: eight elements an instruction
/// (avx512), four (avx) or one; the terms `deferred` marks stored instead.
void large_blocks_dforce(const TetrahedronLargeBlocks& blocks, KernelPath path, std::span<const Tetrahedron> elements,
                         ElementRange range, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                         const DeferredTerms& deferred);

/// df −= F(dx, k_factor) (applyStiffnessSmall) over `range`, element by element.
void small_blocks_dforce(const TetrahedronLargeBlocks& blocks, std::span<const Tetrahedron> elements,
                         ElementRange range, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                         const DeferredTerms& deferred);

}  // namespace penalty::detail
