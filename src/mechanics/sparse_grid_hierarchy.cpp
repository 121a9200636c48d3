// SOFA's sparse-grid hierarchy (SparseGridTopology::buildVirtualFinerLevels, buildFromFiner): a
// coarser level built from a finer one, and the stiffness / mass coefficients of each level.
#include "penalty/mechanics/sparse_grid_topology.hpp"

namespace penalty {

SparseCellType SparseGridTopology::coarse_cell_of_children(int i, int j, int k, std::array<Index, 8>& children) const {
    const int fcx = grid_.n()[0] - 1, fcy = grid_.n()[1] - 1, fcz = grid_.n()[2] - 1;
    bool inside = true, outside = true;
    for (int idx = 0; idx < 8; ++idx) {
        const int fx = 2 * i + (idx & 1), fy = 2 * j + ((idx & 2) >> 1), fz = 2 * k + ((idx & 4) >> 2);
        Index child = -1;
        if (fx < fcx && fy < fcy && fz < fcz) child = kept_of_grid_cell_[grid_cell_index(fx, fy, fz, fcx, fcy)];
        children[std::size_t(idx)] = child;
        if (child < 0) {
            inside = false;
        } else if (types_[std::size_t(child)] == SparseCellType::boundary) {
            inside = outside = false;
        } else if (types_[std::size_t(child)] == SparseCellType::inside) {
            outside = false;
        }
    }
    if (outside) return SparseCellType::outside;
    return inside ? SparseCellType::inside : SparseCellType::boundary;
}

SparseGridTopology SparseGridTopology::from_finer(std::shared_ptr<const SparseGridTopology> finer, bool fill_weighted) {
    if (!finer) throw_invalid_argument("SparseGridTopology: no finer grid to build from");
    const RegularGridTopology& fine_grid = finer->grid();
    const std::array<int, 3> fine_n = fine_grid.n();
    const std::array<int, 3> n{fine_n[0] / 2 + 1, fine_n[1] / 2 + 1, fine_n[2] / 2 + 1};
    const Vec3 min = fine_grid.min(), dx = fine_grid.spacing();
    Vec3 max;
    for (int a = 0; a < 3; ++a) max[a] = min[a] + (n[static_cast<std::size_t>(a)] - 1) * 2.0 * dx[a];
    SparseGridTopology coarse{RegularGridTopology(n, min, max)};
    const int cx = n[0] - 1, cy = n[1] - 1, cz = n[2] - 1;
    const std::size_t cells = std::size_t(cx) * std::size_t(cy) * std::size_t(cz);
    coarse.grid_types_.assign(cells, SparseCellType::outside);
    coarse.kept_of_grid_cell_.assign(cells, -1);
    std::vector<std::array<int, 3>> kept;  // the kept cells' (i, j, k), in SOFA's loop order
    for (int i = 0; i < cx; ++i)
        for (int j = 0; j < cy; ++j)
            for (int k = 0; k < cz; ++k) {
                std::array<Index, 8> children{};
                const SparseCellType type = finer->coarse_cell_of_children(i, j, k, children);
                if (type == SparseCellType::outside) continue;
                const std::size_t w = grid_cell_index(i, j, k, cx, cy);
                coarse.grid_types_[w] = type;
                coarse.kept_of_grid_cell_[w] = Index(kept.size());
                coarse.types_.push_back(type);
                coarse.children_.push_back(children);
                kept.push_back({i, j, k});
            }
    // points: the kept cells' corners, sorted by position (SOFA's std::map keyed by Vec3)
    const auto key = [&](int i, int j, int k) {
        return (std::size_t(i) * std::size_t(n[1]) + std::size_t(j)) * std::size_t(n[2]) + std::size_t(k);
    };
    static constexpr int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const std::size_t grid_points = std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]);
    std::vector<PointId> point_of_key(grid_points, -1);
    for (const auto& c : kept)
        for (const auto& d : kCorner) point_of_key[key(c[0] + d[0], c[1] + d[1], c[2] + d[2])] = 0;
    PointId next = 0;
    for (int i = 0; i < n[0]; ++i)
        for (int j = 0; j < n[1]; ++j)
            for (int k = 0; k < n[2]; ++k) {
                PointId& id = point_of_key[key(i, j, k)];
                if (id < 0) continue;
                id = next++;
                coarse.points_.push_back(coarse.grid_.point(i, j, k));
            }
    for (const auto& c : kept) {
        Hexahedron h{};
        for (std::size_t v = 0; v < 8; ++v)
            h[v] = point_of_key[key(c[0] + kCorner[v][0], c[1] + kCorner[v][1], c[2] + kCorner[v][2])];
        coarse.hexahedra_.push_back(h);
    }
    // coefficients: the children's sum over 8 (absent children count 0); in single precision
    // (SOFA's floats) when the finer level has its own (a SparseGridMultipleTopology's)
    if (!finer->stiffness_coefficients_.empty()) {
        std::vector<float> stiffness(coarse.hexahedra_.size(), 0.0f), mass(coarse.hexahedra_.size(), 0.0f);
        for (std::size_t e = 0; e < coarse.hexahedra_.size(); ++e) {
            for (const Index child : coarse.children_[e]) {
                if (child < 0) continue;
                stiffness[e] += finer->stiffness_coefficients_[std::size_t(child)];
                mass[e] += finer->mass_coefficients_[std::size_t(child)];
            }
            stiffness[e] = float(double(stiffness[e]) / 8.0);
            mass[e] = float(double(mass[e]) / 8.0);
        }
        coarse.set_coefficients(std::move(stiffness), std::move(mass));
    }
    const std::vector<double> fine_coefficients = finer->coefficients(fill_weighted);
    coarse.coefficients_.assign(coarse.hexahedra_.size(), 0.0);
    for (std::size_t e = 0; e < coarse.hexahedra_.size(); ++e) {
        for (const Index child : coarse.children_[e])
            if (child >= 0) coarse.coefficients_[e] += fine_coefficients[std::size_t(child)];
        coarse.coefficients_[e] /= 8.0;
    }
    coarse.finer_ = std::move(finer);
    return coarse;
}

std::vector<double> SparseGridTopology::coefficients(bool fill_weighted) const {
    if (finer_) return coefficients_;
    std::vector<double> c;
    c.reserve(types_.size());
    for (const SparseCellType type : types_) c.push_back(type == SparseCellType::boundary && fill_weighted ? 0.5 : 1.0);
    return c;
}

}  // namespace penalty
