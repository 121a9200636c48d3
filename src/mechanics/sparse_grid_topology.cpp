#include "penalty/mechanics/sparse_grid_topology.hpp"
#include "penalty/mechanics/sparse_grid_ramification.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace penalty {

namespace {

constexpr Index kNotKept = -1;

/// SOFA's RegularGridTopology::findCube: t = ((p − p0)·dx)·(1/(dx·dx)) per axis, cell = floor(t),
/// none outside [0, n−2]; also returns the fractions t − cell.
std::optional<std::pair<std::array<int, 3>, Vec3>> regular_cell(const RegularGridTopology& grid, const Vec3& p) {
    std::array<int, 3> cell{};
    Vec3 fraction;
    const Vec3 dx = grid.spacing();
    for (int a = 0; a < 3; ++a) {
        const double inverse_squared = 1 / (dx[a] * dx[a]);
        const double t = ((p[a] - grid.origin()[a]) * dx[a]) * inverse_squared;
        const double c = std::floor(t);
        if (!(c >= 0 && c <= grid.n()[std::size_t(a)] - 2)) return std::nullopt;
        cell[std::size_t(a)] = int(c);
        fraction[a] = t - c;
    }
    return std::pair{cell, fraction};
}

/// Closed triangle against the closed cube [−½, ½]³, by separating axes (the cube's 3 face
/// normals, the triangle's normal, the 9 edge × axis products), in single precision as SOFA's
/// polygon_cube_intersection::fast_polygon_intersects_cube. Touching counts as meeting.
bool triangle_meets_unit_cube(const std::array<std::array<float, 3>, 3>& v) {
    using F3 = std::array<float, 3>;
    const auto sub = [](const F3& a, const F3& b) { return F3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
    const auto cross = [](const F3& a, const F3& b) {
        return F3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    };
    const auto dot = [](const F3& a, const F3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const auto separates = [&](const F3& axis) {
        const float p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
        const float radius = 0.5f * (std::abs(axis[0]) + std::abs(axis[1]) + std::abs(axis[2]));
        return std::min({p0, p1, p2}) > radius || std::max({p0, p1, p2}) < -radius;
    };
    for (int a = 0; a < 3; ++a) {
        F3 axis{0, 0, 0};
        axis[std::size_t(a)] = 1;
        if (separates(axis)) return false;
    }
    const std::array<F3, 3> edges{sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
    if (separates(cross(edges[0], edges[1]))) return false;
    for (const F3& e : edges)
        for (int a = 0; a < 3; ++a) {
            F3 axis{0, 0, 0};
            axis[std::size_t(a)] = 1;
            if (separates(cross(e, axis))) return false;
        }
    return true;
}

}  // namespace

std::pair<Vec3, Vec3> SparseGridTopology::default_box(std::span<const Vec3> positions) {
    if (positions.empty()) throw_invalid_argument("SparseGridTopology: the surface has no points");
    Vec3 lo = positions[0], hi = positions[0];
    for (const Vec3& p : positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Vec3 grow = (hi - lo) / 100.0;  // SparseGridTopology::buildFromTriangleMesh
    return {lo - grow, hi + grow};
}

SparseGridTopology SparseGridTopology::from_surface(std::array<int, 3> n, Vec3 min, Vec3 max,
                                                    std::span<const Vec3> positions,
                                                    std::span<const Triangle> triangles, bool only_inside_cells) {
    if (positions.empty()) throw_invalid_argument("SparseGridTopology: the surface has no points");
    for (int& count : n) count = std::max(count, 2);  // SparseGridTopology::init
    const RegularGridTopology grid(n, min, max);
    const int cx = n[0] - 1, cy = n[1] - 1, cz = n[2] - 1;
    const auto cell_index = [&](int x, int y, int z) { return grid_cell_index(x, y, z, cx, cy); };
    std::vector<SparseCellType> types;
    types.assign(std::size_t(cx) * std::size_t(cy) * std::size_t(cz), SparseCellType::inside);

    // 1. The cell of each surface vertex is BOUNDARY; a vertex outside the grid is moved half a
    //    cell inside (SOFA: within FLT_EPSILON of a face) and only looked up.
    const Vec3 half_cell = grid.spacing() / 2;
    const double eps = static_cast<double>(std::numeric_limits<float>::epsilon());  // SOFA: FLT_EPSILON
    std::vector<std::array<int, 3>> vertex_cell(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        auto found = regular_cell(grid, positions[i]);
        if (found) {
            types[cell_index(found->first[0], found->first[1], found->first[2])] = SparseCellType::boundary;
        } else {
            Vec3 moved = positions[i];
            for (int a = 0; a < 3; ++a) {
                if (moved[a] - eps < min[a]) moved[a] = min[a] + half_cell[a];
                else if (moved[a] + eps > max[a]) moved[a] = max[a] - half_cell[a];
            }
            found = regular_cell(grid, moved);
            if (!found) throw_invalid_argument("SparseGridTopology: surface vertex ", i, " is outside the grid");
        }
        vertex_cell[i] = found->first;
    }

    // 2. Cells met by a triangle, among those between its vertices' cells.
    for (const Triangle& t : triangles) {
        const auto& c0 = vertex_cell[std::size_t(t[0])];
        const auto& c1 = vertex_cell[std::size_t(t[1])];
        const auto& c2 = vertex_cell[std::size_t(t[2])];
        std::array<int, 3> lo{}, hi{};
        for (std::size_t a = 0; a < 3; ++a) {
            lo[a] = std::min({c0[a], c1[a], c2[a]});
            hi[a] = std::max({c0[a], c1[a], c2[a]});
        }
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    SparseCellType& type = types[cell_index(x, y, z)];
                    if (type == SparseCellType::boundary) continue;
                    const Vec3 corner0 = grid.point(x, y, z);
                    const Vec3 diagonal = grid.point(x + 1, y + 1, z + 1) - corner0;
                    const Vec3 centre = corner0 + diagonal * 0.5;
                    std::array<std::array<float, 3>, 3> scaled{};
                    for (std::size_t k = 0; k < 3; ++k)
                        for (int a = 0; a < 3; ++a)
                            scaled[k][std::size_t(a)] =
                                float((positions[std::size_t(t[k])][a] - centre[a]) / diagonal[a]);
                    if (triangle_meets_unit_cube(scaled)) type = SparseCellType::boundary;
                }
    }

    // 3. Flood fill from the grid's border cells through non-BOUNDARY cells: OUTSIDE
    //    (SparseGridTopology::launchPropagationFromSeed / propagateFrom).
    std::vector<std::array<int, 3>> stack;
    const auto seed = [&](int x, int y, int z) {
        stack.push_back({x, y, z});
        while (!stack.empty()) {
            const auto [px, py, pz] = stack.back();
            stack.pop_back();
            SparseCellType& type = types[cell_index(px, py, pz)];
            if (type != SparseCellType::inside) continue;  // BOUNDARY, or OUTSIDE already
            type = SparseCellType::outside;
            if (px > 0) stack.push_back({px - 1, py, pz});
            if (px < cx - 1) stack.push_back({px + 1, py, pz});
            if (py > 0) stack.push_back({px, py - 1, pz});
            if (py < cy - 1) stack.push_back({px, py + 1, pz});
            if (pz > 0) stack.push_back({px, py, pz - 1});
            if (pz < cz - 1) stack.push_back({px, py, pz + 1});
        }
    };
    for (int z = 0; z < cz; ++z)
        for (int y = 0; y < cy; ++y)
            for (int x = 0; x < cx; ++x)
                if (x == 0 || y == 0 || z == 0 || x == cx - 1 || y == cy - 1 || z == cz - 1) seed(x, y, z);

    return from_grid_types(n, min, max, std::move(types), only_inside_cells);
}

SparseGridTopology SparseGridTopology::from_grid_types(std::array<int, 3> n, const Vec3& min, const Vec3& max,
                                                       std::vector<SparseCellType> types, bool only_inside_cells) {
    for (int& count : n) count = std::max(count, 2);
    SparseGridTopology sparse{RegularGridTopology(n, min, max)};
    const RegularGridTopology& grid = sparse.grid_;
    const int cx = n[0] - 1, cy = n[1] - 1;
    if (types.size() != std::size_t(cx) * std::size_t(cy) * std::size_t(n[2] - 1))
        throw_invalid_argument("SparseGridTopology: ", types.size(), " cell types for a grid of ", cx * cy * (n[2] - 1),
                               " cells");
    sparse.grid_types_ = std::move(types);
    const std::vector<SparseCellType>& grid_types = sparse.grid_types_;
    // Kept cells (SparseGridTopology::buildFromRegularGridTypes): BOUNDARY then INSIDE.
    std::vector<std::size_t> kept;
    if (!only_inside_cells)
        for (std::size_t w = 0; w < grid_types.size(); ++w)
            if (grid_types[w] == SparseCellType::boundary) kept.push_back(w);
    for (std::size_t w = 0; w < grid_types.size(); ++w)
        if (grid_types[w] == SparseCellType::inside) kept.push_back(w);

    // Points: corners of kept cells, ordered by (i, j, k) with i slowest (= SOFA's position order).
    const auto corner_key = [&](int i, int j, int k) {
        return (std::size_t(i) * std::size_t(n[1]) + std::size_t(j)) * std::size_t(n[2]) + std::size_t(k);
    };
    const auto corners_of = [&](std::size_t w) {
        const int x = int(w % std::size_t(cx)), y = int(w / std::size_t(cx) % std::size_t(cy)),
                  z = int(w / (std::size_t(cx) * std::size_t(cy)));
        return std::array<std::array<int, 3>, 8>{{{x, y, z},
                                                  {x + 1, y, z},
                                                  {x + 1, y + 1, z},
                                                  {x, y + 1, z},
                                                  {x, y, z + 1},
                                                  {x + 1, y, z + 1},
                                                  {x + 1, y + 1, z + 1},
                                                  {x, y + 1, z + 1}}};
    };
    const std::size_t grid_points = std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]);
    std::vector<PointId> point_of_key(grid_points, -1);
    for (const std::size_t w : kept)
        for (const auto& c : corners_of(w)) point_of_key[corner_key(c[0], c[1], c[2])] = 0;
    PointId next = 0;
    for (int i = 0; i < n[0]; ++i)
        for (int j = 0; j < n[1]; ++j)
            for (int k = 0; k < n[2]; ++k) {
                PointId& id = point_of_key[corner_key(i, j, k)];
                if (id < 0) continue;
                id = next++;
                sparse.points_.push_back(grid.point(i, j, k));
            }
    sparse.kept_of_grid_cell_.assign(grid_types.size(), kNotKept);
    for (const std::size_t w : kept) {
        sparse.kept_of_grid_cell_[w] = Index(sparse.hexahedra_.size());
        Hexahedron h{};
        const auto corners = corners_of(w);
        for (std::size_t k = 0; k < 8; ++k)
            h[k] = point_of_key[corner_key(corners[k][0], corners[k][1], corners[k][2])];
        sparse.hexahedra_.push_back(h);
        sparse.types_.push_back(grid_types[w]);
    }
    return sparse;
}

std::vector<Edge> SparseGridTopology::edges() const {
    static constexpr int kPairs[12][2] = {{0, 1}, {3, 2}, {4, 5}, {7, 6}, {0, 3}, {1, 2},
                                          {4, 7}, {5, 6}, {0, 4}, {1, 5}, {3, 7}, {2, 6}};
    std::vector<Edge> all;
    for (const Hexahedron& h : hexahedra_)
        for (const auto& p : kPairs) all.push_back({h[std::size_t(p[0])], h[std::size_t(p[1])]});
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
}

std::vector<Quad> SparseGridTopology::quads() const {
    static constexpr int kFaces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                         {3, 2, 6, 7}, {0, 4, 7, 3}, {1, 5, 6, 2}};
    std::vector<Quad> all;
    for (const Hexahedron& h : hexahedra_)
        for (const auto& f : kFaces)
            all.push_back({h[std::size_t(f[0])], h[std::size_t(f[1])], h[std::size_t(f[2])], h[std::size_t(f[3])]});
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
}

