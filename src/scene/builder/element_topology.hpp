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

/// Builds the node's topology from `c` (its lists as declared by `lists`), records its points
/// (a MechanicalObject without positions takes them), and its `penalty info` role.
void build_element_topology(SceneBuilder& b, const io::SceneComponent& c, NodeBuild& info, const ElementLists& lists);

}  // namespace penalty::scene::builder
