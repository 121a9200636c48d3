// SOFA's ...SetTopologyContainer used statically: the lists each class reads, the elements it
// derives (SOFA's order, see src/scene/builder/topology_containers.cpp), the positions a
// MechanicalObject takes from it, and the components accepted or refused around them.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/state.hpp"
#include "penalty/mechanics/topological_mapping.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

/// The topology of the only state of a one-body scene.
const MeshTopology& topology_of(const scene::Scene& s) {
    EXPECT_EQ(s.states().size(), 1u);
    EXPECT_NE(s.states().front().topology, nullptr);
    return *s.states().front().topology;
}

std::string one_body(const std::string& topology) {
    return "<Node name=\"root\">\n  <Node name=\"A\">\n    " + topology +
           "\n    <MechanicalObject name=\"dofs\"/>\n  </Node>\n</Node>\n";
}

TEST(TopologyContainers, TriangleSetDerivesOrientedEdgesInFirstOccurrenceOrder) {
    // TriangleSetTopologyContainer::createEdgeSetArray: edge j of triangle t is (t[j+1], t[j+2]),
    // new when its sorted pair is new; kept oriented.
    const auto s = build(
        one_body(R"(<TriangleSetTopologyContainer position="0 0 0  1 0 0  1 1 0  0 1 0" triangles="0 1 2  0 2 3"/>)"));
    const MeshTopology& t = topology_of(*s);
    EXPECT_THAT(t.edges(), ElementsAre(Edge{1, 2}, Edge{2, 0}, Edge{0, 1}, Edge{2, 3}, Edge{3, 0}));
    EXPECT_TRUE(t.quads().empty());
    // MechanicalObject::init: a state without positions takes its topology's.
    const auto* dofs = dynamic_cast<const Vec3Object*>(s->states().front().state);
    ASSERT_NE(dofs, nullptr);
    ASSERT_EQ(dofs->position.size(), 4u);
    EXPECT_EQ(dofs->position[2], Vec3(1, 1, 0));
}

TEST(TopologyContainers, SrcMayLinkToATopologyBuiltBefore) {
    // SOFA's src link copies a container's same-named Data: a triangle container fed by a
    // tetrahedron container takes its points and its derived triangles (and edges).
    const auto s = build(R"(<Node name="root">
  <Node name="A">
    <TetrahedronSetTopologyContainer name="tetras" position="0 0 0  1 0 0  0 1 0  0 0 1" tetrahedra="0 1 2 3"/>
    <MechanicalObject name="dofs"/>
    <Node name="B">
      <TriangleSetTopologyContainer src="@../tetras"/>
      <TriangleCollisionModel/>
    </Node>
  </Node>
</Node>
)");
    ASSERT_EQ(s->collision_models().size(), 1u);
    EXPECT_EQ(s->collision_models().front().model->size(), 4u);  // the 4 faces {1,2,3}, {0,3,2}, {0,1,3}, {0,2,1}
    EXPECT_THROW(build(R"(<Node name="root"><Node name="A">
    <TriangleSetTopologyContainer src="@../later"/></Node><Node name="B"><MeshTopology name="later" triangles="0 1 2"/></Node>
</Node>)"),
                 io::SceneError);
}

TEST(TopologyContainers, QuadSetDerivesSortedEdges) {
    // QuadSetTopologyContainer::createEdgeSetArray: (q[j+1], q[j+2]) sorted.
    const auto s =
        build(one_body(R"(<QuadSetTopologyContainer position="0 0 0  1 0 0  1 1 0  0 1 0" quads="0 1 2 3"/>)"));
    EXPECT_THAT(topology_of(*s).edges(), ElementsAre(Edge{1, 2}, Edge{2, 3}, Edge{0, 3}, Edge{0, 1}));
}

