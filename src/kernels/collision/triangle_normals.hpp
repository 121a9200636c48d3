#pragma once
/// @file
/// The unit normals of a triangle list (TriangleModel::update, SOFA's
/// TriangleCollisionModel::updateNormals): for triangle (p0, p1, p2)
///   n = (p1 − p0) × (p2 − p0),   |n| = sqrt((n_x² + n_y²) + n_z²),   normal = n / |n|
/// each coordinate divided by |n| (not multiplied by 1/|n|), and the zero vector when |n| is not
/// > 0 (a zero-area triangle, or NaN). The operations and their order are those of Eigen's
/// `cross`, `norm` and `operator/` on Vector3d, so every path gives the same bits. Internal
/// (namespace detail), public for its tests.
#include "penalty/core/types.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/topology.hpp"

#include <span>

namespace penalty::detail {

/// normals[i] = the unit normal of triangles[i] over the positions x, for every i (the sizes of
/// triangles and normals are equal; the vertex ids are valid indices of x). KernelPath::avx
/// computes four triangles per instruction.
void triangle_normals(std::span<const Vec3> x, std::span<const Triangle> triangles, std::span<Vec3> normals,
                      KernelPath path);

}  // namespace penalty::detail
