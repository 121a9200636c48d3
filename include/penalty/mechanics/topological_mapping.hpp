#pragma once
/// @file
/// SOFA's static topological mappings: the elements a ...TopologicalMapping puts in its output
/// topology at init, in SOFA's order (collision elements and contact ids are indexed by it).
/// Each function names the SOFA class::method it follows. Topological changes are not handled.

#include "penalty/mechanics/topology.hpp"

#include <vector>

namespace penalty {

/// Tetra2TriangleTopologicalMapping::init: the input's triangles (given or derived, in its
/// order) that belong to exactly one tetrahedron, as stored (a derived face is outward for a
/// positively oriented tetrahedron); `flip_normals` stores (t0, t2, t1).
[[nodiscard]] std::vector<Triangle> border_triangles(const MeshTopology& input, bool flip_normals);

/// Hexa2QuadTopologicalMapping::init: the input's quads that belong to exactly one hexahedron,
/// in the input's quad order; `flip_normals` stores (q3, q2, q1, q0).
[[nodiscard]] std::vector<Quad> border_quads(const MeshTopology& input, bool flip_normals);

/// Triangle2EdgeTopologicalMapping::init: the input's edges (given or derived, as stored) that
/// belong to exactly one triangle, in the input's edge order.
[[nodiscard]] std::vector<Edge> border_edges(const MeshTopology& input);

/// Quad2TriangleTopologicalMapping::init: two triangles per quad q, (q1, q2, q0) and (q3, q0, q2),
/// or, with `swapping` when ((i % scale) xor (i / scale)) is odd, (q0, q1, q3) and (q2, q3, q1);
/// scale = cells_x, or cells_y when cells_x = 0 (cells of the input grid; 2 and 1 when the input
/// is not a grid, as SOFA). Throws std::invalid_argument when both are 0.
[[nodiscard]] std::vector<Triangle> triangles_of_quads(const std::vector<Quad>& quads, bool swapping, int cells_x,
                                                       int cells_y);

/// Hexa2TetraTopologicalMapping::init: six tetrahedra per hexahedron h, (0,5,1,6) (0,1,3,6)
/// (1,3,6,2) (6,3,0,7) (6,7,0,5) (7,5,4,0) of its vertices; with `swapping`, cell i first swaps
/// its x edges when i % cells_x is even, its y edges when (i / cells_x) % cells_y is odd, its z
/// edges when i / (cells_x·cells_y) is odd, and an odd number of swaps uses the mirrored pattern.
/// Throws std::invalid_argument when swapping with cells_x or cells_y = 0.
[[nodiscard]] std::vector<Tetrahedron> tetrahedra_of_hexahedra(const std::vector<Hexahedron>& hexahedra, bool swapping,
                                                               int cells_x, int cells_y);

}  // namespace penalty
