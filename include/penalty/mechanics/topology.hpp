#pragma once
/// @file
/// SOFA's MeshTopology: element lists (edges, triangles, quads, tetrahedra, hexahedra) with the
/// same derived elements and the same adjacency order as SOFA, because collision element indices,
/// ownership flags and contact ids depend on them (spec §3.3, §3.4).
///
/// Derived elements (as SOFA's MeshTopology):
///  - edges: if the mesh has volumes, from tetrahedra then hexahedra (sorted vertex pairs,
///    first occurrence order); else from triangles (edge opposite vertex j = (t[j+1], t[j+2]),
///    kept oriented) then quads (sorted); explicit edges given by the user take precedence;
///  - triangles: only from tetrahedra (when none are given);
///  - quads: only from hexahedra (when none are given).
/// Adjacency lists are built by walking elements in index order, so the first entry of
/// trianglesAroundVertex(v) is the lowest-index triangle that uses v.

#include "penalty/core/types.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace penalty {

using PointId = std::int32_t;
using Edge = std::array<PointId, 2>;
using Triangle = std::array<PointId, 3>;
using Quad = std::array<PointId, 4>;
using Tetrahedron = std::array<PointId, 4>;
using Hexahedron = std::array<PointId, 8>;

class TopologyContainer;

class MeshTopology {
public:
    MeshTopology() = default;
    MeshTopology(const MeshTopology&) = default;
    MeshTopology(MeshTopology&&) noexcept = default;
    MeshTopology& operator=(const MeshTopology&) = default;
    MeshTopology& operator=(MeshTopology&&) noexcept = default;
    ~MeshTopology() = default;

    /// Element lists as given by the user or a loader (before derivation). Negative indices throw
    /// std::invalid_argument; indices >= an explicit num_points throw on first query.
    void set_num_points(std::size_t n);
    void set_edges(std::vector<Edge> edges);
    void set_triangles(std::vector<Triangle> triangles);
    void set_quads(std::vector<Quad> quads);
    void set_tetrahedra(std::vector<Tetrahedron> tetrahedra);
    void set_hexahedra(std::vector<Hexahedron> hexahedra);

    /// Number of points: the explicit count, or 1 + the largest index used by any element.
    [[nodiscard]] std::size_t num_points() const;

    /// Element lists including the derived ones (computed lazily, cached).
    [[nodiscard]] const std::vector<Edge>& edges() const;
    [[nodiscard]] const std::vector<Triangle>& triangles() const;
    [[nodiscard]] const std::vector<Quad>& quads() const;
    [[nodiscard]] const std::vector<Tetrahedron>& tetrahedra() const;
    [[nodiscard]] const std::vector<Hexahedron>& hexahedra() const;

    /// Adjacency (computed lazily, cached), SOFA order: elements in increasing index.
    [[nodiscard]] const std::vector<std::vector<std::int32_t>>& edges_around_vertex() const;
    [[nodiscard]] const std::vector<std::vector<std::int32_t>>& triangles_around_vertex() const;
    [[nodiscard]] const std::vector<std::vector<std::int32_t>>& triangles_around_edge() const;
    [[nodiscard]] const std::vector<std::vector<std::int32_t>>& quads_around_vertex() const;
    [[nodiscard]] const std::vector<std::vector<std::int32_t>>& tetrahedra_around_vertex() const;
    /// edges_in_triangle()[t][j]: index of the edge opposite vertex j of triangle t.
    [[nodiscard]] const std::vector<std::array<std::int32_t, 3>>& edges_in_triangle() const;
    /// Vertices sharing an edge with v (SOFA's verticesAroundVertex).
    [[nodiscard]] const std::vector<std::vector<PointId>>& vertices_around_vertex() const;
    /// edges_in_quad()[q][j]: index of the edge (q[j+1], q[j+2]) of quad q (SOFA's EdgesInQuad).
    [[nodiscard]] const std::vector<std::array<std::int32_t, 4>>& edges_in_quad() const;
    /// Quads sharing each edge, in quad index order.
    [[nodiscard]] const std::vector<std::vector<std::int32_t>>& quads_around_edge() const;
    /// Hexahedra using each vertex, in hexahedron index order.
    [[nodiscard]] const std::vector<std::vector<std::int32_t>>& hexahedra_around_vertex() const;

    /// SOFA's getEdgeIndex(a, b): the first edge of edges_around_vertex()[a] whose other end is b,
    /// whatever its orientation; -1 when there is none.
    [[nodiscard]] std::int32_t edge_index(PointId a, PointId b) const;

    /// Number of topological changes made to this mesh (TopologyContainer); 0 for a static mesh.
    /// Readers that keep something derived from the elements compare it with the one they saw.
    [[nodiscard]] std::uint64_t revision() const { return revision_; }

    /// True when the mesh has tetrahedra or hexahedra (SOFA's hasVolume).
    [[nodiscard]] bool has_volume() const { return !tetrahedra_.empty() || !hexahedra_.empty(); }

    /// Local vertex pairs of the 6 tetrahedron edges and the 12 hexahedron edges, and the four
    /// oriented faces of a tetrahedron (SOFA's tables; faces point outward for a positive tetra).
    static constexpr std::array<std::array<int, 2>, 6> kTetraEdges{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
    static constexpr std::array<std::array<int, 2>, 12> kHexaEdges{
        {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3}, {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}}};
    static constexpr std::array<std::array<int, 3>, 4> kTetraFaces{{{1, 2, 3}, {0, 3, 2}, {1, 3, 0}, {0, 2, 1}}};
    /// Hexahedron faces in SOFA's order (-z, +z, -y, +x, +y, -x for the grid vertex numbering).
    static constexpr std::array<std::array<int, 4>, 6> kHexaFaces{
        {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};

    struct Cache;  ///< the lists and adjacency (src/mechanics/topology/mesh_cache.hpp)

private:
    friend class TopologyContainer;  // edits the lists in place on a topological change
    /// The built cache, owned by this mesh alone (a copy's shared one is copied first).
    Cache& editable_cache();
    void invalidate();
    // implementation-defined caches (see src/mechanics/topology.cpp)
    std::size_t num_points_ = 0;
    std::vector<Edge> given_edges_;
    std::vector<Triangle> given_triangles_;
    std::vector<Quad> given_quads_;
    std::vector<Tetrahedron> tetrahedra_;
    std::vector<Hexahedron> hexahedra_;
    std::uint64_t revision_ = 0;
    const Cache& cache() const;  ///< builds every derived list once (thread-safe)
    static std::shared_ptr<Cache> new_cache();
    mutable std::shared_ptr<Cache> cache_ = new_cache();
};

}  // namespace penalty