TEST(TopologyContainers, TetrahedronSetDerivesTrianglesAndEdges) {
    // TetrahedronSetTopologyContainer::createTriangleSetArray: faces {1,2,3}, {0,3,2}, {1,3,0},
    // {0,2,1} of each tetrahedron, rotated to start at their smallest vertex, a shared face once;
    // createEdgeSetArray: pairs {0,1}, {0,2}, {0,3}, {1,2}, {1,3}, {2,3}, sorted.
    const auto s = build(one_body(
        R"(<TetrahedronSetTopologyContainer position="0 0 0  1 0 0  0 1 0  0 0 1  1 1 1" tetrahedra="0 1 2 3  1 2 3 4"/>)"));
    const MeshTopology& t = topology_of(*s);
    EXPECT_THAT(t.triangles(), ElementsAre(Triangle{1, 2, 3}, Triangle{0, 3, 2}, Triangle{0, 1, 3}, Triangle{0, 2, 1},
                                           Triangle{2, 3, 4}, Triangle{1, 4, 3}, Triangle{1, 2, 4}));
    EXPECT_THAT(t.edges(), ElementsAre(Edge{0, 1}, Edge{0, 2}, Edge{0, 3}, Edge{1, 2}, Edge{1, 3}, Edge{2, 3},
                                       Edge{1, 4}, Edge{2, 4}, Edge{3, 4}));
}

TEST(TopologyContainers, HexahedronSetDerivesQuadsInSofaFaceOrder) {
    // HexahedronSetTopologyContainer::createQuadSetArray: faces (0,3,2,1), (4,5,6,7), (0,1,5,4),
    // (1,2,6,5), (2,3,7,6), (3,0,4,7), rotated to start at their smallest vertex.
    const auto s = build(one_body(
        R"(<HexahedronSetTopologyContainer position="0 0 0  1 0 0  1 1 0  0 1 0  0 0 1  1 0 1  1 1 1  0 1 1" hexahedra="0 1 2 3 4 5 6 7"/>)"));
    const MeshTopology& t = topology_of(*s);
    EXPECT_THAT(t.quads(), ElementsAre(Quad{0, 3, 2, 1}, Quad{4, 5, 6, 7}, Quad{0, 1, 5, 4}, Quad{1, 2, 6, 5},
                                       Quad{2, 3, 7, 6}, Quad{0, 4, 7, 3}));
    EXPECT_EQ(t.edges().size(), 12u);
    EXPECT_TRUE(t.triangles().empty());
}

TEST(TopologyContainers, GivenEdgesAreKept) {
    const auto s = build(
        one_body(R"(<TriangleSetTopologyContainer position="0 0 0  1 0 0  0 1 0" edges="0 1" triangles="0 1 2"/>)"));
    EXPECT_THAT(topology_of(*s).edges(), ElementsAre(Edge{0, 1}));
}

TEST(TopologyContainers, DataLinksReadTheListsOfAnotherTopology) {
    const auto s = build(R"(<Node name="root">
  <Node name="A">
    <MeshTopology name="mesh" position="0 0 0  1 0 0  1 1 0  0 1 0" triangles="0 1 2" quads="0 1 2 3"/>
    <Node name="B">
      <TriangleSetTopologyContainer name="c" position="@../mesh.position" triangles="@../mesh.triangles"/>
      <MechanicalObject name="dofs"/>
    </Node>
  </Node>
</Node>
)");
    ASSERT_EQ(s->states().size(), 1u);
    const MeshTopology& t = *s->states().front().topology;
    EXPECT_THAT(t.triangles(), ElementsAre(Triangle{0, 1, 2}));
    EXPECT_TRUE(t.quads().empty());
    EXPECT_EQ(t.num_points(), 4u);
}

TEST(TopologyContainers, NbPointsSizesAStateWithoutPositions) {
    const auto s = build(one_body(R"(<PointSetTopologyContainer nbPoints="5"/>)"));
    EXPECT_EQ(topology_of(*s).num_points(), 5u);
}

