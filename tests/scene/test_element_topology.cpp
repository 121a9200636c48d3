// Topologies from element lists (builder/element_topology.cpp: MeshTopology and SOFA's static
// ...SetTopologyContainer classes): `src` links (a loader, a MechanicalObject's points, a topology
// built before, each class keeping only the lists it declares), the aliases, nbPoints raised to
// cover the elements, and the refusals naming the file, line, component and attribute.
#include "penalty/io/error.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::ElementsAre;

/// The topology of the state `index` of `s`.
const MeshTopology& element_topology_of(const scene::Scene& s, std::size_t index = 0) {
    EXPECT_GT(s.states().size(), index);
    EXPECT_NE(s.states()[index].topology, nullptr);
    return *s.states()[index].topology;
}

/// `body` in a node A (line 3 onwards) with a MechanicalObject after it.
std::string element_body(const std::string& body) {
    return "<Node name=\"root\">\n  <Node name=\"A\">\n    " + body +
           "\n    <MechanicalObject name=\"dofs\"/>\n  </Node>\n</Node>\n";
}

TEST(ElementTopology, NbPointsIsRaisedToCoverTheElements) {
    // PointSetTopologyContainer::init: nbPoints, or more when an element uses a higher index
    const auto raised = build(element_body(R"(<EdgeSetTopologyContainer nbPoints="2" edges="0 1  1 4"/>)"));
    EXPECT_EQ(element_topology_of(*raised).num_points(), 5u);
    const auto kept = build(element_body(R"(<EdgeSetTopologyContainer nbPoints="7" edges="0 1  1 4"/>)"));
    EXPECT_EQ(element_topology_of(*kept).num_points(), 7u);
    // the MechanicalObject takes no size from nbPoints (SOFA HEAD's state has one DOF too)
    EXPECT_EQ(kept->states()[0].state->num_dofs(), 1u);
    // positions given: their count, nbPoints not read
    const auto placed =
        build(element_body(R"(<EdgeSetTopologyContainer nbPoints="9" position="0 0 0  1 0 0  2 0 0" edges="0 1"/>)"));
    EXPECT_EQ(element_topology_of(*placed).num_points(), 3u);
    EXPECT_EQ(error_of(element_body(R"(<EdgeSetTopologyContainer nbPoints="-1" edges="0 1"/>)"))
                  .rfind("test.scn:3: EdgeSetTopologyContainer: attribute 'nbPoints': must be between 0 and ", 0),
              0u);
}

