// The generic followers of topology_followers.hpp and SOFA's TriangularBendingSprings edge data.
#include "penalty/mechanics/topology_followers.hpp"

#include "penalty/core/error.hpp"
#include "penalty/mechanics/topology_data.hpp"

#include <algorithm>
#include <span>
#include <vector>

namespace penalty {

namespace {
std::uint8_t type_bit(ElementType t) { return static_cast<std::uint8_t>(1u << static_cast<unsigned>(t)); }

/// SOFA's walk of applyPointDestruction (before the points go): for each removed point in order,
/// the last point takes its index; visit(around, last, taken) runs with `last` that point's index
/// now, `taken` the index it takes, and `around` the point whose neighbourhood in the mesh (not
/// yet renumbered) still names it.
template <class Visit>
void walk_point_destruction(std::size_t num_points, std::span<const ElementId> removed, Visit&& visit) {
    auto last = ElementId(num_points) - 1;
    std::vector<ElementId> last_index(removed.size());
    for (std::size_t k = 0; k < removed.size(); ++k) last_index[k] = last - ElementId(k);
    for (std::size_t i = 0; i < removed.size(); ++i) {
        std::size_t next = i;
        bool reached = false;
        while (!reached && next + 1 < last_index.size()) {
            ++next;
            reached = last_index[next] == removed[i];
        }
        if (reached) last_index[next] = last_index[i];
        visit(last_index[i], last, removed[i]);
        --last;
    }
}
}  // namespace

// ---- RebuildFollower ------------------------------------------------------------------------

RebuildFollower::RebuildFollower(std::function<void()> rebuild, std::initializer_list<ElementType> types)
    : rebuild_(std::move(rebuild)) {
    for (const ElementType t : types) types_ = static_cast<std::uint8_t>(types_ | type_bit(t));
}

void RebuildFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes)
        if (c.kind != TopologyChangeKind::ending && (types_ & type_bit(c.element))) dirty_ = true;
}

void RebuildFollower::topology_change_done() {
    if (!dirty_) return;
    dirty_ = false;
    rebuild_();
}

// ---- SubsetIndicesFollower --------------------------------------------------------------------

void SubsetIndicesFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.element != ElementType::point) continue;
        if (c.kind == TopologyChangeKind::removed) {
            std::vector<Index> indices = get_();
            subset_indices_remove(indices, c.indices, container_->num_points());
            set_(std::move(indices));
        } else if (c.kind == TopologyChangeKind::renumbered) {
            std::vector<Index> indices = get_();
            subset_indices_renumber(indices, c.indices);
            set_(std::move(indices));
        }
    }
}

// ---- SpringPointsFollower -----------------------------------------------------------------------

SpringPointsFollower::SpringPointsFollower(SpringForceField& springs, const TopologyContainer& container)
    : SpringPointsFollower(std::make_shared<SpringListEdit>(SpringListEdit{&springs, {}, false}), container,
                           Ends::both) {}

SpringPointsFollower::SpringPointsFollower(std::shared_ptr<SpringListEdit> edit, const TopologyContainer& container,
                                           Ends ends)
    : edit_(std::move(edit)), container_(&container), ends_(ends) {}

void SpringPointsFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    std::vector<Spring>& list = edit_->list;
    if (!edit_->dirty) list = edit_->springs->springs();
    const MeshTopology& mesh = container_->mesh();
    std::vector<bool> ends;  // false: the first ends (d_springsIndices[0]'s handler), true: the second
    if ((std::uint8_t(ends_) & std::uint8_t(Ends::first)) != 0) ends.push_back(false);
    if ((std::uint8_t(ends_) & std::uint8_t(Ends::second)) != 0) ends.push_back(true);
    for (const TopologyChange& c : changes) {
        if (c.is(TopologyChangeKind::removed, ElementType::point)) {
            // applyRemovedPoints
            for (const bool second : ends) {
                const auto end = [second](Spring& s) -> Index& { return second ? s.b : s.a; };
                Index points = Index(container_->num_points());  // the count before the removal
                for (const ElementId removed : c.indices) {
                    --points;
                    std::erase_if(list, [&](Spring& s) { return end(s) == Index(removed); });
                    if (Index(removed) == points) continue;
                    for (Spring& s : list)
                        if (end(s) == points) end(s) = Index(removed);
                }
            }
            edit_->dirty = true;
        } else if (c.is(TopologyChangeKind::removed, ElementType::edge) && container_->level() == ElementType::edge) {
            // applyRemovedEdges: the first spring along each removed edge, per end
            for (const bool second : ends) {
                std::vector<std::size_t> doomed;
                for (const ElementId e : c.indices) {
                    const Edge& edge = mesh.edges()[std::size_t(e)];
                    for (std::size_t k = 0; k < list.size(); ++k) {
                        const Index first = second ? list[k].b : list[k].a;
                        const Index other = second ? list[k].a : list[k].b;
                        if (first == Index(edge[0]) && other == Index(edge[1])) {
                            doomed.push_back(k);
                            break;
                        }
                    }
                }
                std::sort(doomed.begin(), doomed.end());
                for (auto it = doomed.rbegin(); it != doomed.rend(); ++it)
                    list.erase(list.begin() + std::ptrdiff_t(*it));
            }
            edit_->dirty = true;
        }
    }
}

