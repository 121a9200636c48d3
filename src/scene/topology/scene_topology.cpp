// Scene's topological-change API (scene.hpp): the dynamic topologies by name, and removals and
// additions between steps, checked whole before anything changes.
#include "penalty/scene/scene.hpp"

#include "penalty/core/error.hpp"
#include "scene/live_edits.hpp"
#include "scene/topology/topology_runtime.hpp"

namespace penalty::scene {

namespace {

/// Changes happen between steps (SOFA's modifiers run from an AnimateBegin/End handler): not from
/// a handler of the collision phase inside Scene::step.
void check_between_steps(bool stepping, std::string_view what) {
    if (stepping)
        throw_invalid_argument(what,
                               ": topological changes happen between steps (onAnimateBeginEvent, onAnimateEndEvent), "
                               "not during the collision phase of a step");
}

DynamicTopology& named(const TopologyRuntime* rt, std::string_view topology) {
    DynamicTopology* t = rt != nullptr ? rt->find(topology) : nullptr;
    if (t != nullptr) return *t;
    std::string known;
    if (rt != nullptr)
        for (const auto& d : rt->topologies) known += (known.empty() ? "" : ", ") + d->path;
    throw_invalid_argument("no topology '", topology, "' can change in this scene (",
                           known.empty() ? std::string("none has a topology modifier") : "those that can: " + known,
                           ")");
}

template <std::size_t N>
std::vector<std::array<PointId, N>> grouped(const std::vector<PointId>& flat, ElementType type) {
    if (flat.size() % N != 0)
        throw_invalid_argument("add_elements: ", flat.size(), " vertex indices are not a whole number of ",
                               element_type_name(type), " (", N, " each)");
    std::vector<std::array<PointId, N>> out(flat.size() / N);
    for (std::size_t i = 0; i < flat.size(); ++i) out[i / N][i % N] = flat[i];
    return out;
}

}  // namespace

std::vector<std::string> Scene::dynamic_topologies() const {
    std::vector<std::string> out;
    if (topology_runtime_)
        for (const auto& t : topology_runtime_->topologies) out.push_back(t->path);
    return out;
}

std::uint64_t Scene::topology_revision() const { return topology_runtime_ ? topology_runtime_->revisions() : 0; }

const TopologyContainer& Scene::topology_container(std::string_view topology) const {
    return *named(topology_runtime_.get(), topology).container;
}

void Scene::remove_elements(std::string_view topology, ElementType type, std::vector<ElementId> indices) {
    check_between_steps(live_->stepping, "remove_elements");
    DynamicTopology& t = named(topology_runtime_.get(), topology);
    TopologyContainer& c = *t.container;
    c.check_removal(type, indices);
    topology_runtime_->check_can_change(t);
    TopologyRuntime::check_keeps_elements(t, type, c.count(type) - indices.size());
    switch (type) {
        case ElementType::point:
            c.remove_points(std::move(indices));
            break;
        case ElementType::edge:
            c.remove_edges(std::move(indices));
            break;
        case ElementType::triangle:
            c.remove_triangles(std::move(indices));
            break;
        case ElementType::quad:
            c.remove_quads(std::move(indices));
            break;
        case ElementType::tetrahedron:
            c.remove_tetrahedra(std::move(indices));
            break;
        case ElementType::hexahedron:
            c.remove_hexahedra(std::move(indices));
            break;
    }
    topology_runtime_->changed();
}

void Scene::add_elements(std::string_view topology, ElementType type, const std::vector<PointId>& vertices,
                         std::size_t count, const std::vector<std::vector<ElementId>>& ancestors) {
    check_between_steps(live_->stepping, "add_elements");
    DynamicTopology& t = named(topology_runtime_.get(), topology);
    TopologyContainer& c = *t.container;
    topology_runtime_->check_can_change(t);
    TopologyRuntime::check_added(t, type, vertices);
    switch (type) {
        case ElementType::point:
            if (!vertices.empty()) throw_invalid_argument("add_elements: points take a count, not vertex indices");
            c.add_points(count, ancestors);
            break;
        case ElementType::edge:
            c.add_edges(grouped<2>(vertices, type));
            break;
        case ElementType::triangle:
            c.add_triangles(grouped<3>(vertices, type));
            break;
        case ElementType::quad:
            c.add_quads(grouped<4>(vertices, type));
            break;
        case ElementType::tetrahedron:
            c.add_tetrahedra(grouped<4>(vertices, type));
            break;
        case ElementType::hexahedron:
            c.add_hexahedra(grouped<8>(vertices, type));
            break;
    }
    topology_runtime_->changed();
}

}  // namespace penalty::scene