MeshTopology SparseGridTopology::mesh() const {
    MeshTopology t;
    t.set_num_points(points_.size());
    t.set_edges(edges());
    t.set_quads(quads());
    t.set_hexahedra(hexahedra_);
    return t;
}

namespace {

/// SparseGridTopology::findNearestCube's cell: the BOUNDARY hexahedron whose centre (corners 0
/// and 6) is nearest, in single precision, the first one on ties.
std::size_t nearest_boundary_hexahedron(std::span<const Hexahedron> hexahedra, std::span<const SparseCellType> types,
                                        std::span<const Vec3> points, const Vec3& p) {
    std::size_t best = 0;
    float best_distance = 99999999.0f;
    for (std::size_t w = 0; w < hexahedra.size(); ++w) {
        if (types[w] != SparseCellType::boundary) continue;
        const Vec3 centre = (points[std::size_t(hexahedra[w][0])] + points[std::size_t(hexahedra[w][6])]) * 0.5;
        const auto distance = float((p - centre).norm());
        if (distance < best_distance) {
            best_distance = distance;
            best = w;
        }
    }
    return best;
}

}  // namespace

std::pair<Index, Vec3> SparseGridTopology::locate(const Vec3& p) const {
    if (hexahedra_.empty()) throw_invalid_argument("SparseGridTopology: no cells to locate a point in");
    if (ramification_ && finer_)
        if (auto found = locate_ramified(p)) return *found;
    if (const auto found = regular_cell(grid_, p)) {
        const auto& [c, fraction] = *found;
        const auto w = grid_cell_index(c[0], c[1], c[2], grid_.n()[0] - 1, grid_.n()[1] - 1);
        if (kept_of_grid_cell_[w] != kNotKept) return {kept_of_grid_cell_[w], fraction};
    }
    const std::size_t best = nearest_boundary_hexahedron(hexahedra_, types_, points_, p);
    const Vec3& corner0 = points_[std::size_t(hexahedra_[best][0])];
    const Vec3 diagonal = points_[std::size_t(hexahedra_[best][6])] - corner0;
    return {Index(best), (p - corner0).cwiseQuotient(diagonal)};
}

