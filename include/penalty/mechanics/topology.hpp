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
#include <memory>
#include <cstdint>
#include <vector>

namespace penalty {

using PointId = std::int32_t;
using Edge = std::array<PointId, 2>;
using Triangle = std::array<PointId, 3>;
using Quad = std::array<PointId, 4>;
using Tetrahedron = std::array<PointId, 4>;
using Hexahedron = std::array<PointId, 8>;

class MeshTopology {
public:
    MeshTopology() = default;

    /// Element lists as given by the user or a loader (before derivation).
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

private:
    void invalidate();
    // implementation-defined caches (see src/mechanics/topology.cpp)
    std::size_t num_points_ = 0;
    std::vector<Edge> given_edges_;
    std::vector<Triangle> given_triangles_;
    std::vector<Quad> given_quads_;
    std::vector<Tetrahedron> tetrahedra_;
    std::vector<Hexahedron> hexahedra_;
    struct Cache;
    mutable std::shared_ptr<Cache> cache_;
};

}  // namespace penalty
