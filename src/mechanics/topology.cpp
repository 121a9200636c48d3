/// @file
/// MeshTopology: derived elements and adjacency in SOFA's order (see topology.hpp).

#include "penalty/mechanics/topology.hpp"

#include "mechanics/topology/mesh_cache.hpp"

#include "penalty/core/error.hpp"
#include "penalty/core/index_types.hpp"
#include "penalty/core/vertex_list_hash.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <mutex>

namespace penalty {

std::shared_ptr<MeshTopology::Cache> MeshTopology::new_cache() { return std::make_shared<Cache>(); }

namespace {

template <class Element>
void check_non_negative(const std::vector<Element>& elements, const char* what) {
    for (std::size_t i = 0; i < elements.size(); ++i) {
        for (const PointId p : elements[i]) {
            if (p < 0) {
                throw_invalid_argument("MeshTopology: ", what, "[", i, "] has a negative vertex index ", p);
            }
        }
    }
}

template <class Element>
void update_max(const std::vector<Element>& elements, std::size_t& n) {
    for (const auto& e : elements) {
        for (const PointId p : e) n = std::max(n, static_cast<std::size_t>(p) + 1);
    }
}

template <class Element>
void check_range(const std::vector<Element>& elements, std::size_t n, const char* what) {
    for (std::size_t i = 0; i < elements.size(); ++i) {
        for (const PointId p : elements[i]) {
            if (static_cast<std::size_t>(p) >= n) {
                throw_invalid_argument("MeshTopology: ", what, "[", i, "] uses vertex ", p, " but num_points is ", n);
            }
        }
    }
}

Edge sorted_edge(PointId a, PointId b) { return a < b ? Edge{a, b} : Edge{b, a}; }

/// The edges seen so far, each as (smaller, larger) (core/vertex_list_hash.hpp).
using KnownEdges = VertexListSet<PointId, 2>;

/// Adds the edge {a, b} to `edges` unless already known (first occurrence wins).
/// `stored` is what is pushed (the sorted pair, or the oriented pair for triangle edges).
void add_edge(KnownEdges& known, std::vector<Edge>& edges, PointId a, PointId b, const Edge& stored) {
    if (known.insert(sorted_edge(a, b))) edges.push_back(stored);
}

std::vector<Edge> edges_from_volumes(const std::vector<Tetrahedron>& tetras, const std::vector<Hexahedron>& hexas) {
    std::vector<Edge> edges;
    KnownEdges known;
    known.reserve(2 * tetras.size() + 3 * hexas.size());
    for (const auto& t : tetras) {
        for (const auto& le : MeshTopology::kTetraEdges) {
            const PointId a = t[le[0]];
            const PointId b = t[le[1]];
            add_edge(known, edges, a, b, sorted_edge(a, b));
        }
    }
    for (const auto& h : hexas) {
        for (const auto& le : MeshTopology::kHexaEdges) {
            const PointId a = h[le[0]];
            const PointId b = h[le[1]];
            add_edge(known, edges, a, b, sorted_edge(a, b));
        }
    }
    return edges;
}

std::vector<Edge> edges_from_surface(const std::vector<Triangle>& triangles, const std::vector<Quad>& quads) {
    std::vector<Edge> edges;
    KnownEdges known;
    known.reserve(2 * triangles.size() + 2 * quads.size());
    for (const auto& t : triangles) {
        for (int j = 0; j < 3; ++j) {
            const PointId a = t[(j + 1) % 3];
            const PointId b = t[(j + 2) % 3];
            add_edge(known, edges, a, b, Edge{a, b});  // triangle edges keep their orientation
        }
    }
    for (const auto& q : quads) {
        for (int j = 0; j < 4; ++j) {
            const PointId a = q[(j + 1) % 4];
            const PointId b = q[(j + 2) % 4];
            add_edge(known, edges, a, b, sorted_edge(a, b));  // quad edges are sorted
        }
    }
    return edges;
}

/// Triangles of the tetrahedra: each oriented face rotated so that its smallest vertex comes
/// first; a face is new unless the same face with the opposite orientation was already stored.
std::vector<Triangle> triangles_from_tetrahedra(const std::vector<Tetrahedron>& tetras) {
    std::vector<Triangle> triangles;
    VertexListSet<PointId, 3> known;
    known.reserve(2 * tetras.size());  // (a closed volume mesh: about two faces a tetrahedron)
    for (const auto& t : tetras) {
        for (const auto& f : MeshTopology::kTetraFaces) {
            Triangle v{t[f[0]], t[f[1]], t[f[2]]};
            while (v[0] > v[1] || v[0] > v[2]) v = Triangle{v[1], v[2], v[0]};
            const Triangle opposite{v[0], v[2], v[1]};
            if (!known.contains(opposite)) {
                known.insert(v);
                triangles.push_back(v);
            }
        }
    }
    return triangles;
}

/// Quads of the hexahedra: each oriented face rotated so that its smallest vertex comes first;
/// both orientations of a stored face are remembered, so shared faces are stored once.
std::vector<Quad> quads_from_hexahedra(const std::vector<Hexahedron>& hexas) {
    std::vector<Quad> quads;
    VertexListSet<PointId, 4> known;
    known.reserve(2 * 3 * hexas.size());  // (each face and its reverse; three faces a hexahedron)
    for (const auto& h : hexas) {
        for (const auto& f : MeshTopology::kHexaFaces) {
            Quad v{h[f[0]], h[f[1]], h[f[2]], h[f[3]]};
            while (v[0] > v[1] || v[0] > v[2] || v[0] > v[3]) v = Quad{v[1], v[2], v[3], v[0]};
            const Quad reversed{v[0], v[3], v[2], v[1]};
            if (!known.contains(reversed)) {
                known.insert(reversed);
                known.insert(v);
                quads.push_back(v);
            }
        }
    }
    return quads;
}

/// Each vertex's elements in increasing index; each list allocated once at its size (counted
/// first: growing millions of small lists by push_back was a tenth of a large mesh's load).
template <class Element>
std::vector<std::vector<std::int32_t>> around_vertex(const std::vector<Element>& elements, std::size_t n) {
    std::vector<std::uint32_t> count(n, 0);
    for (const auto& e : elements)
        for (const PointId p : e) ++count[static_cast<std::size_t>(p)];
    std::vector<std::vector<std::int32_t>> around(n);
    for (std::size_t v = 0; v < n; ++v) around[v].reserve(count[v]);
    for (std::size_t i = 0; i < elements.size(); ++i) {
        for (const PointId p : elements[i]) around[static_cast<std::size_t>(p)].push_back(static_cast<std::int32_t>(i));
    }
    return around;
}

std::int32_t find_edge(const std::vector<std::vector<std::int32_t>>& edges_around_vertex,
                       const std::vector<Edge>& edges, PointId a, PointId b) {
    if (a < 0 || static_cast<std::size_t>(a) >= edges_around_vertex.size()) return -1;
    for (const std::int32_t e : edges_around_vertex[static_cast<std::size_t>(a)]) {
        const Edge& edge = edges[static_cast<std::size_t>(e)];
        if (edge[0] == b || edge[1] == b) return e;
    }
    return -1;
}

}  // namespace

void MeshTopology::invalidate() { cache_ = new_cache(); }

void MeshTopology::set_num_points(std::size_t n) {
    num_points_ = n;
    invalidate();
}
void MeshTopology::set_edges(std::vector<Edge> edges) {
    check_non_negative(edges, "edges");
    given_edges_ = std::move(edges);
    invalidate();
}
void MeshTopology::set_triangles(std::vector<Triangle> triangles) {
    check_non_negative(triangles, "triangles");
    given_triangles_ = std::move(triangles);
    invalidate();
}
void MeshTopology::set_quads(std::vector<Quad> quads) {
    check_non_negative(quads, "quads");
    given_quads_ = std::move(quads);
    invalidate();
}
void MeshTopology::set_tetrahedra(std::vector<Tetrahedron> tetrahedra) {
    check_non_negative(tetrahedra, "tetrahedra");
    tetrahedra_ = std::move(tetrahedra);
    invalidate();
}
void MeshTopology::set_hexahedra(std::vector<Hexahedron> hexahedra) {
    check_non_negative(hexahedra, "hexahedra");
    hexahedra_ = std::move(hexahedra);
    invalidate();
}

const MeshTopology::Cache& MeshTopology::cache() const {
    if (!cache_) cache_ = new_cache();  // moved-from object
    Cache& c = *cache_;
    std::call_once(c.once, [&] {
        // Number of points: explicit, or 1 + the largest index used (SOFA's init).
        std::size_t n = 0;
        update_max(given_edges_, n);
        update_max(given_triangles_, n);
        update_max(given_quads_, n);
        update_max(tetrahedra_, n);
        update_max(hexahedra_, n);
        if (num_points_ != 0) {
            check_range(given_edges_, num_points_, "edges");
            check_range(given_triangles_, num_points_, "triangles");
            check_range(given_quads_, num_points_, "quads");
            check_range(tetrahedra_, num_points_, "tetrahedra");
            check_range(hexahedra_, num_points_, "hexahedra");
            n = num_points_;
        }
        c.num_points = n;

        // Derived elements: triangles only from tetrahedra, quads only from hexahedra, edges from
        // volumes when there are any, else from the surface (given or derived).
        c.triangles = given_triangles_.empty() ? triangles_from_tetrahedra(tetrahedra_) : given_triangles_;
        c.quads = given_quads_.empty() ? quads_from_hexahedra(hexahedra_) : given_quads_;
        if (!given_edges_.empty()) {
            c.edges = given_edges_;
        } else if (has_volume()) {
            c.edges = edges_from_volumes(tetrahedra_, hexahedra_);
        } else {
            c.edges = edges_from_surface(c.triangles, c.quads);
        }

        // Adjacency, elements in increasing index.
        c.edges_around_vertex = around_vertex(c.edges, n);
        c.triangles_around_vertex = around_vertex(c.triangles, n);
        c.quads_around_vertex = around_vertex(c.quads, n);
        c.tetrahedra_around_vertex = around_vertex(tetrahedra_, n);
        c.hexahedra_around_vertex = around_vertex(hexahedra_, n);

        c.edges_in_triangle.resize(c.triangles.size());
        for (std::size_t i = 0; i < c.triangles.size(); ++i) {
            const Triangle& t = c.triangles[i];
            for (int j = 0; j < 3; ++j) {
                c.edges_in_triangle[i][static_cast<std::size_t>(j)] =
                    find_edge(c.edges_around_vertex, c.edges, t[(j + 1) % 3], t[(j + 2) % 3]);
            }
        }
        c.edges_in_quad.resize(c.quads.size());
        for (std::size_t i = 0; i < c.quads.size(); ++i) {
            const Quad& q = c.quads[i];
            for (int j = 0; j < 4; ++j) {
                c.edges_in_quad[i][static_cast<std::size_t>(j)] =
                    find_edge(c.edges_around_vertex, c.edges, q[(j + 1) % 4], q[(j + 2) % 4]);
            }
        }

        // trianglesAroundEdge: a triangle on the left of the edge (edge[0] == t[j+1], i.e. the
        // triangle runs along the edge's direction) goes to the front, otherwise to the back.
        // Entries inserted at the front end up in reverse insertion order, before the others:
        // counted first, the front ones then written from their end back, the others after them.
        const auto on_left = [&](std::size_t i, int j, std::size_t e) {
            return c.edges[e][0] == c.triangles[i][static_cast<std::size_t>((j + 1) % 3)];
        };
        std::vector<std::uint32_t> front(c.edges.size(), 0);
        std::vector<std::uint32_t> back(c.edges.size(), 0);
        for (std::size_t i = 0; i < c.triangles.size(); ++i)
            for (int j = 0; j < 3; ++j) {
                const std::int32_t e = c.edges_in_triangle[i][static_cast<std::size_t>(j)];
                if (e >= 0) ++(on_left(i, j, std::size_t(e)) ? front : back)[std::size_t(e)];
            }
        c.triangles_around_edge.assign(c.edges.size(), {});
        for (std::size_t e = 0; e < c.edges.size(); ++e) {
            c.triangles_around_edge[e].resize(front[e] + back[e]);
            back[e] = front[e];  // the next back entry's place; front[e]: one past the next front one's
        }
        for (std::size_t i = 0; i < c.triangles.size(); ++i)
            for (int j = 0; j < 3; ++j) {
                const std::int32_t e = c.edges_in_triangle[i][static_cast<std::size_t>(j)];
                if (e < 0) continue;
                const auto ue = static_cast<std::size_t>(e);
                auto& list = c.triangles_around_edge[ue];
                list[on_left(i, j, ue) ? --front[ue] : back[ue]++] = static_cast<std::int32_t>(i);
            }
        c.quads_around_edge.assign(c.edges.size(), {});
        for (std::size_t i = 0; i < c.quads.size(); ++i) {
            for (int j = 0; j < 4; ++j) {
                const std::int32_t e = c.edges_in_quad[i][static_cast<std::size_t>(j)];
                if (e >= 0) c.quads_around_edge[static_cast<std::size_t>(e)].push_back(static_cast<std::int32_t>(i));
            }
        }

        c.vertices_around_vertex.resize(n);
        for (std::size_t v = 0; v < n; ++v) refresh_vertices_around(c, v);
    });
    return c;
}

MeshTopology::Cache& MeshTopology::editable_cache() {
    (void)cache();
    if (cache_.use_count() > 1) {  // a copy of this mesh shares the lists: edit a copy of them
        auto own = new_cache();
        Cache& from = *cache_;
        Cache& to = *own;
        std::call_once(to.once, [&] {
            to.num_points = from.num_points;
            to.edges = from.edges;
            to.triangles = from.triangles;
            to.quads = from.quads;
            to.edges_around_vertex = from.edges_around_vertex;
            to.triangles_around_vertex = from.triangles_around_vertex;
            to.triangles_around_edge = from.triangles_around_edge;
            to.quads_around_vertex = from.quads_around_vertex;
            to.quads_around_edge = from.quads_around_edge;
            to.tetrahedra_around_vertex = from.tetrahedra_around_vertex;
            to.hexahedra_around_vertex = from.hexahedra_around_vertex;
            to.edges_in_triangle = from.edges_in_triangle;
            to.edges_in_quad = from.edges_in_quad;
            to.vertices_around_vertex = from.vertices_around_vertex;
        });
        cache_ = std::move(own);
    }
    return *cache_;
}

std::size_t MeshTopology::num_points() const { return cache().num_points; }
const std::vector<Edge>& MeshTopology::edges() const { return cache().edges; }
const std::vector<Triangle>& MeshTopology::triangles() const { return cache().triangles; }
const std::vector<Quad>& MeshTopology::quads() const { return cache().quads; }
const std::vector<Tetrahedron>& MeshTopology::tetrahedra() const { return tetrahedra_; }
const std::vector<Hexahedron>& MeshTopology::hexahedra() const { return hexahedra_; }

const std::vector<std::vector<std::int32_t>>& MeshTopology::edges_around_vertex() const {
    return cache().edges_around_vertex;
}
const std::vector<std::vector<std::int32_t>>& MeshTopology::triangles_around_vertex() const {
    return cache().triangles_around_vertex;
}
const std::vector<std::vector<std::int32_t>>& MeshTopology::triangles_around_edge() const {
    return cache().triangles_around_edge;
}
const std::vector<std::vector<std::int32_t>>& MeshTopology::quads_around_vertex() const {
    return cache().quads_around_vertex;
}
const std::vector<std::vector<std::int32_t>>& MeshTopology::tetrahedra_around_vertex() const {
    return cache().tetrahedra_around_vertex;
}
const std::vector<std::array<std::int32_t, 3>>& MeshTopology::edges_in_triangle() const {
    return cache().edges_in_triangle;
}
const std::vector<std::vector<PointId>>& MeshTopology::vertices_around_vertex() const {
    return cache().vertices_around_vertex;
}
const std::vector<std::array<std::int32_t, 4>>& MeshTopology::edges_in_quad() const { return cache().edges_in_quad; }
const std::vector<std::vector<std::int32_t>>& MeshTopology::quads_around_edge() const {
    return cache().quads_around_edge;
}
const std::vector<std::vector<std::int32_t>>& MeshTopology::hexahedra_around_vertex() const {
    return cache().hexahedra_around_vertex;
}
std::int32_t MeshTopology::edge_index(PointId a, PointId b) const {
    const Cache& c = cache();
    return find_edge(c.edges_around_vertex, c.edges, a, b);
}

}  // namespace penalty
