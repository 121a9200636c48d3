// What a component finds in its node's context, as SOFA's Node resolves it: the state it acts on
// (Node::getMechanicalState: the node's own, else the nearest ancestor's) and the topology it reads
// (a `topology` link, else Node::getMeshTopologyLink: the node's own, else the nearest ancestor's).
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene {

using io::SceneComponent;

const NodeBuild* SceneBuilder::state_owner(const NodeBuild& info) {
    for (const io::SceneNode* sn = info.scene_node; sn != nullptr; sn = sn->parent) {
        const auto it = nodes_.find(sn);
        if (it != nodes_.end() && it->second.node != nullptr && it->second.node->state() != nullptr) return &it->second;
    }
    return nullptr;
}

Vec3Object& SceneBuilder::vec3_state(const SceneComponent& c, const NodeBuild& info) {
    BaseState& s = state(c, info);
    auto* v = dynamic_cast<Vec3Object*>(&s);
    if (v == nullptr)
        io::throw_element_error(c, std::string("needs a Vec3d MechanicalObject in its node (found ") +
                                       (dynamic_cast<Vec1Object*>(&s) != nullptr ? "Vec1d" : "Rigid3d") + ")");
    return *v;
}

BaseState& SceneBuilder::state(const SceneComponent& c, const NodeBuild& info) {
    const NodeBuild* owner = state_owner(info);
    if (owner == nullptr) io::throw_element_error(c, "needs a MechanicalObject in its node or an ancestor node");
    return *owner->node->state();
}

BaseState* SceneBuilder::linked_state(const Attributes& a, std::string_view attr) {
    return linked_state(a, attr, a.link(attr));
}

BaseState* SceneBuilder::linked_state(const Attributes& a, std::string_view attr, const io::LinkTarget& t) {
    const io::SceneNode* holder = t.node;
    if (t.component != nullptr) {
        const ComponentSpec* spec = find_component(t.component->type);
        if (spec == nullptr || spec->family != ComponentFamily::state)
            a.fail(attr,
                   "must link to a MechanicalObject or to a node that holds one, found " + t.component->describe());
        holder = t.component->node;
    }
    if (holder == nullptr) a.fail(attr, "must link to a MechanicalObject or to a node that holds one");
    const auto it = nodes_.find(holder);
    if (it == nodes_.end() || it->second.node == nullptr) return nullptr;  // not built yet
    BaseState* s = it->second.node->state();
    if (s == nullptr) a.fail(attr, "links to node '" + holder->path() + "', which has no MechanicalObject");
    return s;
}

void SceneBuilder::after_nodes(const SceneComponent& c, std::function<void()> build) {
    deferred_builds_.push_back({0, std::move(build), &c});
}

void SceneBuilder::build_when_ends_exist(const SceneComponent& c, const Attributes& a,
                                         const std::function<void()>& build) {
    bool later = false;
    guarded(c, [&] {
        for (const std::string_view end : {"object1", "object2"})
            if (a.has(end) && linked_state(a, end) == nullptr) later = true;
    });
    if (later) after_nodes(c, build);
    else guarded(c, build);
}

const MeshTopology& SceneBuilder::topology_of(const Attributes& a, const NodeBuild& info) {
    if (a.has("topology")) {
        const io::LinkTarget t = a.link("topology");
        if (t.component != nullptr) {
            for (const auto& [sn, i] : nodes_)
                if (i.topology_component == t.component) return *i.topology;
        }
        a.fail("topology", "must link to a MeshTopology or RegularGridTopology already built");
    }
    // SOFA's Node::getMeshTopologyLink: the node's own topology, else the nearest ancestor's.
    for (const io::SceneNode* sn = info.scene_node; sn != nullptr; sn = sn->parent) {
        const auto it = nodes_.find(sn);
        if (it != nodes_.end() && it->second.topology != nullptr) return *it->second.topology;
    }
    io::throw_element_error(a.component(),
                            "needs a topology (MeshTopology or RegularGridTopology) in its node or an ancestor node");
}

}  // namespace penalty::scene
