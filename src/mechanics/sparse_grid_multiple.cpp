// SOFA's SparseGridMultipleTopology: one sparse grid voxelising several closed surfaces, each with
// its stiffness and mass coefficients (SparseGridMultipleTopology::buildAsFinest,
// assembleRegularGrids).
#include "penalty/mechanics/sparse_grid_topology.hpp"

#include <algorithm>

namespace penalty {

SparseGridTopology SparseGridTopology::from_surfaces(std::array<int, 3> n, const Vec3& min, const Vec3& max,
                                                     std::span<const WeightedSurface> surfaces, bool fill_weighted,
                                                     bool erase_previous, bool only_inside_cells) {
    if (surfaces.empty()) throw_invalid_argument("SparseGridMultipleTopology: no surface");
    for (int& count : n) count = std::max(count, 2);
    const std::size_t cells = std::size_t(n[0] - 1) * std::size_t(n[1] - 1) * std::size_t(n[2] - 1);
    std::vector<SparseCellType> types(cells, SparseCellType::outside);
    std::vector<float> stiffness(cells, 0.0f), mass(cells, 0.0f);
    for (const WeightedSurface& surface : surfaces) {
        // buildFromTriangleMesh → voxelizeTriangleMesh on the common grid
        const SparseGridTopology voxels = from_surface(n, min, max, surface.positions, surface.triangles);
        const std::vector<SparseCellType>& own = voxels.grid_cell_types();
        for (std::size_t w = 0; w < cells; ++w) {
            if (own[w] == SparseCellType::inside || (own[w] == SparseCellType::boundary && !fill_weighted)) {
                types[w] = SparseCellType::inside;
                stiffness[w] = surface.stiffness;
                mass[w] = surface.mass;
            } else if (own[w] == SparseCellType::boundary) {
                if (types[w] != SparseCellType::inside) types[w] = SparseCellType::boundary;
                stiffness[w] = erase_previous ? surface.stiffness : (stiffness[w] + surface.stiffness) * 0.5f;
                mass[w] = erase_previous ? surface.mass : (mass[w] + surface.mass) * 0.5f;
            }
        }
    }
    SparseGridTopology grid = from_grid_types(n, min, max, std::move(types), only_inside_cells);
    // each kept cell takes its regular cell's coefficients (_indicesOfCubeinRegularGrid)
    std::vector<float> kept_stiffness(grid.hexahedra_.size()), kept_mass(grid.hexahedra_.size());
    for (std::size_t w = 0; w < cells; ++w) {
        const Index kept = grid.kept_of_grid_cell_[w];
        if (kept < 0) continue;
        kept_stiffness[std::size_t(kept)] = stiffness[w];
        kept_mass[std::size_t(kept)] = mass[w];
    }
    grid.set_coefficients(std::move(kept_stiffness), std::move(kept_mass));
    return grid;
}

}  // namespace penalty
