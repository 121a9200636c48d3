// TopologyContainer's additions, SOFA's ...SetTopologyModifier::add...() and add...Process: an
// element is appended with its shells; a face or edge it needs and the mesh lacks is created first,
// with its own event (a new tetrahedron's faces, in SOFA's face order, each after its new edges;
// then its remaining new edges), so the events arrive lowest element first.
#include "penalty/mechanics/topology_container.hpp"

#include "mechanics/topology/mesh_cache.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>

namespace penalty {

namespace {

using Shells = TopologyContainer::Shells;

void grow(Shells& shells, std::size_t n) {
    if (shells.size() < n) shells.resize(n);
}

}  // namespace

template <std::size_t N>
void TopologyContainer::check_addition(ElementType type, const std::vector<std::array<PointId, N>>& elements) const {
    if (!keeps(type))
        throw_invalid_argument("TopologyContainer '", name_, "': a ", element_type_name(level_), " container has no ",
                               element_type_name(type));
    const std::size_t n = num_points();
    for (std::size_t k = 0; k < elements.size(); ++k) {
        for (std::size_t j = 0; j < N; ++j) {
            const PointId p = elements[k][j];
            if (p < 0 || std::size_t(p) >= n)
                throw_invalid_argument("TopologyContainer '", name_, "': new ", element_type_name(type), " ", k,
                                       " uses vertex ", p, ": the container has ", n, " points");
            for (std::size_t i = 0; i < j; ++i)
                if (elements[k][i] == p)
                    throw_invalid_argument("TopologyContainer '", name_, "': new ", element_type_name(type), " ", k,
                                           " uses vertex ", p, " twice");
        }
    }
}

// SOFA's `if (t[i] + 1 > nbrP) setNbPoints(t[i] + 1)` (vertices past the end extend the count).
void TopologyContainer::grow_points(PointId largest) {
    MeshTopology::Cache& c = lists();
    if (std::size_t(largest) + 1 > c.num_points) c.num_points = std::size_t(largest) + 1;
}

// PointSetTopologyModifier::addPointsProcess and the overrides: the count and every shell table.
void TopologyContainer::add_points_process(std::size_t count) {
    MeshTopology::Cache& c = lists();
    c.num_points += count;
    for (Shells* s : {&c.edges_around_vertex, &c.triangles_around_vertex, &c.quads_around_vertex,
                      &c.tetrahedra_around_vertex, &c.hexahedra_around_vertex})
        s->resize(c.num_points);
    c.vertices_around_vertex.resize(c.num_points);
}

// EdgeSetTopologyModifier::addEdgeProcess and the overrides of addEdgesProcess (the shell
// tables of the higher elements grow with the edges).
void TopologyContainer::add_edge_process(const Edge& e) {
    grow_points(std::max(e[0], e[1]));
    MeshTopology::Cache& c = lists();
    grow(c.edges_around_vertex, c.num_points);
    const auto id = ElementId(c.edges.size());
    c.edges_around_vertex[std::size_t(e[0])].push_back(id);
    c.edges_around_vertex[std::size_t(e[1])].push_back(id);
    c.edges.push_back(e);
    touched_vertices_.insert(touched_vertices_.end(), e.begin(), e.end());
    if (keeps(ElementType::triangle)) grow(c.triangles_around_edge, c.edges.size());
    if (keeps(ElementType::quad)) grow(c.quads_around_edge, c.edges.size());
    if (level_ == ElementType::tetrahedron) grow(tetrahedra_around_edge_, c.edges.size());
    if (level_ == ElementType::hexahedron) grow(hexahedra_around_edge_, c.edges.size());
}

ElementId TopologyContainer::edge_or_create(PointId a, PointId b) {
    ElementId e = edge_index(a, b);
    if (e >= 0) return e;
    const std::vector<Edge> created{Edge{a, b}};
    add_edge_process(created[0]);
    e = ElementId(mesh_->edges().size()) - 1;
    add_warning(ElementType::edge, created, e, {}, {});
    return e;
}

// TriangleSetTopologyModifier::addTriangleProcess (and QuadSetTopologyModifier::addQuadProcess):
// shells of the vertices, then each edge (t[j+1], t[j+2]) found or created, then the element.
void TopologyContainer::add_triangle_process(const Triangle& t) {
    grow_points(*std::max_element(t.begin(), t.end()));
    MeshTopology::Cache& c = lists();
    const auto id = ElementId(c.triangles.size());
    grow(c.triangles_around_vertex, c.num_points);
    for (const PointId p : t) c.triangles_around_vertex[std::size_t(p)].push_back(id);
    c.edges_in_triangle.resize(std::size_t(id) + 1);
    for (std::size_t j = 0; j < 3; ++j) {
        const ElementId e = edge_or_create(t[(j + 1) % 3], t[(j + 2) % 3]);
        c.edges_in_triangle[std::size_t(id)][j] = e;
        grow(c.triangles_around_edge, c.edges.size());
        c.triangles_around_edge[std::size_t(e)].push_back(id);
    }
    c.triangles.push_back(t);
    if (level_ == ElementType::tetrahedron) grow(tetrahedra_around_triangle_, c.triangles.size());
}

void TopologyContainer::add_quad_process(const Quad& q) {
    grow_points(*std::max_element(q.begin(), q.end()));
    MeshTopology::Cache& c = lists();
    const auto id = ElementId(c.quads.size());
    grow(c.quads_around_vertex, c.num_points);
    for (const PointId p : q) c.quads_around_vertex[std::size_t(p)].push_back(id);
    c.edges_in_quad.resize(std::size_t(id) + 1);
    for (std::size_t j = 0; j < 4; ++j) {
        const ElementId e = edge_or_create(q[(j + 1) % 4], q[(j + 2) % 4]);
        c.edges_in_quad[std::size_t(id)][j] = e;
        grow(c.quads_around_edge, c.edges.size());
        c.quads_around_edge[std::size_t(e)].push_back(id);
    }
    c.quads.push_back(q);
    if (level_ == ElementType::hexahedron) grow(hexahedra_around_quad_, c.quads.size());
}

// TetrahedronSetTopologyModifier::addTetrahedronProcess: vertex shells; each face
// (trianglesOrientationInTetrahedronArray) found or created with its TrianglesAdded event; each
// edge (edgesInTetrahedronArray) found or created; then the tetrahedron.
void TopologyContainer::add_tetrahedron_process(const Tetrahedron& t) {
    grow_points(*std::max_element(t.begin(), t.end()));
    MeshTopology::Cache& c = lists();
    auto& cells = mesh_->tetrahedra_;
    const auto id = ElementId(cells.size());
    grow(c.tetrahedra_around_vertex, c.num_points);
    for (const PointId p : t) c.tetrahedra_around_vertex[std::size_t(p)].push_back(id);
    triangles_in_tetrahedron_.resize(std::size_t(id) + 1);
    for (std::size_t j = 0; j < 4; ++j) {
        const auto& f = MeshTopology::kTetraFaces[j];
        const Triangle face{t[std::size_t(f[0])], t[std::size_t(f[1])], t[std::size_t(f[2])]};
        ElementId tri = triangle_index(face[0], face[1], face[2]);
        if (tri < 0) {
            add_triangle_process(face);
            tri = ElementId(c.triangles.size()) - 1;
            add_warning(ElementType::triangle, std::vector<Triangle>{face}, tri, {}, {});
        }
        triangles_in_tetrahedron_[std::size_t(id)][j] = tri;
        grow(tetrahedra_around_triangle_, c.triangles.size());
        tetrahedra_around_triangle_[std::size_t(tri)].push_back(id);
    }
    edges_in_tetrahedron_.resize(std::size_t(id) + 1);
    for (std::size_t j = 0; j < 6; ++j) {
        const auto& le = MeshTopology::kTetraEdges[j];
        const ElementId e = edge_or_create(t[std::size_t(le[0])], t[std::size_t(le[1])]);
        edges_in_tetrahedron_[std::size_t(id)][j] = e;
        grow(tetrahedra_around_edge_, c.edges.size());
        tetrahedra_around_edge_[std::size_t(e)].push_back(id);
    }
    cells.push_back(t);
}

// HexahedronSetTopologyModifier::addHexahedronProcess: as a tetrahedron, with the six quads
// (quadsOrientationInHexahedronArray) and twelve edges (edgesInHexahedronArray).
void TopologyContainer::add_hexahedron_process(const Hexahedron& h) {
    grow_points(*std::max_element(h.begin(), h.end()));
    MeshTopology::Cache& c = lists();
    auto& cells = mesh_->hexahedra_;
    const auto id = ElementId(cells.size());
    grow(c.hexahedra_around_vertex, c.num_points);
    for (const PointId p : h) c.hexahedra_around_vertex[std::size_t(p)].push_back(id);
    quads_in_hexahedron_.resize(std::size_t(id) + 1);
    for (std::size_t j = 0; j < 6; ++j) {
        const auto& f = MeshTopology::kHexaFaces[j];
        const Quad face{h[std::size_t(f[0])], h[std::size_t(f[1])], h[std::size_t(f[2])], h[std::size_t(f[3])]};
        ElementId q = quad_index(face[0], face[1], face[2], face[3]);
        if (q < 0) {
            add_quad_process(face);
            q = ElementId(c.quads.size()) - 1;
            add_warning(ElementType::quad, std::vector<Quad>{face}, q, {}, {});
        }
        quads_in_hexahedron_[std::size_t(id)][j] = q;
        grow(hexahedra_around_quad_, c.quads.size());
        hexahedra_around_quad_[std::size_t(q)].push_back(id);
    }
    edges_in_hexahedron_.resize(std::size_t(id) + 1);
    for (std::size_t j = 0; j < 12; ++j) {
        const auto& le = MeshTopology::kHexaEdges[j];
        const ElementId e = edge_or_create(h[std::size_t(le[0])], h[std::size_t(le[1])]);
        edges_in_hexahedron_[std::size_t(id)][j] = e;
        grow(hexahedra_around_edge_, c.edges.size());
        hexahedra_around_edge_[std::size_t(e)].push_back(id);
    }
    cells.push_back(h);
}

// ---- public additions (SOFA's add...()) -------------------------------------------------------

// PointSetTopologyModifier::addPoints: process, warning (the states grow), propagation.
void TopologyContainer::add_points(std::size_t count, const std::vector<std::vector<ElementId>>& ancestors,
                                   const std::vector<std::vector<double>>& coefficients, bool add_dof) {
    if (!ancestors.empty() && ancestors.size() != count)
        throw_invalid_argument("TopologyContainer '", name_, "': ", count, " new points with ", ancestors.size(),
                               " ancestor lists");
    for (std::size_t k = 0; k < ancestors.size(); ++k) {
        for (const ElementId a : ancestors[k])
            if (a < 0 || std::size_t(a) >= num_points())
                throw_invalid_argument("TopologyContainer '", name_, "': new point ", k, " has ancestor ", a,
                                       ": the container has ", num_points(), " points");
        if (!coefficients.empty() && (coefficients.size() != count || coefficients[k].size() != ancestors[k].size()))
            throw_invalid_argument("TopologyContainer '", name_, "': new point ", k, " has ", ancestors[k].size(),
                                   " ancestors and ", coefficients.empty() ? 0 : coefficients[k].size(),
                                   " coefficients");
    }
    begin();
    add_points_process(count);
    add_points_warning(count, ancestors, coefficients, add_dof);
    propagate();
    done();
}

// EdgeSetTopologyModifier::addEdges: process, warning, propagation.
void TopologyContainer::add_edges(const std::vector<Edge>& edges, const std::vector<std::vector<ElementId>>& ancestors,
                                  const std::vector<std::vector<double>>& coefficients) {
    check_addition(ElementType::edge, edges);
    begin();
    const auto first = ElementId(mesh_->edges().size());
    for (const Edge& e : edges) add_edge_process(e);
    add_warning(ElementType::edge, edges, first, ancestors, coefficients);
    propagate();
    done();
}

// TriangleSetTopologyModifier::addTriangles: process (new edges warned as they come), warning,
// propagation.
void TopologyContainer::add_triangles(const std::vector<Triangle>& triangles,
                                      const std::vector<std::vector<ElementId>>& ancestors,
                                      const std::vector<std::vector<double>>& coefficients) {
    check_addition(ElementType::triangle, triangles);
    begin();
    const auto first = ElementId(mesh_->triangles().size());
    for (const Triangle& t : triangles) add_triangle_process(t);
    add_warning(ElementType::triangle, triangles, first, ancestors, coefficients);
    propagate();
    done();
}

void TopologyContainer::add_quads(const std::vector<Quad>& quads, const std::vector<std::vector<ElementId>>& ancestors,
                                  const std::vector<std::vector<double>>& coefficients) {
    check_addition(ElementType::quad, quads);
    begin();
    const auto first = ElementId(mesh_->quads().size());
    for (const Quad& q : quads) add_quad_process(q);
    add_warning(ElementType::quad, quads, first, ancestors, coefficients);
    propagate();
    done();
}

void TopologyContainer::add_tetrahedra(const std::vector<Tetrahedron>& tetrahedra,
                                       const std::vector<std::vector<ElementId>>& ancestors,
                                       const std::vector<std::vector<double>>& coefficients) {
    check_addition(ElementType::tetrahedron, tetrahedra);
    begin();
    const auto first = ElementId(mesh_->tetrahedra().size());
    for (const Tetrahedron& t : tetrahedra) add_tetrahedron_process(t);
    add_warning(ElementType::tetrahedron, tetrahedra, first, ancestors, coefficients);
    propagate();
    done();
}

void TopologyContainer::add_hexahedra(const std::vector<Hexahedron>& hexahedra,
                                      const std::vector<std::vector<ElementId>>& ancestors,
                                      const std::vector<std::vector<double>>& coefficients) {
    check_addition(ElementType::hexahedron, hexahedra);
    begin();
    const auto first = ElementId(mesh_->hexahedra().size());
    for (const Hexahedron& h : hexahedra) add_hexahedron_process(h);
    add_warning(ElementType::hexahedron, hexahedra, first, ancestors, coefficients);
    propagate();
    done();
}

}  // namespace penalty
