#pragma once
/// @file
/// Test and benchmark meshes built from a regular grid.

#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/topology.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace penalty::test {

/// Kuhn subdivision of a regular grid into positively oriented tetrahedra: 6 per cell, one per
/// ordering of the three axes (each walks from the cell's lowest corner to its highest).
inline MeshTopology kuhn_tetrahedra(const RegularGridTopology& g) {
    std::vector<Tetrahedron> tetras;
    const auto pts = g.points();
    for (int k = 0; k + 1 < g.n()[2]; ++k)
        for (int j = 0; j + 1 < g.n()[1]; ++j)
            for (int i = 0; i + 1 < g.n()[0]; ++i) {
                std::array<int, 3> axes{0, 1, 2};
                do {
                    std::array<int, 3> c{i, j, k};
                    Tetrahedron t{};
                    t[0] = g.point_index(c[0], c[1], c[2]);
                    for (std::size_t s = 0; s < 3; ++s) {
                        ++c[static_cast<std::size_t>(axes[s])];
                        t[s + 1] = g.point_index(c[0], c[1], c[2]);
                    }
                    Mat3 m;
                    for (int s = 0; s < 3; ++s)
                        m.col(s) = pts[static_cast<std::size_t>(t[static_cast<std::size_t>(s + 1)])] -
                                   pts[static_cast<std::size_t>(t[0])];
                    if (m.determinant() < 0) std::swap(t[1], t[2]);
                    tetras.push_back(t);
                } while (std::next_permutation(axes.begin(), axes.end()));
            }
    MeshTopology topo;
    topo.set_tetrahedra(std::move(tetras));
    return topo;
}

/// A vertex of grid_mesh: its grid indices (i along x, j along z) and its x, z (m).
struct GridVertex {
    std::size_t i, j;
    double x, z;
};

/// Height field of n × n quads over x, z ∈ [−s, s], y = height(GridVertex); each quad (lowest
/// corner a, b = a + x step, c = a + z step, d = c + 1) split in triangles (a, b, d), (a, d, c).
template <class Height>
void grid_mesh(std::size_t n, double s, const Height& height, std::vector<Vec3>& points, MeshTopology& topology) {
    points.clear();
    for (std::size_t j = 0; j <= n; ++j)
        for (std::size_t i = 0; i <= n; ++i) {
            const double x = -s + 2.0 * s * double(i) / double(n);
            const double z = -s + 2.0 * s * double(j) / double(n);
            points.emplace_back(x, height(GridVertex{i, j, x, z}), z);
        }
    std::vector<Triangle> tris;
    for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < n; ++i) {
            const int a = int(j * (n + 1) + i), b = a + 1, c = a + int(n + 1), d = c + 1;
            tris.push_back(Triangle{a, b, d});
            tris.push_back(Triangle{a, d, c});
        }
    topology.set_num_points(points.size());
    topology.set_triangles(std::move(tris));
}

}  // namespace penalty::test
