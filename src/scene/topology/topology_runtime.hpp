#pragma once
// The topological changes of a built scene (docs/topological-changes.md): its dynamic topologies
// (a *SetTopologyContainer with a topology modifier in its node, a TopologyContainer each), what
// follows each of them (states, masses, force fields, constraints, topological and barycentric
// mappings, collision models: the handlers wire_topological_changes registered), and what changes
// them at the start of each step (TopologicalChangeProcessor, TopologyBoundingTrasher,
// CarvingManager: SOFA's AnimateBeginEvent listeners, in scene order).
#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace penalty {
class Node;
class TopologicalMappingFollower;
}  // namespace penalty

namespace penalty::scene {

class Scene;

/// A topology that may change.
struct DynamicTopology {
    const io::SceneComponent* component = nullptr;  ///< the container
    std::string path;                               ///< node path / component name
    Node* node = nullptr;                           ///< the container's node
    std::unique_ptr<TopologyContainer> container;
    /// Components that use this topology and cannot follow its changes ("Type 'name' (file:line)"):
    /// a change is refused, naming the first, before anything changes.
    std::vector<std::string> blockers;
    /// Components that need at least one element of the container's level ("Type 'name'
    /// (file:line)"): a BarycentricMapping maps its points onto them. A removal of the last ones is
    /// refused, naming the first, before anything changes.
    std::vector<std::string> needs_elements;
    /// Dynamic topologies this one's changes reach (topological mappings' outputs).
    std::vector<DynamicTopology*> outputs;
    /// The topological mapping whose output this is (and its input), or none.
    const class TopologicalMappingFollower* fed_by = nullptr;
    DynamicTopology* input = nullptr;
    /// The Vec3 state of the container's node (its points' rest positions), or none.
    const Vec3Object* geometry = nullptr;
};

/// Something SOFA runs at AnimateBeginEvent that may change topologies.
class TopologyChangeSource {
public:
    virtual ~TopologyChangeSource() = default;
    /// AnimateBeginEvent; `time`: the simulation time at the start of the step (s).
    virtual void begin_step(double /*time*/) {}
    /// AnimateEndEvent; `time`: the simulation time at the end of the step (s).
    virtual void end_step(double /*time*/) {}
};

class TopologyRuntime {
public:
    TopologyRuntime() = default;
    TopologyRuntime(const TopologyRuntime&) = delete;
    TopologyRuntime& operator=(const TopologyRuntime&) = delete;
    ~TopologyRuntime();

    /// Runs the change sources (start of a step) and tells the graph when something changed.
    void begin_step(double time);
    /// The same at the end of a step.
    void end_step(double time);
    /// After any change made outside begin_step (the scene API): the solvers rebuild their systems.
    void changed();

    /// The dynamic topology of `mesh`, or nullptr.
    [[nodiscard]] DynamicTopology* find(const MeshTopology* mesh) const;
    /// By "name", "path/name" or node path, as Scene::topology_container documents; nullptr if none.
    [[nodiscard]] DynamicTopology* find(std::string_view name) const;
    /// Throws std::invalid_argument naming the first component that cannot follow a change of
    /// `t` (or of a topology it changes through a topological mapping).
    void check_can_change(const DynamicTopology& t) const;
    /// Throws std::invalid_argument when a removal of elements of `type` from `t` would leave
    /// `remaining` (0) elements of its level while a component needs one (DynamicTopology::
    /// needs_elements): SOFA's BarycentricMapper init over no element divides by zero.
    static void check_keeps_elements(const DynamicTopology& t, ElementType type, std::size_t remaining);
    /// Throws std::invalid_argument naming the first new element (`flat`: vertices of `type`,
    /// element after element) that is degenerate at rest (a tetrahedron of no volume, a triangle
    /// of no area, as the FEM force fields refuse them), before anything changes. Elements on a
    /// vertex the state does not have yet are not checked.
    static void check_added(const DynamicTopology& t, ElementType type, std::span<const PointId> flat);

    std::vector<std::unique_ptr<DynamicTopology>> topologies;
    std::vector<std::unique_ptr<TopologyHandler>> handlers;
    std::vector<std::unique_ptr<StateFollower>> followers;
    std::vector<std::unique_ptr<TopologyChangeSource>> sources;
    /// Components' doUpdateInternal (SOFA's UpdateInternalDataVisitor, in animate after the
    /// AnimateBeginEvent): run by begin_step after the sources, before the step's solve.
    std::vector<std::function<void()>> internal_updates;
    Node* root = nullptr;

    /// Sum of the dynamic meshes' revisions: changes whenever an element changes.
    std::uint64_t revisions() const;
};

}  // namespace penalty::scene