void SpringPointsFollower::topology_change_done() {
    if (!edit_->dirty) return;
    edit_->dirty = false;
    SpringForceField& springs = *edit_->springs;
    springs.clear_springs();
    for (const Spring& s : edit_->list) springs.add_spring(s);
    springs.init();
}

// ---- TriangularBendingSpringsFollower -----------------------------------------------------------

TriangularBendingSpringsFollower::TriangularBendingSpringsFollower(SpringForceField& springs,
                                                                   const TopologyContainer& container,
                                                                   const Vec3Object& state, double ks, double kd)
    : springs_(&springs), container_(&container), state_(&state), ks_(ks), kd_(kd) {
    // TriangularBendingSprings::reinit: applyEdgeCreation of every edge, then applyTriangleCreation
    // of every triangle in index order.
    edges_.assign(container.count(ElementType::edge), EdgeInformation{});
    std::vector<ElementId> all(container.count(ElementType::triangle));
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = ElementId(i);
    triangles_added(all);
}

void TriangularBendingSpringsFollower::make_spring(EdgeInformation& ei, ElementId edge, ElementId t1,
                                                   ElementId t2) const {
    const MeshTopology& m = container_->mesh();
    const auto index_in = [&](ElementId t) {
        const auto& te = m.edges_in_triangle()[std::size_t(t)];
        return std::size_t(std::find(te.begin(), te.end(), edge) - te.begin());
    };
    ei.m1 = m.triangles()[std::size_t(t1)][index_in(t1)];
    ei.m2 = m.triangles()[std::size_t(t2)][index_in(t2)];
    ei.ks = ks_;
    ei.kd = kd_;
    const auto& x0 = state_->rest_position;
    ei.rest_length = (x0[std::size_t(ei.m1)] - x0[std::size_t(ei.m2)]).norm();
    ei.activated = true;
}

// applyTriangleCreation: an edge met for the first time gets its spring if two triangles share it
// (the other one gives m1, the new one m2); an initialised edge is left as it is.
void TriangularBendingSpringsFollower::triangles_added(std::span<const ElementId> added) {
    const MeshTopology& m = container_->mesh();
    for (const ElementId t : added) {
        for (const std::int32_t e : m.edges_in_triangle()[std::size_t(t)]) {
            EdgeInformation& ei = edges_[std::size_t(e)];
            if (ei.initialized) continue;
            ei.initialized = true;
            const auto& shell = m.triangles_around_edge()[std::size_t(e)];
            if (shell.size() != 2) {
                ei.activated = false;
                continue;
            }
            make_spring(ei, e, shell[0] == t ? shell[1] : shell[0], t);
        }
    }
}

// applyTriangleDestruction (before the triangles go): an edge with three triangles keeps a spring
// between the two others; any other loses its spring.
void TriangularBendingSpringsFollower::triangles_removed(std::span<const ElementId> removed) {
    const MeshTopology& m = container_->mesh();
    for (const ElementId r : removed) {
        for (const std::int32_t e : m.edges_in_triangle()[std::size_t(r)]) {
            EdgeInformation& ei = edges_[std::size_t(e)];
            if (!ei.initialized) {
                ei.activated = ei.initialized = false;
                continue;
            }
            const auto& shell = m.triangles_around_edge()[std::size_t(e)];
            if (shell.size() == 3) {
                const std::size_t at = shell[0] == r ? 0 : shell[1] == r ? 1 : 2;
                make_spring(ei, e, shell[(at + 1) % 3], shell[(at + 2) % 3]);
            } else {
                ei.activated = ei.initialized = false;
            }
        }
    }
}

