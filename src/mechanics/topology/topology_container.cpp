// TopologyContainer: the cross tables, the event list and its propagation (SOFA's
// TopologyContainer / PointSetTopologyModifier::propagateTopologicalChanges,
// ...SetTopologyModifier::propagateTopologicalEngineChanges, TopologyChangeVisitor,
// StateChangeVisitor), and the public removals and additions (SOFA's remove...() / add...()).
#include "penalty/mechanics/topology_container.hpp"

#include "mechanics/topology/mesh_cache.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <functional>

namespace penalty {

const char* element_type_name(ElementType type) {
    switch (type) {
        case ElementType::point:
            return "points";
        case ElementType::edge:
            return "edges";
        case ElementType::triangle:
            return "triangles";
        case ElementType::quad:
            return "quads";
        case ElementType::tetrahedron:
            return "tetrahedra";
        case ElementType::hexahedron:
            return "hexahedra";
    }
    return "?";
}

namespace {

/// The order in which a modifier of class `level` runs its handlers: its own type, then the
/// types its class derives from (TetrahedronSetTopologyModifier → Triangle → Edge → Point;
/// Hexahedron → Quad → Edge → Point).
std::span<const ElementType> handler_phases(ElementType level) {
    using T = ElementType;
    static constexpr T kPoint[] = {T::point};
    static constexpr T kEdge[] = {T::edge, T::point};
    static constexpr T kTriangle[] = {T::triangle, T::edge, T::point};
    static constexpr T kQuad[] = {T::quad, T::edge, T::point};
    static constexpr T kTetrahedron[] = {T::tetrahedron, T::triangle, T::edge, T::point};
    static constexpr T kHexahedron[] = {T::hexahedron, T::quad, T::edge, T::point};
    switch (level) {
        case T::point:
            return kPoint;
        case T::edge:
            return kEdge;
        case T::triangle:
            return kTriangle;
        case T::quad:
            return kQuad;
        case T::tetrahedron:
            return kTetrahedron;
        case T::hexahedron:
            return kHexahedron;
    }
    return kPoint;
}

std::uint8_t bit(ElementType t) { return static_cast<std::uint8_t>(1u << static_cast<unsigned>(t)); }

}  // namespace

TopologyContainer::TopologyContainer(MeshTopology& mesh, ElementType level, std::string name,
                                     TopologyModifierOptions options)
    : mesh_(&mesh), level_(level), name_(std::move(name)), options_(options) {
    (void)lists();
    build_volume_tables();
}

TopologyContainer::~TopologyContainer() = default;

MeshTopology::Cache& TopologyContainer::lists() { return mesh_->editable_cache(); }

bool TopologyContainer::keeps(ElementType type) const {
    const auto phases = handler_phases(level_);
    return std::find(phases.begin(), phases.end(), type) != phases.end();
}

std::size_t TopologyContainer::num_points() const { return mesh_->num_points(); }

std::size_t TopologyContainer::count(ElementType type) const {
    switch (type) {
        case ElementType::point:
            return mesh_->num_points();
        case ElementType::edge:
            return mesh_->edges().size();
        case ElementType::triangle:
            return mesh_->triangles().size();
        case ElementType::quad:
            return mesh_->quads().size();
        case ElementType::tetrahedron:
            return mesh_->tetrahedra().size();
        case ElementType::hexahedron:
            return mesh_->hexahedra().size();
    }
    return 0;
}

std::span<const PointId> TopologyContainer::vertices(ElementType type, ElementId id) const {
    const auto i = static_cast<std::size_t>(id);
    switch (type) {
        case ElementType::point:
            return {};
        case ElementType::edge:
            return mesh_->edges()[i];
        case ElementType::triangle:
            return mesh_->triangles()[i];
        case ElementType::quad:
            return mesh_->quads()[i];
        case ElementType::tetrahedron:
            return mesh_->tetrahedra()[i];
        case ElementType::hexahedron:
            return mesh_->hexahedra()[i];
    }
    return {};
}

// SOFA's createEdgesInTetrahedronArray, createTrianglesInTetrahedronArray,
// createTetrahedraAroundEdgeArray, createTetrahedraAroundTriangleArray (and the hexahedron ones):
// element by element, in index order.
void TopologyContainer::build_volume_tables() {
    const auto& tetrahedra = mesh_->tetrahedra();
    edges_in_tetrahedron_.resize(tetrahedra.size());
    triangles_in_tetrahedron_.resize(tetrahedra.size());
    tetrahedra_around_edge_.assign(mesh_->edges().size(), {});
    tetrahedra_around_triangle_.assign(mesh_->triangles().size(), {});
    for (std::size_t i = 0; i < tetrahedra.size(); ++i) {
        const Tetrahedron& t = tetrahedra[i];
        for (std::size_t j = 0; j < 6; ++j) {
            const auto& le = MeshTopology::kTetraEdges[j];
            const ElementId e = edge_index(t[std::size_t(le[0])], t[std::size_t(le[1])]);
            if (e < 0) throw_invalid_argument("TopologyContainer '", name_, "': tetrahedron ", i, " has no edge ", j);
            edges_in_tetrahedron_[i][j] = e;
            tetrahedra_around_edge_[std::size_t(e)].push_back(ElementId(i));
        }
        for (std::size_t j = 0; j < 4; ++j) {
            const auto& f = MeshTopology::kTetraFaces[j];
            const ElementId tri = triangle_index(t[std::size_t(f[0])], t[std::size_t(f[1])], t[std::size_t(f[2])]);
            if (tri < 0) throw_invalid_argument("TopologyContainer '", name_, "': tetrahedron ", i, " has no face ", j);
            triangles_in_tetrahedron_[i][j] = tri;
            tetrahedra_around_triangle_[std::size_t(tri)].push_back(ElementId(i));
        }
    }
    const auto& hexahedra = mesh_->hexahedra();
    edges_in_hexahedron_.resize(hexahedra.size());
    quads_in_hexahedron_.resize(hexahedra.size());
    hexahedra_around_edge_.assign(mesh_->edges().size(), {});
    hexahedra_around_quad_.assign(mesh_->quads().size(), {});
    for (std::size_t i = 0; i < hexahedra.size(); ++i) {
        const Hexahedron& h = hexahedra[i];
        for (std::size_t j = 0; j < 12; ++j) {
            const auto& le = MeshTopology::kHexaEdges[j];
            const ElementId e = edge_index(h[std::size_t(le[0])], h[std::size_t(le[1])]);
            if (e < 0) throw_invalid_argument("TopologyContainer '", name_, "': hexahedron ", i, " has no edge ", j);
            edges_in_hexahedron_[i][j] = e;
            hexahedra_around_edge_[std::size_t(e)].push_back(ElementId(i));
        }
        for (std::size_t j = 0; j < 6; ++j) {
            const auto& f = MeshTopology::kHexaFaces[j];
            const ElementId q =
                quad_index(h[std::size_t(f[0])], h[std::size_t(f[1])], h[std::size_t(f[2])], h[std::size_t(f[3])]);
            if (q < 0) throw_invalid_argument("TopologyContainer '", name_, "': hexahedron ", i, " has no face ", j);
            quads_in_hexahedron_[i][j] = q;
            hexahedra_around_quad_[std::size_t(q)].push_back(ElementId(i));
        }
    }
}

ElementId TopologyContainer::edge_index(PointId a, PointId b) const { return mesh_->edge_index(a, b); }

ElementId TopologyContainer::triangle_index(PointId a, PointId b, PointId c) const {
    const auto& around = mesh_->triangles_around_vertex();
    if (a < 0 || std::size_t(a) >= around.size()) return -1;
    ElementId found = -1;
    for (const ElementId t : around[std::size_t(a)]) {
        const Triangle& tri = mesh_->triangles()[std::size_t(t)];
        if (std::find(tri.begin(), tri.end(), b) == tri.end() || std::find(tri.begin(), tri.end(), c) == tri.end())
            continue;
        if (found >= 0) return -1;  // SOFA: only a single match counts
        found = t;
    }
    return found;
}

ElementId TopologyContainer::quad_index(PointId a, PointId b, PointId c, PointId d) const {
    const auto& around = mesh_->quads_around_vertex();
    if (a < 0 || std::size_t(a) >= around.size()) return -1;
    ElementId found = -1;
    for (const ElementId q : around[std::size_t(a)]) {
        const Quad& quad = mesh_->quads()[std::size_t(q)];
        const auto has = [&](PointId v) { return std::find(quad.begin(), quad.end(), v) != quad.end(); };
        if (!has(b) || !has(c) || !has(d)) continue;
        if (found >= 0) return -1;
        found = q;
    }
    return found;
}

// ---- registration ---------------------------------------------------------------------------

void TopologyContainer::add_handler(TopologyHandler& handler, std::initializer_list<ElementType> types) {
    auto it =
        std::find_if(handlers_.begin(), handlers_.end(), [&](const Registered& r) { return r.handler == &handler; });
    if (it == handlers_.end()) {
        handlers_.push_back({&handler, 0, false});
        it = handlers_.end() - 1;
    }
    for (const ElementType t : types) it->types = static_cast<std::uint8_t>(it->types | bit(t));
}

void TopologyContainer::add_listener(TopologyHandler& listener) {
    if (std::find(listeners_.begin(), listeners_.end(), &listener) == listeners_.end()) listeners_.push_back(&listener);
}

void TopologyContainer::add_state_follower(StateFollower& follower) {
    if (std::find(state_followers_.begin(), state_followers_.end(), &follower) == state_followers_.end())
        state_followers_.push_back(&follower);
}

void TopologyContainer::remove(const TopologyHandler& object) {
    std::erase_if(handlers_, [&](const Registered& r) { return r.handler == &object; });
    std::erase(listeners_, &object);
}

void TopologyContainer::remove(const StateFollower& object) { std::erase(state_followers_, &object); }

// ---- events -----------------------------------------------------------------------------------

// SOFA's set...TopologyToDirty: the type and every handler registered on it.
void TopologyContainer::set_dirty(ElementType type) {
    dirty_[std::size_t(type)] = true;
    for (Registered& r : handlers_)
        if (r.types & bit(type)) r.dirty = true;
}

void TopologyContainer::add_change(TopologyChange change) { changes_.push_back(std::move(change)); }

// PointSetTopologyModifier::propagateTopologicalChanges: nothing without events; else an ending
// event, the handlers of each dirty type (propagateTopologicalEngineChanges, highest type first),
// the listeners (TopologyChangeVisitor), and the list is cleared. A handler runs at most once (its
// first dirty type); the lists are moved out first, so that a listener may propagate changes of
// its own (a topological mapping's output) and this container's again.
void TopologyContainer::propagate() {
    if (changes_.empty()) return;
    add_change(TopologyChange{});
    std::vector<TopologyChange> changes;
    changes.swap(changes_);
    for (const ElementType phase : handler_phases(level_)) {
        if (!dirty_[std::size_t(phase)]) continue;
        for (std::size_t k = 0; k < handlers_.size(); ++k) {
            if (!(handlers_[k].types & bit(phase)) || !handlers_[k].dirty) continue;
            handlers_[k].dirty = false;
            handlers_[k].handler->handle_topology_changes(changes);
            pending(handlers_[k].handler);
        }
        dirty_[std::size_t(phase)] = false;
    }
    for (std::size_t k = 0; k < listeners_.size(); ++k) {
        listeners_[k]->handle_topology_changes(changes);
        pending(listeners_[k]);
    }
    changed();
}

// PointSetTopologyModifier::propagateStateChanges (StateChangeVisitor): every follower, each event.
void TopologyContainer::propagate_state_changes() {
    std::vector<TopologyChange> changes;
    changes.swap(state_changes_);
    for (const TopologyChange& c : changes)
        for (StateFollower* f : state_followers_) f->handle_state_change(c);
}

void TopologyContainer::changed() {
    ++mesh_->revision_;
    if (touched_vertices_.empty()) return;
    MeshTopology::Cache& c = lists();
    c.vertices_around_vertex.resize(c.num_points);
    std::sort(touched_vertices_.begin(), touched_vertices_.end());
    touched_vertices_.erase(std::unique(touched_vertices_.begin(), touched_vertices_.end()), touched_vertices_.end());
    for (const PointId v : touched_vertices_)
        if (std::size_t(v) < c.num_points) refresh_vertices_around(c, std::size_t(v));
    touched_vertices_.clear();
}

void TopologyContainer::begin() { ++scope_->depth; }

void TopologyContainer::pending(TopologyHandler* h) {
    auto& p = scope_->pending;
    if (std::find(p.begin(), p.end(), h) == p.end()) p.push_back(h);
}

void TopologyContainer::done() {
    changed();
    if (--scope_->depth > 0) return;
    const std::shared_ptr<TopologyChangeScope> scope = scope_;  // a handler may not outlive it here
    for (std::size_t k = 0; k < scope->pending.size(); ++k) scope->pending[k]->topology_change_done();
    scope->pending.clear();
}

// ...SetTopologyModifier::remove...Warning: the type dirty, the indices sorted in decreasing
// order (the caller's list too, as SOFA's), the event joins the list.
void TopologyContainer::remove_warning(ElementType type, std::vector<ElementId>& indices) {
    set_dirty(type);
    std::sort(indices.begin(), indices.end(), std::greater<>());
    TopologyChange c;
    c.kind = TopologyChangeKind::removed;
    c.element = type;
    c.indices = indices;
    add_change(std::move(c));
}

// PointSetTopologyModifier::removePointsWarning: as remove_warning, and the same event for the
// states when `remove_dof` (sent by removePointsProcess).
void TopologyContainer::remove_points_warning(std::vector<ElementId>& indices, bool remove_dof) {
    remove_warning(ElementType::point, indices);
    if (remove_dof) state_changes_.push_back(changes_.back());
}

// PointSetTopologyModifier::addPointsWarning: the new points are the last `count`; the states
// grow first (with `add_dof`), then the event joins the list.
void TopologyContainer::add_points_warning(std::size_t count, const std::vector<std::vector<ElementId>>& ancestors,
                                           const std::vector<std::vector<double>>& coefficients, bool add_dof,
                                           const std::vector<PointAncestorElement>& elements) {
    set_dirty(ElementType::point);
    TopologyChange c;
    c.kind = TopologyChangeKind::added;
    c.element = ElementType::point;
    const std::size_t first = num_points() - count;
    for (std::size_t i = 0; i < count; ++i) c.indices.push_back(ElementId(first + i));
    c.ancestors = ancestors;
    c.coefficients = coefficients;
    c.ancestor_elements = elements;
    if (add_dof) {
        state_changes_.push_back(c);
        propagate_state_changes();
    }
    add_change(std::move(c));
}

template <class Element>
void TopologyContainer::add_warning(ElementType type, const std::vector<Element>& elements, ElementId first,
                                    const std::vector<std::vector<ElementId>>& ancestors,
                                    const std::vector<std::vector<double>>& coefficients) {
    set_dirty(type);
    TopologyChange c;
    c.kind = TopologyChangeKind::added;
    c.element = type;
    for (std::size_t i = 0; i < elements.size(); ++i) {
        c.indices.push_back(ElementId(first + ElementId(i)));
        c.vertices.insert(c.vertices.end(), elements[i].begin(), elements[i].end());
    }
    c.ancestors = ancestors;
    c.coefficients = coefficients;
    add_change(std::move(c));
}
template void TopologyContainer::add_warning(ElementType, const std::vector<Edge>&, ElementId,
                                             const std::vector<std::vector<ElementId>>&,
                                             const std::vector<std::vector<double>>&);
template void TopologyContainer::add_warning(ElementType, const std::vector<Triangle>&, ElementId,
                                             const std::vector<std::vector<ElementId>>&,
                                             const std::vector<std::vector<double>>&);
template void TopologyContainer::add_warning(ElementType, const std::vector<Quad>&, ElementId,
                                             const std::vector<std::vector<ElementId>>&,
                                             const std::vector<std::vector<double>>&);
template void TopologyContainer::add_warning(ElementType, const std::vector<Hexahedron>&, ElementId,
                                             const std::vector<std::vector<ElementId>>&,
                                             const std::vector<std::vector<double>>&);

void TopologyContainer::notify_ending_event() {
    begin();
    add_change(TopologyChange{});
    propagate();
    done();
}

// ---- public removals (SOFA's remove...()) ---------------------------------------------------

void TopologyContainer::check_removal(ElementType type, std::span<const ElementId> indices) const {
    if (!keeps(type))
        throw_invalid_argument("TopologyContainer '", name_, "': a ", element_type_name(level_), " container has no ",
                               element_type_name(type));
    const std::size_t n = count(type);
    std::vector<char> seen(n, 0);
    for (std::size_t k = 0; k < indices.size(); ++k) {
        const ElementId i = indices[k];
        if (i < 0 || std::size_t(i) >= n)
            throw_invalid_argument("TopologyContainer '", name_, "': cannot remove ", element_type_name(type), " ", i,
                                   " (entry ", k, "): out of range, the container has ", n, " ",
                                   element_type_name(type));
        if (seen[std::size_t(i)])
            throw_invalid_argument("TopologyContainer '", name_, "': ", element_type_name(type), " ", i,
                                   " is listed twice (entry ", k, ") in one removal");
        seen[std::size_t(i)] = 1;
    }
}

void TopologyContainer::remove_items(std::vector<ElementId> indices) {
    switch (level_) {
        case ElementType::point:
            return remove_points(std::move(indices));
        case ElementType::edge:
            return remove_edges(std::move(indices));
        case ElementType::triangle:
            return remove_triangles(std::move(indices));
        case ElementType::quad:
            return remove_quads(std::move(indices));
        case ElementType::tetrahedron:
            return remove_tetrahedra(std::move(indices));
        case ElementType::hexahedron:
            return remove_hexahedra(std::move(indices));
    }
}

// PointSetTopologyModifier::removePoints: warning, propagation, process.
void TopologyContainer::remove_points(std::vector<ElementId> indices, bool remove_dof) {
    check_removal(ElementType::point, indices);
    begin();
    remove_points_warning(indices, remove_dof);
    propagate();
    remove_points_process(indices, remove_dof);
    done();
}

void TopologyContainer::remove_edges(std::vector<ElementId> indices, bool remove_isolated_points) {
    check_removal(ElementType::edge, indices);
    begin();
    remove_warning(ElementType::edge, indices);
    propagate();
    remove_edges_process(indices, remove_isolated_points);
    done();
}

void TopologyContainer::remove_triangles(std::vector<ElementId> indices, bool remove_isolated_edges,
                                         bool remove_isolated_points) {
    check_removal(ElementType::triangle, indices);
    begin();
    remove_warning(ElementType::triangle, indices);
    propagate();
    remove_triangles_process(indices, remove_isolated_edges, remove_isolated_points);
    done();
}

void TopologyContainer::remove_quads(std::vector<ElementId> indices, bool remove_isolated_edges,
                                     bool remove_isolated_points) {
    check_removal(ElementType::quad, indices);
    begin();
    remove_warning(ElementType::quad, indices);
    propagate();
    remove_quads_process(indices, remove_isolated_edges, remove_isolated_points);
    done();
}

void TopologyContainer::remove_tetrahedra(std::vector<ElementId> indices, bool remove_isolated_items) {
    check_removal(ElementType::tetrahedron, indices);
    begin();
    remove_warning(ElementType::tetrahedron, indices);
    propagate();
    remove_tetrahedra_process(indices, remove_isolated_items);
    done();
}

void TopologyContainer::remove_hexahedra(std::vector<ElementId> indices) {
    check_removal(ElementType::hexahedron, indices);
    begin();
    remove_warning(ElementType::hexahedron, indices);
    propagate();
    remove_hexahedra_process(indices, true);
    done();
}

// ...Process of the removed elements' isolated faces, edges and points (the end of SOFA's
// removeTetrahedraProcess / removeHexahedraProcess / removeTrianglesProcess / removeQuadsProcess).
void TopologyContainer::remove_isolated(std::vector<ElementId>& faces, ElementType face_type,
                                        std::vector<ElementId>& edges, std::vector<ElementId>& points) {
    if (!faces.empty() || !edges.empty()) {
        if (!faces.empty()) remove_warning(face_type, faces);
        if (!edges.empty()) remove_warning(ElementType::edge, edges);
        propagate();
        if (!faces.empty()) {
            if (face_type == ElementType::triangle) remove_triangles_process(faces, false, false);
            else remove_quads_process(faces, false, false);
        }
        if (!edges.empty()) remove_edges_process(edges, false);
    }
    if (!points.empty()) {
        remove_points_warning(points, true);
        propagate();
        remove_points_process(points, options_.propagate_to_dof);
    }
}

}  // namespace penalty
