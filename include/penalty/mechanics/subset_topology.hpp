#pragma once
/// @file
/// SOFA's SubsetTopology engine (SubsetTopology::doUpdate): splits a mesh into the part inside a
/// region of interest and the part outside, in SOFA's order.
///
///  - Region: boxes (bounds included, each pair of bounds put in order), or spheres when centers
///    are given (|p − c| ≤ r). A point is in the region when it is in any box/sphere; an element
///    when all its vertices are in one same box/sphere.
///  - Outputs: the indices of the points and elements inside (increasing), the points inside and
///    outside, and the element lists inside and outside (input order).
///  - `local_indices`: element vertices are renumbered into the point lists they come with. The
///    "border" points — the inside vertices of the triangles (the tetrahedra when there are
///    some) that have vertices both inside and outside the FIRST region — come first in both
///    point lists (increasing), then the other inside (resp. outside) points in order; every
///    vertex is renumbered by its position in the list of its side (border points: the same
///    number on both sides).
///  - `tetrahedra_input` (SOFA's `tetrahedraInput`): the listed tetrahedra are inside, whatever
///    the region; the point lists then hold the vertices of the inside (resp. outside) tetrahedra
///    in order of first use, and local indices follow that order.

#include "penalty/mechanics/regions.hpp"
#include "penalty/mechanics/topology.hpp"

#include <optional>
#include <vector>

namespace penalty {

struct SubsetRegion {
    std::vector<AlignedBox> boxes;  ///< used when `centers` is empty
    std::vector<Vec3> centers;      ///< spheres (SOFA: when `centers` is set)
    std::vector<double> radii;      ///< one per center
};

struct SubsetInput {
    std::vector<Vec3> positions;  ///< rest positions (m)
    std::vector<Edge> edges;
    std::vector<Triangle> triangles;
    std::vector<Quad> quads;
    std::vector<Tetrahedron> tetrahedra;
    std::vector<Hexahedron> hexahedra;
    std::optional<std::vector<PointId>> tetrahedra_input;
    bool local_indices = false;
};

struct SubsetOutput {
    std::vector<PointId> indices;  ///< points inside (with local indices: border points first)
    std::vector<PointId> edge_indices, triangle_indices, quad_indices, tetrahedron_indices, hexahedron_indices;
    std::vector<Vec3> points_in, points_out;
    std::vector<Edge> edges_in, edges_out;
    std::vector<Triangle> triangles_in, triangles_out;
    std::vector<Quad> quads_in, quads_out;
    std::vector<Tetrahedron> tetrahedra_in, tetrahedra_out;
    std::vector<Hexahedron> hexahedra_in, hexahedra_out;
    std::size_t border_count = 0;  ///< SOFA's `nbrborder` (local indices only)
};

/// SubsetTopology::doUpdate. Throws std::invalid_argument for an element vertex out of range or
/// spheres whose centers and radii differ in number.
[[nodiscard]] SubsetOutput select_subset(const SubsetInput& input, const SubsetRegion& region);

}  // namespace penalty
