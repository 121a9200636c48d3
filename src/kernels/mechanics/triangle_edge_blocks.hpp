#pragma once
/// @file
/// The product of the triangle spring fields whose stiffness is one 3×3 block D_k per triangle
/// edge k (TriangularQuadraticSpringsForceField, TriangularBiquadraticSpringsForceField: SOFA's
/// addDForce). For triangle t, edge k = 0, 1, 2 with (i, j) = (t_{k+1}, t_{k+2}) and
/// δ = dx_i − dx_j (component by component):
///   df_i += (D_k·δ)·k_factor     row r: D(r,0)·δ₀ + D(r,1)·δ₁ + D(r,2)·δ₂, summed left to right
///   df_j −= (D_kᵀ·δ)·k_factor    row r: D(0,r)·δ₀ + D(1,r)·δ₁ + D(2,r)·δ₂
/// triangle by triangle, edge by edge, i before j (type::Mat::operator*, multTranspose). Scalar
/// (the reference) and in AVX lanes of four triangles (KernelPath::avx; avx512 runs avx): each
/// lane does the scalar operations for its triangle in their order, IEEE lane-wise, nothing
/// fused, and the terms are added after, in the scalar order, so every path gives the same bits
/// (tests/kernels/test_triangle_edge_blocks.cpp). Internal (namespace detail).
#include "penalty/core/types.hpp"
#include "penalty/mechanics/edge_triangle_scatter.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace penalty::detail {

/// Sizes `blocks` for `count` triangles, the last block's lanes zero (then set each triangle's lane).
void size_triangle_edge_blocks(std::vector<TriangleEdgeBlock>& blocks, std::size_t count);
/// Triangle e's vertices and its three edges' blocks D_k into its lane.
void set_triangle_edge_lane(std::vector<TriangleEdgeBlock>& blocks, std::size_t e, const Triangle& t,
                            const std::array<Mat3, 3>& dfdx);

/// df += the terms of triangles [0, count) (see the file comment); `path`: scalar or avx.
void triangle_edge_dforce(KernelPath path, std::span<const TriangleEdgeBlock> blocks, std::size_t count, Vec3* df,
                          const Vec3* dx, double k_factor);

}  // namespace penalty::detail
