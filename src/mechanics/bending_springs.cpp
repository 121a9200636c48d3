#include "penalty/mechanics/bending_springs.hpp"

#include <algorithm>

namespace penalty {

std::vector<Spring> triangular_bending_springs(const MeshTopology& topology, std::span<const Vec3> rest_positions,
                                               double ks, double kd) {
    const auto& triangles = topology.triangles();
    const auto& around_edge = topology.triangles_around_edge();
    const auto& edges_in_triangle = topology.edges_in_triangle();
    // the vertex of triangle t opposite edge e: t[j] where edges_in_triangle[t][j] == e
    const auto opposite = [&](std::int32_t t, std::int32_t e) -> PointId {
        const auto tt = static_cast<std::size_t>(t);
        for (std::size_t j = 0; j < 3; ++j)
            if (edges_in_triangle[tt][j] == e) return triangles[tt][j];
        throw_invalid_argument("TriangularBendingSprings: edge ", e, " is not in triangle ", t);
    };
    std::vector<Spring> springs;
    for (std::size_t e = 0; e < around_edge.size(); ++e) {
        const auto& shell = around_edge[e];
        if (shell.size() != 2) continue;  // only manifold edges carry a spring
        const auto edge = static_cast<std::int32_t>(e);
        // SOFA visits triangles in index order: the first one holding the edge gives m2
        const std::int32_t first = std::min(shell[0], shell[1]);
        const std::int32_t second = std::max(shell[0], shell[1]);
        const PointId m1 = opposite(second, edge);
        const PointId m2 = opposite(first, edge);
        for (const PointId m : {m1, m2})
            if (m < 0 || static_cast<std::size_t>(m) >= rest_positions.size())
                throw_invalid_argument("TriangularBendingSprings: point ", m, " out of range for a state of ",
                                       rest_positions.size(), " points");
        const Vec3 u = rest_positions[static_cast<std::size_t>(m1)] - rest_positions[static_cast<std::size_t>(m2)];
        springs.push_back({.a = m1, .b = m2, .ks = ks, .kd = kd, .rest_length = u.norm()});
    }
    return springs;
}

}  // namespace penalty