std::optional<std::pair<Index, Vec3>> SparseGridTopology::locate_ramified(const Vec3& p) const {
    // SparseGridRamificationTopology::findCube / findNearestCube: the finest level's cell (its
    // SparseGridTopology::findCube, else findNearestCube), its connexion's coarsest parent here; the
    // fractions in this level's regular grid (RegularGridTopology::findCube, else findNearestCube:
    // the cell clamped into the grid, the fractions not)
    std::vector<const SparseGridTopology*> levels{this};
    while (levels.back()->finer_) levels.push_back(levels.back()->finer_.get());
    const SparseGridTopology& finest = *levels.back();
    if (!finest.ramification_) return std::nullopt;
    Index fine_cell = kNotKept;
    if (const auto found = regular_cell(finest.grid_, p)) {
        const auto& c = found->first;
        fine_cell = finest.kept_of_grid_cell_[grid_cell_index(c[0], c[1], c[2], finest.grid_.n()[0] - 1,
                                                              finest.grid_.n()[1] - 1)];
    }
    Vec3 fraction;
    const auto inside = fine_cell != kNotKept ? regular_cell(grid_, p) : std::nullopt;
    if (inside) {
        fraction = inside->second;
    } else {
        if (fine_cell == kNotKept)
            fine_cell = Index(nearest_boundary_hexahedron(finest.hexahedra_, finest.types_, finest.points_, p));
        const Vec3 dx = grid_.spacing();
        for (int a = 0; a < 3; ++a) {
            const double t = ((p[a] - grid_.origin()[a]) * dx[a]) * (1 / (dx[a] * dx[a]));
            const double cell = std::clamp(std::floor(t), 0.0, double(grid_.n()[std::size_t(a)] - 2));
            fraction[a] = t - cell;
        }
    }
    Index connexion = finest.ramification_->of_cell[std::size_t(fine_cell)].front();
    for (std::size_t l = levels.size() - 1; l-- > 0;) {
        if (!levels[l]->ramification_) return std::nullopt;
        connexion = levels[l]->ramification_->parent_of_finer[std::size_t(connexion)];
        if (connexion < 0) return std::nullopt;
    }
    return std::pair{connexion, fraction};  // a connexion's id is its hexahedron's index
}

