// SceneBuilder::wire_topological_changes: once the scene is built, every topology that may change
// (a *SetTopologyContainer with a topology modifier in its node or above, SOFA's
// TopologyContainer + TopologyModifier) gets a TopologyContainer, and everything that uses it
// follows it with SOFA's rule for its class (topology_followers.hpp), registered in SOFA's init
// order (depth first, file order). A component that uses a changing topology (or a state whose
// points it changes) and has no rule blocks the topology: a change is refused, naming it.
#include "penalty/mechanics/corotational_fem.hpp"
#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/fixed_plane_constraint.hpp"
#include "penalty/mechanics/hexahedral_fem.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/state_topology.hpp"
#include "penalty/mechanics/topological_mapping_changes.hpp"
#include "penalty/mechanics/topology_followers.hpp"
#include "penalty/mechanics/triangular_fem.hpp"
#include "scene/builder/scene_builder.hpp"
#include "scene/topology/topology_changes.hpp"
#include "scene/topology/topology_runtime.hpp"

#include <algorithm>
#include <set>
#include <unordered_map>

namespace penalty::scene {

using io::SceneComponent;
using io::SceneNode;

namespace {

/// The class of a dynamic container, from its type.
std::optional<ElementType> container_level(std::string_view type) {
    using T = ElementType;
    static constexpr std::pair<std::string_view, T> kLevels[] = {{"PointSetTopologyContainer", T::point},
                                                                 {"EdgeSetTopologyContainer", T::edge},
                                                                 {"TriangleSetTopologyContainer", T::triangle},
                                                                 {"QuadSetTopologyContainer", T::quad},
                                                                 {"TetrahedronSetTopologyContainer", T::tetrahedron},
                                                                 {"HexahedronSetTopologyContainer", T::hexahedron}};
    for (const auto& [name, level] : kLevels)
        if (type == name) return level;
    return std::nullopt;
}

bool is_modifier(std::string_view type) {
    return type.size() > 16 && type.substr(type.size() - 16) == "TopologyModifier";
}

/// The modifier of a container's node or, as SOFA's getContext()->get(), of an ancestor.
const SceneComponent* find_modifier(const SceneNode& node) {
    for (const SceneNode* n = &node; n != nullptr; n = n->parent)
        for (const auto& c : n->components)
            if (is_modifier(c->type)) return c.get();
    return nullptr;
}

template <class F>
void depth_first(const SceneNode& n, F&& f) {
    f(n);
    for (const auto& child : n.children) depth_first(*child, f);
}

}  // namespace

// SOFA's l_topology: the `topology` link, else the node's topology or the nearest ancestor's
// (Node::getMeshTopologyLink).
const MeshTopology* TopologyWiring::topology_used(const io::SceneComponent& c) const {
    if (const auto text = io::get_string(c, "topology"); text && io::is_link(*text)) {
        const io::LinkTarget t = io::resolve_link(c, "topology");
        for (const auto& [sn, nb] : builder.node_builds())
            if (t.component != nullptr && nb.topology_component == t.component) return nb.topology;
        return nullptr;
    }
    for (const io::SceneNode* sn = c.node; sn != nullptr; sn = sn->parent) {
        const NodeBuild& nb = builder.node_build(*sn);
        if (nb.topology != nullptr) return nb.topology;
    }
    return nullptr;
}

TopologyHandler& TopologyWiring::keep(std::unique_ptr<TopologyHandler> h) {
    runtime.handlers.push_back(std::move(h));
    return *runtime.handlers.back();
}

void SceneBuilder::wire_topological_changes() {
    auto runtime = std::make_unique<TopologyRuntime>();
    runtime->root = &simulation().root();
    TopologyRuntime& rt = *runtime;

    // ---- the dynamic topologies ------------------------------------------------------------
    depth_first(*file_.root, [&](const SceneNode& sn) {
        const NodeBuild& nb = nodes_[&sn];
        if (nb.topology_component == nullptr || nb.topology == nullptr) return;
        const auto level = container_level(nb.topology_component->type);
        const SceneComponent* modifier = level ? find_modifier(sn) : nullptr;
        if (!level || modifier == nullptr) return;
        MeshTopology* mesh = nullptr;
        for (auto& t : scene_.topologies_)
            if (t.get() == nb.topology) mesh = t.get();
        if (mesh == nullptr) return;
        TopologyModifierOptions options;
        options.remove_isolated = io::get_bool(*modifier, "removeIsolated").value_or(true);
        options.propagate_to_dof = io::get_bool(*modifier, "propagateToDOF").value_or(true);
        auto t = std::make_unique<DynamicTopology>();
        t->component = nb.topology_component;
        t->path = (sn.parent == nullptr ? std::string() : sn.path()) + "/" +
                  (nb.topology_component->name.empty() ? sofa_default_name(*nb.topology_component)
                                                       : nb.topology_component->name);
        t->node = nb.node;
        guarded(*nb.topology_component,
                [&] { t->container = std::make_unique<TopologyContainer>(*mesh, *level, t->path, options); });
        if (container_level(modifier->type.substr(0, modifier->type.size() - 8) + "Container") != level)
            t->blockers.push_back(where(*modifier) + " (a modifier of another class than its container)");
        rt.topologies.push_back(std::move(t));
    });

    // one scope: a change and every change it makes through topological mappings end together
    const auto scope = std::make_shared<TopologyChangeScope>();
    for (auto& t : rt.topologies) t->container->set_scope(scope);

    // ---- the states that follow each topology's points (SOFA's StateChangeVisitor) ----------
    TopologyWiring w{*this, rt, {}};
    for (auto& t : rt.topologies) {
        const auto visit = [&](const auto& self, const SceneNode& sn, bool root) -> void {
            const NodeBuild& nb = nodes_[&sn];
            // StateChangeVisitor::processNodeTopDown: a mapped child node is pruned unless its
            // mapping keeps the same topology (BaseMapping::sameTopology: IdentityMapping,
            // DeformableOnRigidFrameMapping), or (penalty's rule) when it has a topology of its own
            if (!root && nb.mapped) {
                const BaseMapping* m = nb.node != nullptr ? nb.node->mapping() : nullptr;
                const SceneComponent* mc = m != nullptr ? scene_.component_of(m) : nullptr;
                const bool same_topology =
                    mc != nullptr && (mc->type == "IdentityMapping" || mc->type == "DeformableOnRigidFrameMapping");
                if (!same_topology || nb.topology_component != nullptr) return;
            }
            if (nb.node != nullptr && nb.node->state() != nullptr) {
                BaseState* s = nb.node->state();
                std::unique_ptr<StateFollower> follower;
                if (auto* v = dynamic_cast<Vec3Object*>(s)) {
                    follower = std::make_unique<StateTopologyFollower<Vec3Types>>(*v);
                    if (root && t->geometry == nullptr) t->geometry = v;
                } else if (auto* r = dynamic_cast<Rigid3Object*>(s))
                    follower = std::make_unique<StateTopologyFollower<Rigid3Types>>(*r);
                if (follower) {
                    t->container->add_state_follower(*follower);
                    rt.followers.push_back(std::move(follower));
                    w.followed_states[s] = t.get();
                }
            }
            for (const auto& child : sn.children) self(self, *child, false);
        };
        visit(visit, *t->component->node, true);
    }

    wire_topological_mappings(w);
    wire_components(w);
    wire_collision_models(w);
    add_topology_change_sources(w);
    add_carving_managers(w);

    if (!rt.topologies.empty()) scene_.topology_runtime_ = std::move(runtime);
}

}  // namespace penalty::scene
