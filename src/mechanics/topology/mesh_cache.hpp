#pragma once
// MeshTopology's element lists and adjacency (private to src/mechanics): the static derivation
// fills it once (topology.cpp); a TopologyContainer edits it in place when the mesh changes
// (topology_container.cpp), so every MeshTopology reader sees the changed mesh.
#include "penalty/mechanics/topology.hpp"

#include <mutex>

namespace penalty {

struct MeshTopology::Cache {
    std::once_flag once;
    std::size_t num_points = 0;
    std::vector<Edge> edges;
    std::vector<Triangle> triangles;
    std::vector<Quad> quads;
    std::vector<std::vector<std::int32_t>> edges_around_vertex;
    std::vector<std::vector<std::int32_t>> triangles_around_vertex;
    std::vector<std::vector<std::int32_t>> triangles_around_edge;
    std::vector<std::vector<std::int32_t>> quads_around_vertex;
    std::vector<std::vector<std::int32_t>> quads_around_edge;
    std::vector<std::vector<std::int32_t>> tetrahedra_around_vertex;
    std::vector<std::vector<std::int32_t>> hexahedra_around_vertex;
    std::vector<std::array<std::int32_t, 3>> edges_in_triangle;
    std::vector<std::array<std::int32_t, 4>> edges_in_quad;
    std::vector<std::vector<PointId>> vertices_around_vertex;
};

/// SOFA's verticesAroundVertex of one vertex: the other end of each edge around it, in order.
inline void refresh_vertices_around(MeshTopology::Cache& c, std::size_t v) {
    auto& out = c.vertices_around_vertex[v];
    out.clear();
    out.reserve(c.edges_around_vertex[v].size());
    for (const std::int32_t e : c.edges_around_vertex[v]) {
        const Edge& edge = c.edges[static_cast<std::size_t>(e)];
        out.push_back(edge[0] == static_cast<PointId>(v) ? edge[1] : edge[0]);
    }
}

}  // namespace penalty
