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

/// The list a data link names (`triangles="@loader.triangles"`, `tetrahedra="@../topo.tetrahedra"`):
/// a loader's list, or a built topology's (with its derived elements, as SOFA's Data).
template <class Element>
std::vector<Element> linked_elements(SceneBuilder& b, const Attributes& a, std::string_view attr,
                                     std::vector<Element> io::MeshData::*loaded,
                                     const std::vector<Element>& (MeshTopology::*built)() const) {
    const io::LinkTarget t = a.link(attr);
    if (t.component == nullptr) a.fail(attr, "link must name a loader or a topology");
    if (component_category(t.component->type) == ComponentCategory::loader) return b.mesh_of(*t.component).*loaded;
    for (const auto& [node, info] : b.node_builds())
        if (info.topology_component == t.component && info.topology != nullptr) return (info.topology->*built)();
    a.fail(attr, "cannot read elements from " + t.component->describe() + " (a loader or a topology built before it)");
}

/// Builds the node's topology from `c` (its lists as declared by `lists`), records its points
/// (a MechanicalObject without positions takes them), and its `penalty info` role.
void build_element_topology(SceneBuilder& b, const io::SceneComponent& c, NodeBuild& info, const ElementLists& lists);

}  // namespace penalty::scene::builder
