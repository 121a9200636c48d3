// The topological mappings whose input changes: SOFA's TopologyChangeVisitor runs each one's
// updateTopologicalMappingTopDown after the input's data handlers (a listener of the input), and
// the mapping changes its output through the output's modifier. A mapping whose output has no
// modifier leaves it as built (SOFA: no TopologyModifier found, changes not supported), so its
// input changes alone.
#include "penalty/mechanics/topological_mapping_changes.hpp"
#include "scene/topology/topology_changes.hpp"

namespace penalty::scene {

void wire_topological_mappings(TopologyWiring& w) {
    TopologyRuntime& rt = w.runtime;
    const auto dynamic_of = [&](const io::SceneComponent& c, std::string_view attr) -> DynamicTopology* {
        if (!c.has(attr)) return nullptr;
        const io::LinkTarget t = io::resolve_link(c, attr);
        for (const auto& d : rt.topologies)
            if (d->component == t.component) return d.get();
        return nullptr;
    };
    const auto visit = [&](const auto& self, const io::SceneNode& sn) -> void {
        for (const auto& cp : sn.components) {
            const io::SceneComponent& c = *cp;
            if (c.type.find("TopologicalMapping") == std::string::npos) continue;
            DynamicTopology* in = dynamic_of(c, "input");
            DynamicTopology* out = dynamic_of(c, "output");
            if (in == nullptr || out == nullptr) continue;
            std::unique_ptr<TopologicalMappingFollower> follower;
            if (c.type == "Tetra2TriangleTopologicalMapping") {
                follower = std::make_unique<Tetra2TriangleMappingFollower>(
                    *in->container, *out->container, io::get_bool_or(c, "flipNormals", false),
                    io::get_bool_or(c, "noNewTriangles", false), io::get_bool_or(c, "noInitialTriangles", false));
            } else if (c.type == "Hexa2QuadTopologicalMapping") {
                follower = std::make_unique<Hexa2QuadMappingFollower>(*in->container, *out->container,
                                                                      io::get_bool_or(c, "flipNormals", false));
            } else if (c.type == "Quad2TriangleTopologicalMapping") {
                follower = std::make_unique<Quad2TriangleMappingFollower>(*in->container, *out->container);
            } else if (c.type == "Triangle2EdgeTopologicalMapping") {
                follower = std::make_unique<Triangle2EdgeMappingFollower>(*in->container, *out->container);
            }
            if (follower) {
                out->fed_by = follower.get();
                out->input = in;
                in->container->add_listener(w.keep(std::move(follower)));
                in->outputs.push_back(out);
            } else {
                in->blockers.push_back(where(c));  // its output has no rule to follow the input
            }
        }
        for (const auto& child : sn.children) self(self, *child);
    };
    visit(visit, *w.builder.scene().file().root);
}

}  // namespace penalty::scene
