#pragma once
/// @file
/// Test and benchmark meshes built from a regular grid.

#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/topology.hpp"

#include <algorithm>
#include <array>
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
                        m.col(s) = pts[static_cast<std::size_t>(t[static_cast<std::size_t>(s + 1)])] - pts[static_cast<std::size_t>(t[0])];
                    if (m.determinant() < 0) std::swap(t[1], t[2]);
                    tetras.push_back(t);
                } while (std::next_permutation(axes.begin(), axes.end()));
            }
    MeshTopology topo;
    topo.set_tetrahedra(std::move(tetras));
    return topo;
}

}  // namespace penalty::test