TEST(TopologyContainers, ModifiersAndAlgorithmsAreAccepted) {
    const auto s = build(one_body(R"(<TriangleSetTopologyContainer position="0 0 0  1 0 0  0 1 0" triangles="0 1 2"/>
    <TriangleSetTopologyModifier/>
    <TriangleSetGeometryAlgorithms template="Vec3d"/>)"));
    EXPECT_EQ(topology_of(*s).triangles().size(), 1u);
}

TEST(TopologyContainers, TopologicalChangeProcessorWithoutADynamicTopologyIsRefusedNamingItsLine) {
    try {
        (void)build(one_body(R"(<TopologicalChangeProcessor filename="changes.txt"/>)"));
        ADD_FAILURE() << "no SceneError";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("test.scn:3"));
        EXPECT_THAT(e.what(), HasSubstr("TopologicalChangeProcessor"));
        EXPECT_THAT(e.what(), HasSubstr("needs a topology that can change"));
    }
}

TEST(TopologicalMappings, Tetra2TriangleFillsTheOutputContainerOfItsNode) {
    const auto s = build(R"(<Node name="root">
  <Node name="A">
    <TetrahedronSetTopologyContainer name="Container" position="0 0 0  1 0 0  0 1 0  0 0 1  1 1 1" tetrahedra="0 1 2 3  1 2 3 4"/>
    <MechanicalObject name="dofs"/>
    <Node name="T">
      <TriangleSetTopologyContainer name="Container"/>
      <TriangleSetTopologyModifier/>
      <Tetra2TriangleTopologicalMapping input="@../Container" output="@Container" flipNormals="1"/>
      <MechanicalObject name="surface"/>
      <IdentityMapping/>
    </Node>
  </Node>
</Node>
)");
    ASSERT_EQ(s->states().size(), 2u);
    const MeshTopology& surface = *s->states()[1].topology;
    EXPECT_EQ(surface.num_points(), 5u);
    EXPECT_THAT(surface.triangles(), ElementsAre(Triangle{0, 2, 3}, Triangle{0, 3, 1}, Triangle{0, 1, 2},
                                                 Triangle{2, 4, 3}, Triangle{1, 3, 4}, Triangle{1, 4, 2}));
    EXPECT_TRUE(surface.tetrahedra().empty());
    const auto* dofs = dynamic_cast<const Vec3Object*>(s->states()[1].state);
    ASSERT_NE(dofs, nullptr);
    EXPECT_EQ(dofs->position.size(), 5u);  // from the IdentityMapping, not from the topology
}

TEST(TopologicalMappings, OutputMustBeTheTopologyOfTheMappingsNode) {
    try {
        (void)build(R"(<Node name="root">
  <Node name="A">
    <TetrahedronSetTopologyContainer name="Container" position="0 0 0  1 0 0  0 1 0  0 0 1" tetrahedra="0 1 2 3"/>
    <Node name="T">
      <Tetra2TriangleTopologicalMapping input="@../Container" output="@../Container"/>
    </Node>
  </Node>
</Node>
)");
        ADD_FAILURE() << "no SceneError";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("test.scn:5"));
        EXPECT_THAT(e.what(), HasSubstr("output"));
    }
}

TEST(TopologicalMappings, Hexa2TetraOnAGridFillsTheOutput) {
    const auto s = build(R"(<Node name="root">
  <Node name="A">
    <RegularGridTopology name="grid" n="3 2 2" min="0 0 0" max="2 1 1"/>
    <MechanicalObject name="dofs"/>
    <Node name="T">
      <TetrahedronSetTopologyContainer name="Container"/>
      <Hexa2TetraTopologicalMapping input="@../grid" output="@Container" swapping="1"/>
      <MechanicalObject name="tetras"/>
      <IdentityMapping/>
    </Node>
  </Node>
</Node>
)");
    ASSERT_EQ(s->states().size(), 2u);
    const MeshTopology& grid = *s->states()[0].topology;
    const MeshTopology& tetras = *s->states()[1].topology;
    ASSERT_EQ(grid.hexahedra().size(), 2u);
    EXPECT_EQ(tetras.tetrahedra(), tetrahedra_of_hexahedra(grid.hexahedra(), true, 2, 1));
    EXPECT_EQ(tetras.num_points(), 12u);
}

}  // namespace