// applyPointDestruction (before the points go): for the triangles around each point that will take
// a removed one's index, the spring of the edge opposite it names the new index.
void TriangularBendingSpringsFollower::points_removed(std::span<const ElementId> removed) {
    const MeshTopology& m = container_->mesh();
    walk_point_destruction(container_->num_points(), removed, [&](ElementId around, ElementId last, ElementId taken) {
        for (const std::int32_t t : m.triangles_around_vertex()[std::size_t(around)]) {
            const Triangle& tri = m.triangles()[std::size_t(t)];
            const auto j = std::size_t(std::find(tri.begin(), tri.end(), around) - tri.begin());
            EdgeInformation& ei = edges_[std::size_t(m.edges_in_triangle()[std::size_t(t)][j])];
            if (ei.m1 == last) ei.m1 = taken;
            else if (ei.m2 == last) ei.m2 = taken;
        }
    });
}

void TriangularBendingSpringsFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.kind == TopologyChangeKind::ending) continue;
        dirty_ = true;
        if (c.is(TopologyChangeKind::added, ElementType::triangle)) triangles_added(c.indices);
        else if (c.is(TopologyChangeKind::removed, ElementType::triangle)) triangles_removed(c.indices);
        else if (c.is(TopologyChangeKind::removed, ElementType::point)) points_removed(c.indices);
        else if (c.is(TopologyChangeKind::renumbered, ElementType::point)) {
            for (EdgeInformation& ei : edges_) {
                if (!ei.activated) continue;
                ei.m1 = c.indices[std::size_t(ei.m1)];
                ei.m2 = c.indices[std::size_t(ei.m2)];
            }
        } else if (c.is(TopologyChangeKind::added, ElementType::edge)) {
            edges_.resize(edges_.size() + c.indices.size(), EdgeInformation{});
        } else if (c.is(TopologyChangeKind::removed, ElementType::edge)) {
            topology_data_remove(edges_, c.indices);
        }
    }
}

std::vector<Spring> TriangularBendingSpringsFollower::springs() const {
    std::vector<Spring> out;
    for (const EdgeInformation& ei : edges_)
        if (ei.activated)
            out.push_back({.a = ei.m1, .b = ei.m2, .ks = ei.ks, .kd = ei.kd, .rest_length = ei.rest_length});
    return out;
}

void TriangularBendingSpringsFollower::topology_change_done() {
    if (!dirty_) return;
    dirty_ = false;
    springs_->clear_springs();
    for (const Spring& s : springs()) springs_->add_spring(s);
    springs_->init();
}

// ---- QuadularBendingSpringsFollower -------------------------------------------------------------

QuadularBendingSpringsFollower::QuadularBendingSpringsFollower(SpringForceField& springs,
                                                               const TopologyContainer& container,
                                                               const Vec3Object& state, double ks, double kd)
    : springs_(&springs), container_(&container), state_(&state), ks_(ks), kd_(kd) {
    edges_.assign(container.count(ElementType::edge), EdgeInformation{});
    std::vector<ElementId> all(container.count(ElementType::quad));
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = ElementId(i);
    quads_added(all);
}

// springs (t1[i1], t2[i2+3]) and (t1[i1+3], t2[i2]) across the edge, i the edge's place in each quad
void QuadularBendingSpringsFollower::make_springs(EdgeInformation& ei, ElementId edge, ElementId q1,
                                                  ElementId q2) const {
    const MeshTopology& m = container_->mesh();
    const auto index_in = [&](ElementId q) {
        const auto& qe = m.edges_in_quad()[std::size_t(q)];
        return std::size_t(std::find(qe.begin(), qe.end(), edge) - qe.begin());
    };
    const Quad& t1 = m.quads()[std::size_t(q1)];
    const Quad& t2 = m.quads()[std::size_t(q2)];
    const std::size_t i1 = index_in(q1), i2 = index_in(q2);
    ei.springs[0] = {t1[i1], t2[(i2 + 3) % 4]};
    ei.springs[1] = {t1[(i1 + 3) % 4], t2[i2]};
    ei.ks = ks_;
    ei.kd = kd_;
    const auto& x0 = state_->rest_position;
    for (std::size_t s = 0; s < 2; ++s)
        ei.rest_length[s] = (x0[std::size_t(ei.springs[s][0])] - x0[std::size_t(ei.springs[s][1])]).norm();
    ei.activated = true;
}

