#pragma once
/// @file
/// SOFA's MeshTetraStuffing engine: fills a closed triangle surface with tetrahedra by isosurface
/// stuffing (Labelle & Shewchuk, SIGGRAPH 2007), with SOFA's points and tetrahedra in SOFA's order
/// (docs/components/mesh_tetra_stuffing.md). In short (MeshTetraStuffing::doUpdate):
///  1. a body-centred cubic lattice over the box: grid G (spacing `size`, centred on the box's
///     centre, two cells beyond it on each side) and grid H (G shifted by half a cell, one more
///     point per axis); the points are G's then H's, x fastest;
///  2. each lattice point is inside, outside or uncertain by the surface crossings of the lattice
///     lines through it (the 3 axes and the 4 diagonals), each line traced from its first point;
///     each point also keeps, per direction, the distance to the nearest crossing (in edge lengths);
///  3. optional snapping (`snapPoints`): a point whose crossing on an edge to a point of the other
///     side is closer than alphaLong (axis edges) or alphaShort (diagonal edges) moves onto it;
///  4. optional cut points (`splitTetrahedra`) on every edge from an outside to an inside point;
///  5. the lattice tetrahedra (4 around each G edge) with an inside vertex are kept, whole or,
///     with splitting, cut by the surface (1, 2 or 3 tetrahedra by the stuffing cases);
///  6. unused points removed (the kept ones keep their order), inverted tetrahedra turned.

#include "penalty/core/types.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <optional>
#include <span>
#include <vector>

namespace penalty {

struct MeshTetraStuffingParameters {
    /// vbbox: the box to fill; unset (or min x ≥ max x): the surface's box grown by 1 % of its size.
    std::optional<std::array<Vec3, 2>> box;
    double size = -8.0;            ///< cell size (m); negative: −(cells along the box's largest side)
    double alpha_long = 0.24999;   ///< snapping threshold on axis edges (fraction of the edge)
    double alpha_short = 0.42978;  ///< snapping threshold on diagonal edges
    bool snap_points = false;
    bool split_tetrahedra = false;
};

struct StuffedVolume {
    std::vector<Vec3> points;
    std::vector<Tetrahedron> tetrahedra;
    std::size_t grid_points = 0;      ///< |G| + |H| before unused points were removed
    std::size_t inverted_turned = 0;  ///< final tetrahedra SOFA reports as inverted (turned)
    std::size_t invalid_splits = 0;   ///< SOFA's "Invalid tetra split" / missing cut point errors
};

/// The stuffing of the closed surface (`triangles`, then each quad as two triangles (0,1,2),
/// (0,2,3)). Throws std::invalid_argument on an empty surface, an index out of range, a
/// non-finite or non-positive cell size, or a lattice above `max_points` points.
[[nodiscard]] StuffedVolume mesh_tetra_stuffing(std::span<const Vec3> points, std::span<const Triangle> triangles,
                                                std::span<const Quad> quads, const MeshTetraStuffingParameters& p,
                                                std::size_t max_points = 50'000'000);

}  // namespace penalty
