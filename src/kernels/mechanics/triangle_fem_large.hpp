#pragma once
/// @file
/// TriangularFEMForceField's product with method "large" in SOFA's operation order
/// (applyStiffnessLarge through TriangleFEMUtils, also TriangleFEMForceField's): per triangle,
/// with Rᵀ its frame (columns = local axes), J and Dₐ of the last force evaluation,
///   D = (x, y of R·dx_a, R·dx_b, R·dx_c)          (each a row of Rᵀ times dx, summed left to right)
///   ε = Jᵀ·D, σ = Dₐ·ε, F = J·σ                    (the non-zero terms only, in SOFA's order)
///   df_k += k·(Rᵀ·(−F_2k, −F_2k+1, 0))              (the third column times +0 included)
/// the terms added triangle by triangle, vertex by vertex. Scalar (the reference) and in AVX lanes
/// of four triangles (KernelPath::avx): each lane does the scalar operations in their order, IEEE
/// lane-wise, nothing fused, so every path gives the same bits
/// (tests/kernels/test_triangle_fem_large.cpp), on detail::TriangleFemLargeBlock
/// (triangular_fem.hpp). Internal (namespace detail).
#include "penalty/core/types.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/triangular_fem.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace penalty::detail {

/// The blocks of the triangles (frames Rᵀ, J and Dₐ per triangle, same size); a last block's
/// unused lanes hold zeros and vertex 0.
void fill_triangle_fem_large_blocks(std::vector<TriangleFemLargeBlock>& blocks, std::span<const Triangle> triangles,
                                    std::span<const Mat3> frames, std::span<const Eigen::Matrix<double, 6, 3>> j,
                                    std::span<const Mat3> material);

/// df[v] += each term of triangles [first, end) (see the file comment), triangle by triangle,
/// vertex by vertex; a term `deferred` marks (bit k of mask[e]) is stored at
/// deferred.terms[3e + k] instead. `path`: scalar or avx (avx512 runs avx).
void triangle_fem_large_dforce(KernelPath path, std::span<const TriangleFemLargeBlock> blocks, std::size_t first,
                               std::size_t end, Vec3* df, const Vec3* dx, double k_factor,
                               const DeferredTerms& deferred);

}  // namespace penalty::detail
