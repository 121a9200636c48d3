#pragma once
// The parts of SceneBuilder::wire_topological_changes (wiring.cpp), one file each.
#include "scene/builder/scene_builder.hpp"
#include "scene/topology/topology_runtime.hpp"

#include <unordered_map>

namespace penalty::scene {

/// "Type 'name' (file:line)": a component in the topology wiring's messages.
inline std::string where(const io::SceneComponent& c) {
    return c.describe() + " (" + c.file + ":" + std::to_string(c.line) + ")";
}

struct TopologyWiring {
    SceneBuilder& builder;
    TopologyRuntime& runtime;
    /// The states that follow a topology's points (SOFA's StateChangeVisitor), and that topology.
    std::unordered_map<const BaseState*, DynamicTopology*> followed_states;

    /// The topology a component reads (its `topology` link or its node's), or nullptr.
    [[nodiscard]] const MeshTopology* topology_used(const io::SceneComponent& c) const;
    /// Keeps `h` alive for the scene's lifetime.
    TopologyHandler& keep(std::unique_ptr<TopologyHandler> h);
};

/// Masses, force fields, constraints and mappings of the graph (component_followers.cpp).
void wire_components(TopologyWiring& w);
/// SurfacePressureForceField, TaitSurfacePressureForceField, RestShapeSpringsForceField `f` of
/// component `c` on `t`, its topology (load_followers.cpp): false when it has no rule.
bool follow_surface_load_or_rest_springs(TopologyWiring& w, const io::SceneComponent& c, BaseForceField& f,
                                         DynamicTopology& t);
/// Collision models (component_followers.cpp).
void wire_collision_models(TopologyWiring& w);
/// The topological mappings between dynamic topologies (topological_mappings.cpp).
void wire_topological_mappings(TopologyWiring& w);
/// TopologicalChangeProcessor, TopologyBoundingTrasher, CarvingManager
/// (topological_change_processor.cpp, ...).
void add_topology_change_sources(TopologyWiring& w);
/// CarvingManager (carving_manager.cpp).
void add_carving_managers(TopologyWiring& w);

}  // namespace penalty::scene
