#include "penalty/mechanics/regular_grid_topology.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

RegularGridTopology::RegularGridTopology(std::array<int, 3> n, const Vec3& min, const Vec3& max)
    : n_(n), min_(min), max_(max), dx_(Vec3::Zero()) {
    if (!min.allFinite() || !max.allFinite()) throw_invalid_argument("RegularGridTopology: min/max must be finite");
    for (int a = 0; a < 3; ++a) {
        if (n[static_cast<std::size_t>(a)] < 1) throw_invalid_argument("RegularGridTopology: n[", a, "] must be >= 1, got ", n[static_cast<std::size_t>(a)]);
        if (n[static_cast<std::size_t>(a)] > 1) {
            if (!(max[a] > min[a])) throw_invalid_argument("RegularGridTopology: max[", a, "] must be > min[", a, "]");
            dx_[a] = (max[a] - min[a]) / (n[static_cast<std::size_t>(a)] - 1);
        }
    }
}

Vec3 RegularGridTopology::point(int i, int j, int k) const {
    return min_ + Vec3(i * dx_.x(), j * dx_.y(), k * dx_.z());
}

std::vector<Vec3> RegularGridTopology::points() const {
    std::vector<Vec3> p;
    p.reserve(num_points());
    for (int k = 0; k < n_[2]; ++k)
        for (int j = 0; j < n_[1]; ++j)
            for (int i = 0; i < n_[0]; ++i) p.push_back(point(i, j, k));
    return p;
}

MeshTopology RegularGridTopology::mesh() const {
    MeshTopology topo;
    topo.set_num_points(num_points());
    std::array<int, 3> axes{};
    int dims = 0;
    for (int a = 0; a < 3; ++a)
        if (n_[static_cast<std::size_t>(a)] > 1) axes[static_cast<std::size_t>(dims++)] = a;
    if (dims == 3) {
        std::vector<Hexahedron> hexas;
        for (int k = 0; k + 1 < n_[2]; ++k)
            for (int j = 0; j + 1 < n_[1]; ++j)
                for (int i = 0; i + 1 < n_[0]; ++i)
                    hexas.push_back({point_index(i, j, k), point_index(i + 1, j, k), point_index(i + 1, j + 1, k),
                                     point_index(i, j + 1, k), point_index(i, j, k + 1), point_index(i + 1, j, k + 1),
                                     point_index(i + 1, j + 1, k + 1), point_index(i, j + 1, k + 1)});
        topo.set_hexahedra(std::move(hexas));
    } else if (dims == 2) {
        const int a0 = axes[0], a1 = axes[1];
        std::vector<Quad> quads;
        auto idx = [&](int u, int v) {
            std::array<int, 3> c{0, 0, 0};
            c[static_cast<std::size_t>(a0)] = u;
            c[static_cast<std::size_t>(a1)] = v;
            return point_index(c[0], c[1], c[2]);
        };
        for (int v = 0; v + 1 < n_[static_cast<std::size_t>(a1)]; ++v)
            for (int u = 0; u + 1 < n_[static_cast<std::size_t>(a0)]; ++u)
                quads.push_back({idx(u, v), idx(u + 1, v), idx(u + 1, v + 1), idx(u, v + 1)});
        topo.set_quads(std::move(quads));
    } else if (dims == 1) {
        std::vector<Edge> edges;
        for (int u = 0; u + 1 < static_cast<int>(num_points()); ++u) edges.push_back({u, u + 1});
        topo.set_edges(std::move(edges));
    }
    return topo;
}

std::pair<std::array<int, 3>, Vec3> RegularGridTopology::locate(const Vec3& p) const {
    std::array<int, 3> cell{};
    Vec3 uvw;
    for (int a = 0; a < 3; ++a) {
        const auto ua = static_cast<std::size_t>(a);
        if (n_[ua] < 2) throw_invalid_argument("RegularGridTopology: locate needs a 3-D grid");
        const double t = (p[a] - min_[a]) / dx_[a];
        const int c = std::clamp(static_cast<int>(std::floor(t)), 0, n_[ua] - 2);
        cell[ua] = c;
        uvw[a] = t - c;
    }
    return {cell, uvw};
}

void map_on_regular_grid(BarycentricMapping& mapping, const RegularGridTopology& grid, std::span<const Vec3> points) {
    std::vector<std::vector<BarycentricMapping::Entry>> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!points[i].allFinite()) throw_invalid_argument("BarycentricMapping: point ", i, " is not finite");
        const auto [c, uvw] = grid.locate(points[i]);
        const auto w = trilinear_weights(uvw);
        const std::array<PointId, 8> v = {grid.point_index(c[0], c[1], c[2]),         grid.point_index(c[0] + 1, c[1], c[2]),
                                          grid.point_index(c[0] + 1, c[1] + 1, c[2]), grid.point_index(c[0], c[1] + 1, c[2]),
                                          grid.point_index(c[0], c[1], c[2] + 1),     grid.point_index(c[0] + 1, c[1], c[2] + 1),
                                          grid.point_index(c[0] + 1, c[1] + 1, c[2] + 1), grid.point_index(c[0], c[1] + 1, c[2] + 1)};
        for (std::size_t k = 0; k < 8; ++k) rows[i].push_back({v[k], w[k]});
    }
    mapping.set_weights(std::move(rows));
}

std::vector<Spring> regular_grid_springs(const RegularGridTopology& grid, const MeshSpringParameters& p) {
    MeshSpringParameters q;
    q.lines_stiffness = p.lines_stiffness;
    q.lines_damping = p.lines_damping;
    q.quads_stiffness = p.quads_stiffness;
    q.quads_damping = p.quads_damping;
    q.cubes_stiffness = p.cubes_stiffness;
    q.cubes_damping = p.cubes_damping;
    const std::vector<Vec3> x = grid.points();
    return mesh_springs(grid.mesh(), x, q);
}

}  // namespace penalty
