// SOFA's SparseGridRamificationTopology: a sparse grid whose cells split into several hexahedra
// where the material inside a cell is not connected (two arms of a C in one coarse cell move
// apart). findConnexionsAtFinestLevel, buildRamifiedFinestLevel and buildFromFiner.
#include "penalty/mechanics/sparse_grid_ramification.hpp"

#include <algorithm>
#include <map>
#include <set>

namespace penalty {

namespace {

constexpr Index kNone = -1;

/// SparseGridRamificationTopology::intersectionSegmentTriangle: the segment [s0, s1] meets the
/// triangle (t0, t1, t2); a segment within 1e-10 of the triangle's plane direction never does.
bool segment_meets_triangle(const Vec3& s0, const Vec3& s1, const Vec3& t0, const Vec3& t1, const Vec3& t2) {
    const Vec3 q = s0 - t0, e1 = t1 - t0, e2 = t2 - t0;
    const Vec3 normal = e1.cross(e2);
    Vec3 direction = s1 - s0;
    const double length = (s1 - s0).norm();
    direction /= length;
    double d_dot_n = direction.dot(normal);
    double sign = 0;
    if (d_dot_n > 1.0e-10) {
        sign = 1.0;
    } else if (d_dot_n < -1.0e-10) {
        sign = -1.0;
        d_dot_n = -d_dot_n;
    } else {
        return false;
    }
    const double b1 = sign * direction.dot(q.cross(e2));
    if (b1 < 0) return false;
    const double b2 = sign * direction.dot(e1.cross(q));
    if (b2 < 0 || b1 + b2 > d_dot_n) return false;
    const double q_dot_n = -sign * q.dot(normal);
    const double extent = length * d_dot_n;
    return -extent <= q_dot_n && q_dot_n <= extent;
}

/// SparseGridRamificationTopology::sharingTriangle: whether a facet edge (each facet's (v[j−1],
/// v[j]), j ≥ 1) crosses the square face (a, b, c, d), split (a, b, c) and (a, c, d).
bool surface_crosses_face(const SparseGridFacets& surface, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    for (const auto& facet : surface.facets)
        for (std::size_t j = 1; j < facet.size(); ++j) {
            const Vec3& s0 = surface.positions[std::size_t(facet[j - 1])];
            const Vec3& s1 = surface.positions[std::size_t(facet[j])];
            if (segment_meets_triangle(s0, s1, a, b, c) || segment_meets_triangle(s0, s1, a, c, d)) return true;
        }
    return false;
}

/// The point numbering shared by buildRamifiedFinestLevel and buildFromFiner: hexahedron h (one
/// per connexion, in id order) first gets the points 8h … 8h+7; across each BEFORE, DOWN and LEFT
/// neighbour the face's 4 points take the neighbour's labels (SOFA's changeIndices(old, new): in
/// every hexahedron the first corner labelled old is relabelled new); the labels still in use are
/// then numbered in increasing order, each at the corner of its first (hexahedron, corner).
void number_ramified_points(const SparseGridRamification& r, std::span<const std::array<Vec3, 8>> cell_corners,
                            std::vector<Hexahedron>& hexahedra, std::vector<Vec3>& points) {
    const std::size_t count = r.connexions.size();
    hexahedra.assign(count, Hexahedron{});
    std::vector<std::vector<Index>> holders(count * 8);  // label -> hexahedra holding it (once per corner)
    for (std::size_t h = 0; h < count; ++h)
        for (std::size_t k = 0; k < 8; ++k) {
            hexahedra[h][k] = PointId(8 * h + k);
            holders[8 * h + k].push_back(Index(h));
        }
    std::vector<Index> moved;
    const auto change = [&](PointId from, PointId to) {
        if (from == to) return;
        moved.swap(holders[std::size_t(from)]);
        holders[std::size_t(from)].clear();
        std::sort(moved.begin(), moved.end());
        for (std::size_t k = 0; k < moved.size(); ++k) {
            const Index h = moved[k];
            if (k > 0 && moved[k - 1] == h) {  // a second corner labelled `from`: SOFA changes only the first
                holders[std::size_t(from)].push_back(h);
                continue;
            }
            for (PointId& corner : hexahedra[std::size_t(h)])
                if (corner == from) {
                    corner = to;
                    break;
                }
            holders[std::size_t(to)].push_back(h);
        }
        moved.clear();
    };
    // (direction, this hexahedron's corner, the neighbour's corner) of the merged faces
    static constexpr int kFaces[3][4][2] = {{{0, 4}, {1, 5}, {2, 6}, {3, 7}},   // BEFORE
                                            {{0, 3}, {4, 7}, {5, 6}, {1, 2}},   // DOWN
                                            {{0, 1}, {4, 5}, {7, 6}, {3, 2}}};  // LEFT
    static constexpr int kFaceDirections[3] = {kBefore, kDown, kLeft};
    for (std::size_t h = 0; h < count; ++h)
        for (int f = 0; f < 3; ++f)
            for (const Index n : r.connexions[h].neighbors[std::size_t(kFaceDirections[f])])
                for (const auto& pair : kFaces[f])
                    change(hexahedra[h][std::size_t(pair[0])], hexahedra[std::size_t(n)][std::size_t(pair[1])]);
    // first (hexahedron, corner) of each label still used, labels in increasing order
    std::vector<std::pair<Index, int>> first(count * 8, {kNone, 0});
    for (std::size_t h = 0; h < count; ++h)
        for (int k = 0; k < 8; ++k) {
            auto& f = first[std::size_t(hexahedra[h][std::size_t(k)])];
            if (f.first == kNone) f = {Index(h), k};
        }
    std::vector<PointId> number(count * 8, -1);
    points.clear();
    for (std::size_t label = 0; label < first.size(); ++label) {
        if (first[label].first == kNone) continue;
        number[label] = PointId(points.size());
        const SparseGridConnexion& holder = r.connexions[std::size_t(first[label].first)];
        points.push_back(cell_corners[std::size_t(holder.cell)][std::size_t(first[label].second)]);
    }
    for (Hexahedron& hexahedron : hexahedra)
        for (PointId& corner : hexahedron) corner = number[std::size_t(corner)];
}

/// SparseGridRamificationTopology::buildFromFiner's connexions (steps 2 and 3 below) of the coarse
/// cells whose finer cells are `cell_children`.
std::shared_ptr<SparseGridRamification> group_connexions(const SparseGridRamification& fine,
                                                         std::span<const std::array<Index, 8>> cell_children) {
    // 2. The connexions of each cell: its finer connexions grouped by their neighbour graph
    //    restricted to the cell (propagateConnexionNumberToNeighbors), groups in the order of their
    //    first member, members in child order
    auto r = std::make_shared<SparseGridRamification>();
    r->of_cell.resize(cell_children.size());
    r->parent_of_finer.assign(fine.connexions.size(), kNone);
    std::vector<Index> group(fine.connexions.size(), kNone);
    std::vector<Index> stack;
    for (std::size_t cell = 0; cell < cell_children.size(); ++cell) {
        std::vector<std::pair<int, Index>> members;  // (place, finer connexion)
        for (int place = 0; place < 8; ++place) {
            const Index child = cell_children[cell][std::size_t(place)];
            if (child == kNone) continue;
            for (const Index c : fine.of_cell[std::size_t(child)]) members.emplace_back(place, c);
        }
        std::set<Index> in_cell;
        for (const auto& m : members) {
            in_cell.insert(m.second);
            group[std::size_t(m.second)] = kNone;
        }
        for (std::size_t m = 0; m < members.size(); ++m) {
            if (group[std::size_t(members[m].second)] != kNone) continue;
            stack.assign(1, members[m].second);
            while (!stack.empty()) {
                const Index c = stack.back();
                stack.pop_back();
                if (group[std::size_t(c)] != kNone) continue;
                group[std::size_t(c)] = Index(m);
                for (const auto& direction : fine.connexions[std::size_t(c)].neighbors)
                    for (const Index neighbour : direction)
                        if (in_cell.contains(neighbour) && group[std::size_t(neighbour)] == kNone)
                            stack.push_back(neighbour);
            }
        }
        std::map<Index, Index> connexion_of_group;
        for (const auto& m : members) connexion_of_group.emplace(group[std::size_t(m.second)], kNone);
        for (auto& [g, id] : connexion_of_group) {
            id = Index(r->connexions.size());
            r->connexions.emplace_back().cell = Index(cell);
            r->of_cell[cell].push_back(id);
        }
        for (const auto& m : members) {
            const Index id = connexion_of_group.at(group[std::size_t(m.second)]);
            r->connexions[std::size_t(id)].children.push_back(m);
            r->parent_of_finer[std::size_t(m.second)] = id;
        }
    }

    // 3. Neighbours: two connexions are neighbours when finer connexions of theirs, in different
    //    cells, are
    std::vector<std::array<std::set<Index>, kDirections>> neighbours(r->connexions.size());
    for (std::size_t c1 = 0; c1 < fine.connexions.size(); ++c1) {  // sets: the order of the visits does not matter
        const Index coarse1 = r->parent_of_finer[c1];
        if (coarse1 == kNone) continue;  // (never: every kept finer cell lies in a kept coarse cell)
        for (int d = 0; d < kDirections; ++d)
            for (const Index c2 : fine.connexions[c1].neighbors[std::size_t(d)]) {
                const Index coarse2 = r->parent_of_finer[std::size_t(c2)];
                if (coarse2 == kNone) continue;
                if (r->connexions[std::size_t(coarse1)].cell == r->connexions[std::size_t(coarse2)].cell) continue;
                neighbours[std::size_t(coarse1)][std::size_t(d)].insert(coarse2);
                neighbours[std::size_t(coarse2)][std::size_t(d ^ 1)].insert(coarse1);
            }
    }
    for (std::size_t c = 0; c < neighbours.size(); ++c)
        for (int d = 0; d < kDirections; ++d)
            r->connexions[c].neighbors[std::size_t(d)].assign(neighbours[c][std::size_t(d)].begin(),
                                                              neighbours[c][std::size_t(d)].end());

    return r;
}

}  // namespace

SparseGridTopology SparseGridTopology::ramified_finest(SparseGridTopology voxels, const SparseGridFacets* surface,
                                                       bool ramify_points) {
    SparseGridTopology grid = std::move(voxels);
    auto r = std::make_shared<SparseGridRamification>();
    const std::size_t cells = grid.hexahedra_.size();
    r->connexions.resize(cells);
    r->of_cell.resize(cells);
    for (std::size_t i = 0; i < cells; ++i) {
        r->connexions[i].cell = Index(i);
        r->of_cell[i] = {Index(i)};
    }
    const auto corner = [&](Index cell, int k) -> const Vec3& {
        return grid.points_[std::size_t(grid.hexahedra_[std::size_t(cell)][std::size_t(k)])];
    };
    // sharingTriangle: only two BOUNDARY cells are tested, on the cell's face toward the neighbour
    const auto connected = [&](Index cell, Index neighbour, int direction) {
        if (surface == nullptr) return true;
        if (grid.types_[std::size_t(cell)] != SparseCellType::boundary ||
            grid.types_[std::size_t(neighbour)] != SparseCellType::boundary)
            return true;
        static constexpr int kFace[6][4] = {{}, {0, 1, 5, 4}, {}, {0, 4, 7, 3}, {0, 1, 2, 3}, {}};
        const auto& f = kFace[direction];
        return surface_crosses_face(*surface, corner(cell, f[0]), corner(cell, f[1]), corner(cell, f[2]),
                                    corner(cell, f[3]));
    };
    const std::array<int, 3> n = grid.grid_.n();
    const int cx = n[0] - 1, cy = n[1] - 1, cz = n[2] - 1;
    const auto kept = [&](int x, int y, int z) { return grid.kept_of_grid_cell_[grid_cell_index(x, y, z, cx, cy)]; };
    const auto link = [&](Index cell, Index neighbour, int direction) {
        if (neighbour == kNone || !connected(cell, neighbour, direction)) return;
        r->connexions[std::size_t(cell)].neighbors[std::size_t(direction)].push_back(neighbour);
        r->connexions[std::size_t(neighbour)].neighbors[std::size_t(direction ^ 1)].push_back(cell);
    };
    for (int z = 0; z < cz; ++z)
        for (int y = 0; y < cy; ++y)
            for (int x = 0; x < cx; ++x) {
                const Index cell = kept(x, y, z);
                if (cell == kNone) continue;
                if (x > 0) link(cell, kept(x - 1, y, z), kLeft);
                if (y > 0) link(cell, kept(x, y - 1, z), kDown);
                if (z > 0) link(cell, kept(x, y, z - 1), kBefore);
            }
    if (ramify_points) {
        std::vector<std::array<Vec3, 8>> cell_corners(cells);
        for (std::size_t i = 0; i < cells; ++i)
            for (int k = 0; k < 8; ++k) cell_corners[i][std::size_t(k)] = corner(Index(i), k);
        number_ramified_points(*r, cell_corners, grid.hexahedra_, grid.points_);
    }
    grid.ramification_ = std::move(r);
    return grid;
}

SparseGridTopology SparseGridTopology::from_finer_ramified(std::shared_ptr<const SparseGridTopology> finer,
                                                           bool fill_weighted) {
    if (!finer || !finer->ramification_)
        throw_invalid_argument("SparseGridRamificationTopology: no ramified finer grid to build from");
    const SparseGridRamification& fine = *finer->ramification_;
    const RegularGridTopology& fine_grid = finer->grid();
    const std::array<int, 3> fine_n = fine_grid.n();
    const std::array<int, 3> n{fine_n[0] / 2 + 1, fine_n[1] / 2 + 1, fine_n[2] / 2 + 1};
    const Vec3 min = fine_grid.min(), dx = fine_grid.spacing();
    Vec3 max;
    for (int a = 0; a < 3; ++a) max[a] = min[a] + (n[static_cast<std::size_t>(a)] - 1) * 2.0 * dx[a];
    SparseGridTopology coarse{RegularGridTopology(n, min, max)};
    const int cx = n[0] - 1, cy = n[1] - 1, cz = n[2] - 1;
    const std::size_t grid_cells = std::size_t(cx) * std::size_t(cy) * std::size_t(cz);
    coarse.grid_types_.assign(grid_cells, SparseCellType::outside);
    coarse.kept_of_grid_cell_.assign(grid_cells, kNone);

    // 1. The cells as SparseGridTopology::buildFromFiner keeps them (x slowest, z fastest); the
    //    finer types are read at the finer cell indices, as SOFA does
    std::vector<std::array<Index, 8>> cell_children;
    std::vector<SparseCellType> cell_types;
    std::vector<std::array<Vec3, 8>> cell_corners;
    static constexpr int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int i = 0; i < cx; ++i)
        for (int j = 0; j < cy; ++j)
            for (int k = 0; k < cz; ++k) {
                std::array<Index, 8> children{};
                const SparseCellType type = finer->coarse_cell_of_children(i, j, k, children);
                if (type == SparseCellType::outside) continue;
                const std::size_t w = grid_cell_index(i, j, k, cx, cy);
                coarse.grid_types_[w] = type;
                coarse.kept_of_grid_cell_[w] = Index(cell_children.size());
                cell_types.push_back(type);
                cell_children.push_back(children);
                std::array<Vec3, 8> corners;
                for (std::size_t v = 0; v < 8; ++v)
                    corners[v] = coarse.grid_.point(i + kCorner[v][0], j + kCorner[v][1], k + kCorner[v][2]);
                cell_corners.push_back(corners);
            }

