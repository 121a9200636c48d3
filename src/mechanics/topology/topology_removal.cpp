// TopologyContainer's removal processes, SOFA's ...SetTopologyModifier::remove...Process: the
// removed element's slot takes the last element (indices in decreasing order), every table that
// names the moved element or vertex is renamed, and the shells of the removed element's vertices,
// edges and faces lose it (those left empty are the isolated items to remove next).
#include "penalty/mechanics/topology_container.hpp"

#include "mechanics/topology/mesh_cache.hpp"

#include <algorithm>

namespace penalty {

namespace {

using Shells = TopologyContainer::Shells;

std::vector<ElementId>& shell(Shells& shells, ElementId i) { return shells[std::size_t(i)]; }

void erase_value(std::vector<ElementId>& s, ElementId v) { s.erase(std::remove(s.begin(), s.end(), v), s.end()); }

void replace_value(std::vector<ElementId>& s, ElementId from, ElementId to) {
    std::replace(s.begin(), s.end(), from, to);
}

/// Removes `id` from the shells of its `items` (vertices, edges or faces); an emptied shell's item
/// joins `isolated` when `collect`.
template <class Items>
void leave_shells(Shells& shells, const Items& items, ElementId id, bool collect, std::vector<ElementId>& isolated) {
    for (const auto item : items) {
        auto& s = shell(shells, ElementId(item));
        erase_value(s, id);
        if (collect && s.empty()) isolated.push_back(ElementId(item));
    }
}

template <class Items>
void rename_in_shells(Shells& shells, const Items& items, ElementId from, ElementId to) {
    for (const auto item : items) replace_value(shell(shells, ElementId(item)), from, to);
}

/// Swap-and-pop of entry `i` of a per-element table whose last entry is `last`.
template <class T>
void move_last_into(std::vector<T>& v, ElementId i, ElementId last) {
    v[std::size_t(i)] = v[std::size_t(last)];
    v.resize(std::size_t(last));
}

/// The cells (tetrahedra or hexahedra) of SOFA's removeTetrahedraProcess /
/// removeHexahedraProcess: leave the shells of their vertices, edges and faces, then swap-and-pop.
template <std::size_t NV, std::size_t NE, std::size_t NF>
void remove_cells(std::vector<std::array<PointId, NV>>& cells, Shells& around_vertex,
                  std::vector<std::array<ElementId, NE>>& edges_in, Shells& around_edge,
                  std::vector<std::array<ElementId, NF>>& faces_in, Shells& around_face,
                  const std::vector<ElementId>& indices, bool vertices, bool edges, bool faces,
                  std::vector<ElementId>& isolated_vertices, std::vector<ElementId>& isolated_edges,
                  std::vector<ElementId>& isolated_faces) {
    auto last = ElementId(cells.size()) - 1;
    for (const ElementId i : indices) {
        const auto removed = cells[std::size_t(i)];
        const auto moved = cells[std::size_t(last)];
        leave_shells(around_vertex, removed, i, vertices, isolated_vertices);
        leave_shells(around_edge, edges_in[std::size_t(i)], i, edges, isolated_edges);
        leave_shells(around_face, faces_in[std::size_t(i)], i, faces, isolated_faces);
        if (i < last) {
            rename_in_shells(around_vertex, moved, last, i);
            rename_in_shells(around_edge, edges_in[std::size_t(last)], last, i);
            rename_in_shells(around_face, faces_in[std::size_t(last)], last, i);
        }
        move_last_into(faces_in, i, last);
        move_last_into(edges_in, i, last);
        move_last_into(cells, i, last);
        --last;
    }
}

/// The surface elements (triangles or quads) of SOFA's removeTrianglesProcess / removeQuadsProcess.
template <std::size_t N>
void remove_faces(std::vector<std::array<PointId, N>>& faces, Shells& around_vertex,
                  std::vector<std::array<ElementId, N>>& edges_in, Shells& around_edge,
                  const std::vector<ElementId>& indices, bool edges, bool vertices,
                  std::vector<ElementId>& isolated_edges, std::vector<ElementId>& isolated_vertices) {
    auto last = ElementId(faces.size()) - 1;
    for (const ElementId i : indices) {
        const auto removed = faces[std::size_t(i)];
        const auto moved = faces[std::size_t(last)];
        leave_shells(around_vertex, removed, i, vertices, isolated_vertices);
        leave_shells(around_edge, edges_in[std::size_t(i)], i, edges, isolated_edges);
        if (i < last) {
            rename_in_shells(around_vertex, moved, last, i);
            rename_in_shells(around_edge, edges_in[std::size_t(last)], last, i);
        }
        move_last_into(edges_in, i, last);
        move_last_into(faces, i, last);
        --last;
    }
}

/// A higher element's references to lower elements removed by swap-and-pop (SOFA's
/// removeEdgesProcess / removeTrianglesProcess of the higher modifiers): each element around
/// the last lower element names it by the removed one's index, whose shell it takes.
template <std::size_t K>
void rename_lower(std::vector<std::array<ElementId, K>>& in, Shells& around, const std::vector<ElementId>& indices) {
    if (in.empty()) return;  // SOFA: only when the higher elements' table exists
    auto last = ElementId(around.size()) - 1;
    for (const ElementId i : indices) {
        for (const ElementId higher : shell(around, last)) {
            auto& refs = in[std::size_t(higher)];
            const auto at = std::find(refs.begin(), refs.end(), last);
            if (at != refs.end()) *at = i;
        }
        around[std::size_t(i)] = around[std::size_t(last)];
        --last;
    }
    around.resize(around.size() - indices.size());
}

/// removePointsProcess of one element type: the elements around the last point name it by the
/// removed point's index (`all`: every slot holding it, as SOFA's triangle and quad modifiers;
/// otherwise the first, as its tetrahedron and hexahedron modifiers), whose shell it takes.
template <std::size_t N>
void rename_vertices(std::vector<std::array<PointId, N>>& elements, Shells& around,
                     const std::vector<ElementId>& indices, std::size_t num_points, bool all) {
    if (elements.empty()) {  // no element to rename; the shells (all empty) follow the count
        around.resize(std::min(around.size(), num_points - indices.size()));
        return;
    }
    auto last = ElementId(num_points) - 1;
    for (const ElementId i : indices) {
        for (const ElementId e : shell(around, last)) {
            auto& v = elements[std::size_t(e)];
            for (auto& p : v) {
                if (p != last) continue;
                p = i;
                if (!all) break;
            }
        }
        around[std::size_t(i)] = around[std::size_t(last)];
        --last;
    }
    around.resize(around.size() - indices.size());
}

}  // namespace

void TopologyContainer::remove_tetrahedra_process(const std::vector<ElementId>& indices, bool remove_isolated_items) {
    auto& cells = mesh_->tetrahedra_;
    if (cells.empty()) return;
    MeshTopology::Cache& c = lists();
    std::vector<ElementId> faces, edges, points;
    remove_cells(cells, c.tetrahedra_around_vertex, edges_in_tetrahedron_, tetrahedra_around_edge_,
                 triangles_in_tetrahedron_, tetrahedra_around_triangle_, indices,
                 remove_isolated_items && options_.remove_isolated, remove_isolated_items && !c.edges.empty(),
                 remove_isolated_items && !c.triangles.empty(), points, edges, faces);
    remove_isolated(faces, ElementType::triangle, edges, points);
}

void TopologyContainer::remove_hexahedra_process(const std::vector<ElementId>& indices, bool remove_isolated_items) {
    auto& cells = mesh_->hexahedra_;
    if (cells.empty()) return;
    MeshTopology::Cache& c = lists();
    std::vector<ElementId> faces, edges, points;
    remove_cells(cells, c.hexahedra_around_vertex, edges_in_hexahedron_, hexahedra_around_edge_, quads_in_hexahedron_,
                 hexahedra_around_quad_, indices, remove_isolated_items && options_.remove_isolated,
                 remove_isolated_items && !c.edges.empty(), remove_isolated_items && !c.quads.empty(), points, edges,
                 faces);
    remove_isolated(faces, ElementType::quad, edges, points);
}

void TopologyContainer::remove_triangles_process(const std::vector<ElementId>& indices, bool remove_isolated_edges,
                                                 bool remove_isolated_points) {
    MeshTopology::Cache& c = lists();
    if (c.triangles.empty()) return;
    if (level_ == ElementType::tetrahedron)
        rename_lower(triangles_in_tetrahedron_, tetrahedra_around_triangle_, indices);
    std::vector<ElementId> faces, edges, points;
    remove_faces(c.triangles, c.triangles_around_vertex, c.edges_in_triangle, c.triangles_around_edge, indices,
                 remove_isolated_edges && !c.edges.empty(), remove_isolated_points, edges, points);
    remove_isolated(faces, ElementType::triangle, edges, points);
}

void TopologyContainer::remove_quads_process(const std::vector<ElementId>& indices, bool remove_isolated_edges,
                                             bool remove_isolated_points) {
    MeshTopology::Cache& c = lists();
    if (c.quads.empty()) return;
    if (level_ == ElementType::hexahedron) rename_lower(quads_in_hexahedron_, hexahedra_around_quad_, indices);
    std::vector<ElementId> faces, edges, points;
    remove_faces(c.quads, c.quads_around_vertex, c.edges_in_quad, c.quads_around_edge, indices,
                 remove_isolated_edges && !c.edges.empty(), remove_isolated_points, edges, points);
    remove_isolated(faces, ElementType::quad, edges, points);
}

// The cells' and faces' tables first (SOFA's Tetrahedron/Hexahedron, then Triangle/Quad
// removeEdgesProcess), then EdgeSetTopologyModifier::removeEdgesProcess.
void TopologyContainer::remove_edges_process(const std::vector<ElementId>& indices, bool remove_isolated_points) {
    MeshTopology::Cache& c = lists();
    if (c.edges.empty()) return;
    if (level_ == ElementType::tetrahedron) rename_lower(edges_in_tetrahedron_, tetrahedra_around_edge_, indices);
    if (level_ == ElementType::hexahedron) rename_lower(edges_in_hexahedron_, hexahedra_around_edge_, indices);
    if (keeps(ElementType::triangle)) rename_lower(c.edges_in_triangle, c.triangles_around_edge, indices);
    if (keeps(ElementType::quad)) rename_lower(c.edges_in_quad, c.quads_around_edge, indices);

    std::vector<ElementId> points;
    auto last = ElementId(c.edges.size()) - 1;
    for (const ElementId i : indices) {
        const Edge removed = c.edges[std::size_t(i)];
        const Edge moved = c.edges[std::size_t(last)];
        leave_shells(c.edges_around_vertex, removed, i, remove_isolated_points, points);
        if (i < last) rename_in_shells(c.edges_around_vertex, moved, last, i);
        move_last_into(c.edges, i, last);
        touched_vertices_.insert(touched_vertices_.end(), removed.begin(), removed.end());
        --last;
    }
    if (!points.empty()) {
        remove_points_warning(points, true);
        propagate();
        remove_points_process(points, options_.propagate_to_dof);
    }
}

// The elements' vertices renamed, type by type from the highest (SOFA's
// removePointsProcess overrides), then PointSetTopologyModifier::removePointsProcess: the states
// follow (with `remove_dof`), the point count drops.
void TopologyContainer::remove_points_process(const std::vector<ElementId>& indices, bool remove_dof) {
    MeshTopology::Cache& c = lists();
    const std::size_t n = c.num_points;
    rename_vertices(mesh_->tetrahedra_, c.tetrahedra_around_vertex, indices, n, false);
    rename_vertices(mesh_->hexahedra_, c.hexahedra_around_vertex, indices, n, false);
    // (a level below triangles or quads has none: their shells, all empty, follow the count)
    if (keeps(ElementType::triangle) || c.triangles.empty())
        rename_vertices(c.triangles, c.triangles_around_vertex, indices, n, true);
    if (keeps(ElementType::quad) || c.quads.empty()) rename_vertices(c.quads, c.quads_around_vertex, indices, n, true);
    if (!c.edges.empty()) {
        // EdgeSetTopologyModifier::removePointsProcess: an edge's first end if it is the last point, else its second.
        auto last = ElementId(n) - 1;
        for (const ElementId i : indices) {
            for (const ElementId e : c.edges_around_vertex[std::size_t(last)]) {
                Edge& edge = c.edges[std::size_t(e)];
                (edge[0] == last ? edge[0] : edge[1]) = i;
                touched_vertices_.push_back(edge[0] == i ? edge[1] : edge[0]);
            }
            c.edges_around_vertex[std::size_t(i)] = c.edges_around_vertex[std::size_t(last)];
            touched_vertices_.push_back(i);
            --last;
        }
        c.edges_around_vertex.resize(c.edges_around_vertex.size() - indices.size());
    }
    if (remove_dof) propagate_state_changes();
    c.num_points -= indices.size();
    c.vertices_around_vertex.resize(c.num_points);
}

}  // namespace penalty