std::vector<double> SparseGridTopology::stiffness_coefficients(bool fill_weighted) const {
    if (stiffness_coefficients_.empty()) return coefficients(fill_weighted);
    return {stiffness_coefficients_.begin(), stiffness_coefficients_.end()};
}

std::vector<double> SparseGridTopology::mass_coefficients(bool fill_weighted) const {
    if (mass_coefficients_.empty()) return coefficients(fill_weighted);
    return {mass_coefficients_.begin(), mass_coefficients_.end()};
}

void SparseGridTopology::set_coefficients(std::vector<float> stiffness, std::vector<float> mass) {
    if (stiffness.size() != hexahedra_.size() || mass.size() != hexahedra_.size())
        throw_invalid_argument("SparseGridTopology: ", stiffness.size(), " stiffness and ", mass.size(),
                               " mass coefficients for ", hexahedra_.size(), " hexahedra");
    stiffness_coefficients_ = std::move(stiffness);
    mass_coefficients_ = std::move(mass);
}

void map_on_sparse_grid(BarycentricMapping& mapping, const SparseGridTopology& grid, std::span<const Vec3> points) {
    // corner of the hexahedron for (dx, dy, dz) = bits of k: SOFA's summation order 0 1 3 2 4 5 7 6
    static constexpr int kCorner[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    std::vector<std::vector<BarycentricMapping::Entry>> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) throw_invalid_argument("BarycentricMapping: point ", i, " is not finite");
        const auto [cell, f] = grid.locate(points[i]);
        const Hexahedron& h = grid.hexahedra()[std::size_t(cell)];
        const double fx = f.x(), fy = f.y(), fz = f.z();
        for (int k = 0; k < 8; ++k) {
            const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
            const double weight = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz);
            rows[i].push_back({Index(h[std::size_t(kCorner[k])]), weight});
        }
    }
    mapping.set_weights(std::move(rows));
}

}  // namespace penalty