// applyQuadCreation: an edge met for the first time gets its springs if two quads share it.
void QuadularBendingSpringsFollower::quads_added(std::span<const ElementId> added) {
    const MeshTopology& m = container_->mesh();
    for (const ElementId q : added) {
        for (const std::int32_t e : m.edges_in_quad()[std::size_t(q)]) {
            EdgeInformation& ei = edges_[std::size_t(e)];
            if (ei.initialized) continue;
            const auto& shell = m.quads_around_edge()[std::size_t(e)];
            if (shell.size() == 2) make_springs(ei, e, shell[0] == q ? shell[1] : shell[0], q);
            else ei.activated = false;
            ei.initialized = true;
        }
    }
}

// applyQuadDestruction (before the quads go).
void QuadularBendingSpringsFollower::quads_removed(std::span<const ElementId> removed) {
    const MeshTopology& m = container_->mesh();
    for (const ElementId r : removed) {
        for (const std::int32_t e : m.edges_in_quad()[std::size_t(r)]) {
            EdgeInformation& ei = edges_[std::size_t(e)];
            const auto& shell = m.quads_around_edge()[std::size_t(e)];
            if (ei.initialized && shell.size() == 3) {
                const std::size_t at = shell[0] == r ? 0 : shell[1] == r ? 1 : 2;
                make_springs(ei, e, shell[(at + 1) % 3], shell[(at + 2) % 3]);
            } else {
                ei.activated = ei.initialized = false;
            }
        }
    }
}

// applyPointDestruction: the springs of the two edges of each quad around the point that will take
// a removed one's index, away from it, name the new index.
void QuadularBendingSpringsFollower::points_removed(std::span<const ElementId> removed) {
    const MeshTopology& m = container_->mesh();
    walk_point_destruction(container_->num_points(), removed, [&](ElementId around, ElementId last, ElementId taken) {
        for (const std::int32_t q : m.quads_around_vertex()[std::size_t(around)]) {
            const Quad& quad = m.quads()[std::size_t(q)];
            const auto v = std::size_t(std::find(quad.begin(), quad.end(), around) - quad.begin());
            for (std::size_t j = v; j % 4 != (v + 2) % 4; ++j)
                for (auto& spring : edges_[std::size_t(m.edges_in_quad()[std::size_t(q)][j % 4])].springs)
                    for (auto& end : spring)
                        if (end == last) end = taken;
        }
    });
}

void QuadularBendingSpringsFollower::handle_topology_changes(std::span<const TopologyChange> changes) {
    for (const TopologyChange& c : changes) {
        if (c.kind == TopologyChangeKind::ending) continue;
        dirty_ = true;
        if (c.is(TopologyChangeKind::added, ElementType::quad)) quads_added(c.indices);
        else if (c.is(TopologyChangeKind::removed, ElementType::quad)) quads_removed(c.indices);
        else if (c.is(TopologyChangeKind::removed, ElementType::point)) points_removed(c.indices);
        else if (c.is(TopologyChangeKind::renumbered, ElementType::point)) {
            for (EdgeInformation& ei : edges_)
                if (ei.activated)
                    for (auto& spring : ei.springs)
                        for (auto& end : spring) end = c.indices[std::size_t(end)];
        } else if (c.is(TopologyChangeKind::added, ElementType::edge)) {
            edges_.resize(edges_.size() + c.indices.size(), EdgeInformation{});
        } else if (c.is(TopologyChangeKind::removed, ElementType::edge)) {
            topology_data_remove(edges_, c.indices);
        }
    }
}

std::vector<Spring> QuadularBendingSpringsFollower::springs() const {
    std::vector<Spring> out;
    for (const EdgeInformation& ei : edges_)
        if (ei.activated)
            for (std::size_t s = 0; s < 2; ++s)
                out.push_back({.a = ei.springs[s][0],
                               .b = ei.springs[s][1],
                               .ks = ei.ks,
                               .kd = ei.kd,
                               .rest_length = ei.rest_length[s]});
    return out;
}

void QuadularBendingSpringsFollower::topology_change_done() {
    if (!dirty_) return;
    dirty_ = false;
    springs_->clear_springs();
    for (const Spring& s : springs()) springs_->add_spring(s);
    springs_->init();
}

}  // namespace penalty