TEST(ElementTopology, TheAliasesTetrasAndHexasAreTheLists) {
    const auto tetras = build(
        element_body(R"(<TetrahedronSetTopologyContainer position="0 0 0  1 0 0  0 1 0  0 0 1" tetras="0 1 2 3"/>)"));
    EXPECT_THAT(element_topology_of(*tetras).tetrahedra(), ElementsAre(Tetrahedron{0, 1, 2, 3}));
    const auto hexas = build(element_body(
        R"(<HexahedronSetTopologyContainer position="0 0 0  1 0 0  1 1 0  0 1 0  0 0 1  1 0 1  1 1 1  0 1 1" hexas="0 1 2 3 4 5 6 7"/>)"));
    EXPECT_THAT(element_topology_of(*hexas).hexahedra(), ElementsAre(Hexahedron{0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(ElementTopology, SrcCopiesOnlyTheListsTheClassDeclares) {
    // a MeshTopology with triangles and quads, linked by an EdgeSetTopologyContainer (edges only:
    // the edges derived from the triangles and quads, no faces) and by a TriangleSet one
    const auto s = build(R"(<Node name="root">
  <Node name="A">
    <MeshTopology name="mesh" position="0 0 0  1 0 0  1 1 0  0 1 0  2 0 0" triangles="1 4 2" quads="0 1 2 3"/>
    <MechanicalObject name="a"/>
    <Node name="B">
      <EdgeSetTopologyContainer name="edges" src="@../mesh"/>
      <MechanicalObject name="b"/>
    </Node>
    <Node name="C">
      <TriangleSetTopologyContainer name="triangles" src="@../mesh"/>
      <MechanicalObject name="c"/>
    </Node>
  </Node>
</Node>
)");
    ASSERT_EQ(s->states().size(), 3u);
    const MeshTopology& edges = element_topology_of(*s, 1);
    EXPECT_TRUE(edges.triangles().empty());
    EXPECT_TRUE(edges.quads().empty());
    EXPECT_EQ(edges.edges().size(), element_topology_of(*s, 0).edges().size());
    EXPECT_EQ(edges.num_points(), 5u);
    const MeshTopology& triangles = element_topology_of(*s, 2);
    EXPECT_THAT(triangles.triangles(), ElementsAre(Triangle{1, 4, 2}));
    EXPECT_TRUE(triangles.quads().empty());
}

TEST(ElementTopology, SrcOfAMechanicalObjectGivesItsPointsOnly) {
    const auto s = build(R"(<Node name="root">
  <Node name="A">
    <MechanicalObject name="cloud" position="0 0 0  1 0 0  0 1 0  0 0 1"/>
    <Node name="B">
      <TetrahedronSetTopologyContainer name="t" src="@../cloud" tetrahedra="0 1 2 3"/>
      <MechanicalObject name="b"/>
    </Node>
  </Node>
</Node>
)");
    const MeshTopology& t = element_topology_of(*s, 1);
    EXPECT_EQ(t.num_points(), 4u);
    EXPECT_THAT(t.tetrahedra(), ElementsAre(Tetrahedron{0, 1, 2, 3}));
    EXPECT_EQ(s->states()[1].state->num_dofs(), 4u);
}

TEST(ElementTopology, BadSourcesAndIndicesAreRefusedNamingTheAttribute) {
    // `src` onto a component that is neither a loader nor a topology built before
    EXPECT_EQ(error_of(R"(<Node name="root">
  <Node name="A">
    <UniformMass name="mass" totalMass="1"/>
    <TriangleSetTopologyContainer src="@mass"/>
    <MechanicalObject name="dofs"/>
  </Node>
</Node>
)"),
              "test.scn:4: TriangleSetTopologyContainer: attribute 'src': must link to a mesh loader or a topology "
              "built before this one");
    // an index past the points
    const std::string past =
        error_of(element_body(R"(<TriangleSetTopologyContainer position="0 0 0  1 0 0  0 1 0" triangles="0 1 3"/>)"));
    EXPECT_EQ(past,
              "test.scn:3: TriangleSetTopologyContainer: MeshTopology: triangles[0] uses vertex 3 but num_points is 3");
}

TEST(ElementTopology, AContainersFileWinsOverItsSrcLinksAsSofasLoadAtInit) {
    // BaseMeshTopology::init loads `filename` after the Data links are read and its load clears
    // them; the container then derives the lists the file lacks (createTriangleSetArray: each face
    // turned so that its smallest vertex comes first). So with both, the triangles are the file's
    // derived ones, not src's (a MeshGmshLoader's faces of each tetrahedron, as it writes them).
    // SOFA HEAD's TopologyTetra2TriangleTopologicalMapping.scn example has both, measured with
    // SofaPython3: its container's triangles are the derived ones.
    const std::string file = ::testing::TempDir() + "penalty_one_tetrahedron.msh";
    {
        std::ofstream out(file);
        out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
               "$Elements\n1\n1 4 2 0 1 4 2 3 1\n$EndElements\n";
    }
    const auto triangles_of = [&](const std::string& attributes) {
        const auto s = build(element_body(R"(<MeshGmshLoader name="loader" filename=")" + file + R"("/>
    <TetrahedronSetTopologyContainer name="volume" )" +
                                          attributes + "/>"));
        return element_topology_of(*s).triangles();
    };
    const auto from_file = triangles_of(R"(filename=")" + file + R"(")");
    const auto from_loader = triangles_of(R"(src="@loader")");
    EXPECT_EQ(triangles_of(R"(src="@loader" filename=")" + file + R"(")"), from_file);
    EXPECT_NE(from_file, from_loader);
    ASSERT_EQ(from_file.size(), 4u);
    for (const Triangle& t : from_file) EXPECT_TRUE(t[0] < t[1] && t[0] < t[2]) << t[0] << ' ' << t[1] << ' ' << t[2];
    std::remove(file.c_str());
}

}  // namespace
