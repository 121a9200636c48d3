#pragma once
/// @file
/// SOFA's SparseGridTopology built from a closed surface (SparseGridTopology::buildAsFinest →
/// buildFromTriangleMesh → voxelizeTriangleMesh → buildFromRegularGridTypes):
///  - a regular grid of n points per axis between min and max (when both are zero: the surface's
///    bounding box grown by 1/100 of its size on each side);
///  - each cell is BOUNDARY when it holds a surface vertex (floor of the cell coordinates) or when
///    a surface triangle (polygons split as fans v0, v[j−1], v[j]) meets the closed cell (tested
///    in single precision in the cell scaled to the unit cube, as SOFA's polygon–cube test), and
///    only among the cells between the triangle's vertex cells; the cells reachable from the
///    grid's border through non-BOUNDARY cells are OUTSIDE, the rest INSIDE;
///  - kept cells: the BOUNDARY ones in regular-grid order (unless only_inside_cells), then the
///    INSIDE ones in regular-grid order; their hexahedra use the grid's vertex order (i,j,k)
///    (i+1,j,k) (i+1,j+1,k) (i,j+1,k), then the same at k+1;
///  - points: the corners of the kept cells, sorted by position lexicographically (x, then y,
///    then z: SOFA's std::map keyed by Vec3), i.e. by (i, j, k) with i slowest.
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace penalty {

enum class SparseCellType : unsigned char { outside, inside, boundary };

struct SparseGridRamification;  // sparse_grid_ramification.hpp

/// A closed surface given as polygons (SOFA's helper::io::Mesh facets), for the ramification's
/// face test (SparseGridRamificationTopology::sharingTriangle).
struct SparseGridFacets {
    std::vector<Vec3> positions;
    std::vector<std::vector<PointId>> facets;
};

class SparseGridTopology {
public:
    /// Voxelises the closed surface (positions, triangles) on the grid (n, min, max); n is
    /// raised to 2 per axis (SOFA's init). Throws std::invalid_argument for an empty surface or
    /// a surface vertex SOFA cannot place in the grid.
    static SparseGridTopology from_surface(std::array<int, 3> n, Vec3 min, Vec3 max, std::span<const Vec3> positions,
                                           std::span<const Triangle> triangles, bool only_inside_cells = false);
    /// SOFA's SparseGridTopology::buildFromRegularGridTypes: the cells of the regular grid (n, min,
    /// max) typed `types` (regular-grid order, x fastest): BOUNDARY cells (unless
    /// only_inside_cells) then INSIDE ones, points sorted by position.
    static SparseGridTopology from_grid_types(std::array<int, 3> n, const Vec3& min, const Vec3& max,
                                              std::vector<SparseCellType> types, bool only_inside_cells = false);
    /// SOFA's SparseGridMultipleTopology::buildAsFinest (sparse_grid_multiple.cpp): each surface
    /// voxelised on the grid (n, min, max), then the cells assembled surface by surface
    /// (assembleRegularGrids): a cell INSIDE a surface (or BOUNDARY of it without fill_weighted)
    /// becomes INSIDE with that surface's coefficients; a BOUNDARY cell (fill_weighted) becomes
    /// BOUNDARY unless INSIDE already, its coefficients the surface's (erase_previous) or the mean
    /// of the previous ones (0 at first) and the surface's, in single precision.
    struct WeightedSurface {
        std::span<const Vec3> positions;
        std::span<const Triangle> triangles;
        float stiffness = 1.0f, mass = 1.0f;
    };
    static SparseGridTopology from_surfaces(std::array<int, 3> n, const Vec3& min, const Vec3& max,
                                            std::span<const WeightedSurface> surfaces, bool fill_weighted,
                                            bool erase_previous, bool only_inside_cells = false);
    /// SOFA's default box: the bounding box of `positions` grown by 1/100 of its size each side.
    static std::pair<Vec3, Vec3> default_box(std::span<const Vec3> positions);

    [[nodiscard]] const RegularGridTopology& grid() const { return grid_; }
    [[nodiscard]] const std::vector<Vec3>& points() const { return points_; }
    [[nodiscard]] const std::vector<Hexahedron>& hexahedra() const { return hexahedra_; }
    /// Type of each kept cell (boundary or inside), hexahedron order.
    [[nodiscard]] const std::vector<SparseCellType>& cell_types() const { return types_; }
    /// Type of each cell of the regular grid, regular-grid order (x fastest).
    [[nodiscard]] const std::vector<SparseCellType>& grid_cell_types() const { return grid_types_; }
    /// SOFA's SparseGridTopology::updateEdges: the 12 edges of each hexahedron, sorted, unique.
    [[nodiscard]] std::vector<Edge> edges() const;
    /// SOFA's SparseGridTopology::updateQuads: the 6 faces of each hexahedron, sorted, unique.
    [[nodiscard]] std::vector<Quad> quads() const;
    /// The points, hexahedra, edges and quads as a MeshTopology.
    [[nodiscard]] MeshTopology mesh() const;

    /// SOFA's SparseGridTopology::buildFromFiner (the coarser level of a grid with
    /// nbVirtualFinerLevels, sparse_grid_hierarchy.cpp): n = finer n / 2 + 1 per axis, min the
    /// finer's, max = min + (n − 1)·2·(finer spacing); a coarse cell is kept unless its 8 finer
    /// cells (bit 0: +x, bit 1: +y, bit 2: +z) are all absent; INSIDE when all 8 are INSIDE, else
    /// BOUNDARY; cells in the loop order x slowest, z fastest; points sorted by position.
    static SparseGridTopology from_finer(std::shared_ptr<const SparseGridTopology> finer, bool fill_weighted);
    /// The finer level this grid was built from (nullptr for a grid voxelised directly).
    [[nodiscard]] const SparseGridTopology* finer() const { return finer_.get(); }
    /// Per kept cell, its 8 cells of finer() (-1 where none); empty without finer().
    [[nodiscard]] const std::vector<std::array<Index, 8>>& children() const { return children_; }
    /// SOFA's getStiffnessCoef (= getMassCoef) of each kept cell: for a voxelised grid 0.5 for a
    /// boundary cell when `fill_weighted`, else 1; for a coarser level the sum of its children's
    /// over 8 (computed from the finest one's fillWeighted).
    [[nodiscard]] std::vector<double> coefficients(bool fill_weighted) const;
    /// SOFA's getStiffnessCoef / getMassCoef of each hexahedron (floats in SOFA): the coefficients
    /// a builder set (set_coefficients, the ramified levels), else coefficients(fill_weighted).
    [[nodiscard]] std::vector<double> stiffness_coefficients(bool fill_weighted) const;
    [[nodiscard]] std::vector<double> mass_coefficients(bool fill_weighted) const;
    /// Sets SOFA's _stiffnessCoefs and _massCoefs (one per hexahedron).
    void set_coefficients(std::vector<float> stiffness, std::vector<float> mass);

    // ---- SparseGridRamificationTopology (sparse_grid_ramification.cpp) ----
    /// SparseGridRamificationTopology::buildAsFinest after the voxelisation: the connexion graph
    /// of the cells (findConnexionsAtFinestLevel: two face-neighbour cells are connected unless
    /// `surface` is given, both are BOUNDARY and no facet edge crosses their common face), then
    /// with `ramify_points` (finestConnectivity) the hexahedra's points numbered again, a point
    /// shared only through connected faces (buildRamifiedFinestLevel).
    static SparseGridTopology ramified_finest(SparseGridTopology voxels, const SparseGridFacets* surface,
                                              bool ramify_points);
    /// SparseGridRamificationTopology::buildFromFiner: as from_finer, but each coarse cell gives
    /// one hexahedron per connected group of its finer connexions, with its own points; the finer
    /// coefficients are its set ones, else coefficients(fill_weighted).
    static SparseGridTopology from_finer_ramified(std::shared_ptr<const SparseGridTopology> finer, bool fill_weighted);
    /// The connexion graph of a ramification level (nullptr for a plain sparse grid).
    [[nodiscard]] const SparseGridRamification* ramification() const { return ramification_.get(); }

    /// Number of finer levels below this one.
    [[nodiscard]] int finer_levels() const { return finer_ ? 1 + finer_->finer_levels() : 0; }

    /// SOFA's SparseGridTopology::findCube, then findNearestCube: the kept cell holding p and
    /// (fx, fy, fz) in it; a point in no kept cell takes the BOUNDARY cell whose centre is nearest
    /// (single-precision distance, first one on ties) with (p − corner0) / diagonal.
    [[nodiscard]] std::pair<Index, Vec3> locate(const Vec3& p) const;

private:
    explicit SparseGridTopology(const RegularGridTopology& grid) : grid_(grid) {}
    RegularGridTopology grid_;
    std::vector<SparseCellType> grid_types_;
    std::vector<Index> kept_of_grid_cell_;  ///< kept cell of each regular cell, or kNotKept
    std::vector<Vec3> points_;
    std::vector<Hexahedron> hexahedra_;
    std::vector<SparseCellType> types_;
    std::shared_ptr<const SparseGridTopology> finer_;                ///< from_finer's finer level
    std::vector<std::array<Index, 8>> children_;                     ///< from_finer's cells of finer_
    std::vector<double> coefficients_;                               ///< from_finer's averaged coefficients
    std::vector<float> stiffness_coefficients_, mass_coefficients_;  ///< set_coefficients (empty: none)
    std::shared_ptr<const SparseGridRamification> ramification_;
    [[nodiscard]] std::optional<std::pair<Index, Vec3>> locate_ramified(const Vec3& p) const;
    /// SparseGridTopology::buildFromFiner's test of coarse cell (i, j, k) over this (finer) grid:
    /// its 8 finer cells into `children` (bit 0: +x, bit 1: +y, bit 2: +z; -1 where none) and its
    /// type: OUTSIDE when all 8 are absent or OUTSIDE (the cell is not kept), INSIDE when all are
    /// INSIDE, else BOUNDARY.
    [[nodiscard]] SparseCellType coarse_cell_of_children(int i, int j, int k, std::array<Index, 8>& children) const;
};

/// BarycentricMapping of points onto a sparse grid, as SOFA's BarycentricMapperSparseGridTopology
/// (trilinear weights summed in the corner order 0, 1, 3, 2, 4, 5, 7, 6).
void map_on_sparse_grid(BarycentricMapping& mapping, const SparseGridTopology& grid, std::span<const Vec3> points);

}  // namespace penalty