    auto r = group_connexions(fine, cell_children);

    // 4. One hexahedron per connexion, its points numbered as SOFA's
    number_ramified_points(*r, cell_corners, coarse.hexahedra_, coarse.points_);

    // 5. Children and types per hexahedron: a cell of one connexion keeps its 8 finer cells; a split
    //    one is BOUNDARY and keeps, as SOFA, only its last child's entry (each child overwrites the
    //    8 entries)
    for (std::size_t cell = 0; cell < cell_children.size(); ++cell) {
        if (r->of_cell[cell].size() == 1) {
            coarse.children_.push_back(cell_children[cell]);
            coarse.types_.push_back(cell_types[cell]);
            continue;
        }
        for (const Index id : r->of_cell[cell]) {
            std::array<Index, 8> children{};
            children.fill(kNone);
            for (const auto& [place, c] : r->connexions[std::size_t(id)].children) {
                const Index child_cell = fine.connexions[std::size_t(c)].cell;
                for (std::size_t p = 0; p < 8; ++p) children[p] = child_cell == cell_children[cell][p] ? c : kNone;
            }
            coarse.children_.push_back(children);
            coarse.types_.push_back(SparseCellType::boundary);
        }
    }

    // 6. Coefficients: the children's sum over 8, in single precision (SOFA's floats)
    const std::vector<double> fine_stiffness = finer->stiffness_coefficients(fill_weighted);
    const std::vector<double> fine_mass = finer->mass_coefficients(fill_weighted);
    std::vector<float> stiffness(coarse.hexahedra_.size(), 0.0f), mass(coarse.hexahedra_.size(), 0.0f);
    for (std::size_t e = 0; e < coarse.hexahedra_.size(); ++e) {
        for (const Index child : coarse.children_[e]) {
            if (child == kNone) continue;
            mass[e] += float(fine_mass[std::size_t(child)]);
            stiffness[e] += float(fine_stiffness[std::size_t(child)]);
        }
        stiffness[e] = float(double(stiffness[e]) / 8.0);
        mass[e] = float(double(mass[e]) / 8.0);
    }
    coarse.set_coefficients(std::move(stiffness), std::move(mass));
    coarse.ramification_ = std::move(r);
    coarse.finer_ = std::move(finer);
    return coarse;
}

}  // namespace penalty
