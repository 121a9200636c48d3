// TopologyRuntime: the scene's dynamic topologies and their change sources (topology_runtime.hpp).
#include "scene/topology/topology_runtime.hpp"

#include "penalty/core/error.hpp"
#include "penalty/simulation/node.hpp"

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
    if (sources.empty()) return;
    const std::uint64_t before = revisions();
    for (auto& s : sources) s->begin_step(time);
    if (revisions() != before) changed();
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

}  // namespace penalty::scene
