// TopologyRuntime: the scene's dynamic topologies and their change sources (topology_runtime.hpp).
#include "scene/topology/topology_runtime.hpp"

#include "penalty/core/error.hpp"
#include "penalty/simulation/node.hpp"

#include <algorithm>
#include <cmath>

namespace penalty::scene {

TopologyRuntime::~TopologyRuntime() {
    // the handlers refer to the containers: unregister before either goes
    for (auto& t : topologies) {
        for (auto& h : handlers) t->container->remove(*h);
        for (auto& f : followers) t->container->remove(*f);
    }
}

std::uint64_t TopologyRuntime::revisions() const {
    std::uint64_t sum = 0;
    for (const auto& t : topologies) sum += t->container->mesh().revision();
    return sum;
}

void TopologyRuntime::begin_step(double time) {
    if (!sources.empty()) {
        const std::uint64_t before = revisions();
        for (auto& s : sources) s->begin_step(time);
        if (revisions() != before) changed();
    }
    for (const auto& update : internal_updates) update();
}

void TopologyRuntime::end_step(double time) {
    if (sources.empty()) return;
    const std::uint64_t before = revisions();
    for (auto& s : sources) s->end_step(time);
    if (revisions() != before) changed();
}

void TopologyRuntime::changed() {
    if (root != nullptr) root->mark_structure_changed();
}

DynamicTopology* TopologyRuntime::find(const MeshTopology* mesh) const {
    for (const auto& t : topologies)
        if (&t->container->mesh() == mesh) return t.get();
    return nullptr;
}

DynamicTopology* TopologyRuntime::find(std::string_view name) const {
    for (const auto& t : topologies)
        if (t->path == name) return t.get();
    DynamicTopology* found = nullptr;
    for (const auto& t : topologies) {
        const std::string& own = t->component->name;
        const std::string node = t->path.substr(0, t->path.rfind('/'));
        if (own == name || node == name || (node.empty() && name == "/")) {
            if (found != nullptr)
                throw_invalid_argument("topology '", name, "' is ambiguous: '", found->path, "' and '", t->path,
                                       "' (give the path)");
            found = t.get();
        }
    }
    return found;
}

void TopologyRuntime::check_can_change(const DynamicTopology& t) const {
    if (!t.blockers.empty())
        throw_invalid_argument("topology '", t.path, "' cannot change: ", t.blockers.front(),
                               " does not follow topological changes");
    for (const DynamicTopology* out : t.outputs) check_can_change(*out);
}

void TopologyRuntime::check_keeps_elements(const DynamicTopology& t, ElementType type, std::size_t remaining) {
    const ElementType level = t.container->level();
    if (t.needs_elements.empty() || type != level || remaining > 0) return;
    throw_invalid_argument("topology '", t.path, "': the removal leaves no ", element_type_name(level), ", and ",
                           t.needs_elements.front(), " maps its points onto them (refused; nothing changed)");
}

}  // namespace penalty::scene

namespace penalty::scene {

void TopologyRuntime::check_added(const DynamicTopology& t, ElementType type, std::span<const PointId> flat) {
    if (t.geometry == nullptr || (type != ElementType::tetrahedron && type != ElementType::triangle)) return;
    const std::vector<Vec3>& x = t.geometry->rest_position.size() == t.geometry->position.size()
                                     ? t.geometry->rest_position
                                     : t.geometry->position;
    const std::size_t per = std::size_t(vertices_per_element(type));
    for (std::size_t e = 0; e + per <= flat.size(); e += per) {
        bool known = true;
        for (std::size_t k = 0; k < per; ++k) known = known && flat[e + k] >= 0 && std::size_t(flat[e + k]) < x.size();
        if (!known) continue;
        const Vec3& a = x[std::size_t(flat[e])];
        const Vec3 u = x[std::size_t(flat[e + 1])] - a, v = x[std::size_t(flat[e + 2])] - a;
        if (type == ElementType::tetrahedron) {
            // TetrahedronFEMForceField's test (fem.cpp compute_stiffness)
            const Vec3 w = x[std::size_t(flat[e + 3])] - a;
            const double det = u.cross(v).dot(w);
            const double scale = std::max({u.norm(), v.norm(), w.norm()});
            if (!std::isfinite(det) || std::abs(det) <= 1e-12 * scale * scale * scale)
                throw_invalid_argument("the topology '", t.path, "': new tetrahedron ", e / per, " (", flat[e], " ",
                                       flat[e + 1], " ", flat[e + 2], " ", flat[e + 3], ") is degenerate (volume ",
                                       det / 6, ")");
        } else {
            const double area = 0.5 * u.cross(v).norm();
            const double scale = std::max(u.norm(), v.norm());
            if (!std::isfinite(area) || area <= 1e-12 * scale * scale)
                throw_invalid_argument("the topology '", t.path, "': new triangle ", e / per, " (", flat[e], " ",
                                       flat[e + 1], " ", flat[e + 2], ") is degenerate (area ", area, ")");
        }
    }
}

}  // namespace penalty::scene
