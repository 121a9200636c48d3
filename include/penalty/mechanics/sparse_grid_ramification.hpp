#pragma once
/// @file
/// The connexion graph of SOFA's SparseGridRamificationTopology (one level): each cell of the
/// sparse grid holds one or more connexions (groups of finer cells connected through their faces),
/// each connexion is one hexahedron of the level. Built by SparseGridTopology::ramified_finest and
/// SparseGridTopology::from_finer_ramified (src/mechanics/sparse_grid_ramification.cpp).
#include "penalty/mechanics/sparse_grid_topology.hpp"

#include <array>
#include <utility>
#include <vector>

namespace penalty {

/// SOFA's neighbour directions (SparseGridRamificationTopology's enum): a direction d and d ^ 1
/// are opposite.
enum SparseGridDirection : int { kUp = 0, kDown, kRight, kLeft, kBefore, kBehind, kDirections };

/// SparseGridRamificationTopology::Connexion. Its id in the level is its hexahedron's index:
/// connexions are numbered cell by cell (cell order), as SOFA numbers their hexahedra.
struct SparseGridConnexion {
    /// connexions of the same level across each face, ascending ids (SOFA's std::set)
    std::array<std::vector<Index>, kDirections> neighbors;
    /// (place 0..7 in this cell: bit 0 +x, bit 1 +y, bit 2 +z; connexion id in the finer level)
    std::vector<std::pair<int, Index>> children;
    Index cell = 0;  ///< _nonRamifiedHexaIdx: the sparse-grid cell it lies in
};

struct SparseGridRamification {
    std::vector<SparseGridConnexion> connexions;
    std::vector<std::vector<Index>> of_cell;  ///< SOFA's _connexions: the connexions of each cell
    std::vector<Index> parent_of_finer;       ///< each finer connexion's connexion here (empty at the finest level)
};

}  // namespace penalty
