#pragma once
// Building a topology from element lists (MeshTopology and SOFA's static ...SetTopologyContainer
// classes): the lists a class reads, from `src`, `filename`, `position` and the element Data.
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

/// The Data a topology class declares: SOFA copies from `src` only the lists the class has (a
/// TriangleSetTopologyContainer takes the loader's points, edges and triangles, not its quads).
struct ElementLists {
    bool edges = false;
    bool triangles = false;
    bool quads = false;
    bool tetrahedra = false;  ///< `tetrahedra` and its alias `tetras`
    bool hexahedra = false;   ///< `hexahedra` and its alias `hexas`
    bool nb_points = false;   ///< PointSetTopologyContainer's `nbPoints` (and `points`, alias of `position`)
};

/// The points of MechanicalObject `state` (of node `info`) after its init, as SOFA's Data
/// `position` reads once the state is initialised (a topology whose `src` links a state):
/// its positions with its translation, rotation and scale applied; Rigid3d: the frames' centres.
/// Made from the component's attributes, without building the state (states_and_topologies.cpp).
[[nodiscard]] std::vector<Vec3> state_initial_points(SceneBuilder& b, const io::SceneComponent& state,
                                                     const NodeBuild& info);

/// The list a data link names (`triangles="@loader.triangles"`, `tetrahedra="@../topo.tetrahedra"`,
/// `triangles="@subset.trianglesInROI"`): a loader's list, an engine's output, or a built
/// topology's (with its derived elements, as SOFA's Data).
template <class Element>
std::vector<Element> linked_elements(SceneBuilder& b, const Attributes& a, std::string_view attr,
                                     std::vector<Element> io::MeshData::*loaded,
                                     const std::vector<Element>& (MeshTopology::*built)() const) {
    const io::LinkTarget t = a.link(attr);
    if (t.component == nullptr) a.fail(attr, "link must name a loader or a topology");
    if (component_category(t.component->type) == ComponentCategory::loader) return b.mesh_of(*t.component).*loaded;
    if (const io::MeshData* engine = b.engine_mesh(*t.component, t.data)) return engine->*loaded;
    if (const SceneBuilder::BuiltTopology* topology = b.built_topology(*t.component); topology && topology->topology)
        return (topology->topology->*built)();
    a.fail(attr, "cannot read elements from " + t.component->describe() + " (a loader or a topology built before it)");
}

/// `out` := the list of attribute `attr` (inline or a link), when the component sets it.
template <class Element>
void read_element_list(SceneBuilder& b, const Attributes& a, std::string_view attr, std::vector<Element>& out,
                       std::vector<Element> io::MeshData::*loaded,
                       const std::vector<Element>& (MeshTopology::*built)() const) {
    if (!a.has(attr)) return;
    if (a.is_link(attr)) out = linked_elements(b, a, attr, loaded, built);
    else out = a.elements<std::tuple_size_v<Element>>(attr);
}

/// Builds the node's topology from `c` (its lists as declared by `lists`), records its points
/// (a MechanicalObject without positions takes them), and its `penalty info` role.
void build_element_topology(SceneBuilder& b, const io::SceneComponent& c, NodeBuild& info, const ElementLists& lists);

}  // namespace penalty::scene::builder
