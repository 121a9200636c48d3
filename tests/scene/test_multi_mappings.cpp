// CenterOfMassMapping, SubsetMultiMapping, IdentityMultiMapping, DiagonalMass on Rigid3d frames
// and a MeshTopology whose `src` is a MechanicalObject, built from scenes made here: the mapped
// states in closed form, a force on a mapped state reaching its inputs (one implicit step of a
// free mass), and bad attributes as errors naming the file, line, component and attribute.
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

std::string multi_replaced(std::string xml, const std::string& what, const std::string& by) {
    xml.replace(xml.find(what), what.size(), by);
    return xml;
}

const Node& multi_child(const Node& n, std::size_t i) { return *n.children()[i]; }

// Two bodies of two points each, a concatenation node below the second picking points of both;
// the only mass is on the mapped state, and a force pulls its point 0 (input 0's point 1).
const std::string kSubsetScene = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/><CGLinearSolver iterations="50" tolerance="1e-20" threshold="1e-30"/>
  <Node name="A"><MechanicalObject name="a" position="0 0 0  1 0 0"/>
    <Node name="B"><MechanicalObject name="b" position="5 0 0  6 0 0"/>
      <Node name="C"><MechanicalObject name="c"/>
        <MAPPING/>
        <UniformMass vertexMass="2"/>
        <ConstantForceField indices="0" forces="1 0 0"/>
      </Node>
    </Node>
  </Node>
</Node>)";

TEST(MultiMappingComponents, SubsetMultiMappingPicksPointsAndCarriesTheirForces) {
    auto s =
        build(multi_replaced(kSubsetScene, "<MAPPING/>",
                             R"(<SubsetMultiMapping input="@../../a @../b" output="@c" indexPairs="0 1  1 0  1 1"/>)"));
    const Node& a = multi_child(s->simulation().root(), 0);
    const Node& b = multi_child(a, 0);
    const auto& c = dynamic_cast<const Vec3Object&>(*multi_child(b, 0).state());
    ASSERT_EQ(c.position.size(), 3u);
    EXPECT_EQ(c.position[0], Vec3(1, 0, 0));
    EXPECT_EQ(c.position[2], Vec3(6, 0, 0));
    s->step();
    // the input point under output 0 has mass 2 (through Jᵀ M J) and force 1: v = h·f/m
    const auto& av = dynamic_cast<const Vec3Object&>(*a.state());
    EXPECT_NEAR(av.velocity[1].x(), 0.01 * 1.0 / 2.0, 1e-15);
    EXPECT_NEAR(av.position[1].x(), 1.0 + 0.01 * 0.005, 1e-15);
    EXPECT_EQ(av.velocity[0], Vec3::Zero());  // picked by nobody
    EXPECT_EQ(c.position[0], av.position[1]);
}

TEST(MultiMappingComponents, IdentityMultiMappingConcatenates) {
    auto s = build(
        multi_replaced(kSubsetScene, "<MAPPING/>", R"(<IdentityMultiMapping input="@../../a @../b" output="@c"/>)"));
    const auto& c = dynamic_cast<const Vec3Object&>(
        *multi_child(multi_child(multi_child(s->simulation().root(), 0), 0), 0).state());
    ASSERT_EQ(c.position.size(), 4u);
    EXPECT_EQ(c.position[1], Vec3(1, 0, 0));
    EXPECT_EQ(c.position[2], Vec3(5, 0, 0));
}

TEST(MultiMappingComponents, BadMultiMappingAttributesAreNamed) {
    const auto with_mapping = [](const std::string& m) { return multi_replaced(kSubsetScene, "<MAPPING/>", m); };
    EXPECT_THAT(
        error_of(with_mapping(R"(<SubsetMultiMapping input="@../../a @../b" indexPairs="0 1 1"/>)")),
        HasSubstr(
            "test.scn:6: SubsetMultiMapping: attribute 'indexPairs': expected pairs (input, index), found 3 numbers"));
    EXPECT_THAT(error_of(with_mapping(R"(<SubsetMultiMapping input="@../../a @../b" indexPairs="2 0"/>)")),
                HasSubstr("SubsetMultiMapping: attribute 'indexPairs': pair 0 names input 2, and there are 2 inputs"));
    EXPECT_THAT(error_of(with_mapping(R"(<SubsetMultiMapping input="@../../a @../b" indexPairs="1 7"/>)")),
                HasSubstr("pair 0 names DOF 7 of input 1, which has 2 DOFs"));
    EXPECT_THAT(error_of(with_mapping(R"(<SubsetMultiMapping input="@../../a @../b @." indexPairs="0 0"/>)")),
                HasSubstr("SubsetMultiMapping: attribute 'input': penalty maps from two states at most"));
    EXPECT_THAT(error_of(with_mapping(R"(<IdentityMultiMapping input="@../../a @../../a"/>)")),
                HasSubstr("IdentityMultiMapping: attribute 'input': names the same state twice"));
    EXPECT_THAT(error_of(with_mapping(R"(<CenterOfMassMapping input="@../../a"/>)")),
                HasSubstr("CenterOfMassMapping: attribute 'input': must be a Rigid3d state"));
}

const std::string kCenterOfMassScene = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Frames"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject template="Rigid3" name="frames" position="0 0 0 0 0 0 1  3 0 0 0 0 0 1  0 6 0 0 0 0 1"/>
    MASS
    <Node name="Centre"><MechanicalObject name="centre"/><CenterOfMassMapping/></Node>
  </Node>
</Node>)";

TEST(MultiMappingComponents, CenterOfMassOfRigidFramesWeighedByTheirDiagonalMass) {
    auto s = build(multi_replaced(
        kCenterOfMassScene, "MASS",
        R"(<DiagonalMass template="Rigid3" vertexMass="1 1 [1 0 0,0 1 0,0 0 1]  2 1 [1 0 0,0 1 0,0 0 1]  3 1 [1 0 0,0 1 0,0 0 1]"/>)"));
    const Node& frames = multi_child(s->simulation().root(), 0);
    const auto& centre = dynamic_cast<const Vec3Object&>(*multi_child(frames, 0).state());
    ASSERT_EQ(centre.position.size(), 1u);
    EXPECT_NEAR((centre.position[0] - Vec3(6.0 / 6.0, 18.0 / 6.0, 0)).norm(), 0, 1e-15);  // Σ m c / M
    s->step();
    // free fall: every frame moves by the same amount, so does the centre
    const auto& f = dynamic_cast<const Rigid3Object&>(*frames.state());
    EXPECT_NEAR(centre.position[0].y(),
                (f.position[0].center.y() + 2 * f.position[1].center.y() + 3 * f.position[2].center.y()) / 6.0, 1e-14);
    EXPECT_LT(centre.position[0].y(), 3.0);
    EXPECT_THAT(error_of(multi_replaced(kCenterOfMassScene, "MASS", "")),
                HasSubstr("test.scn:5: CenterOfMassMapping: attribute 'input': the input's node has no mass"));
    EXPECT_THAT(
        error_of(multi_replaced(kCenterOfMassScene, "MASS",
                                R"(<DiagonalMass template="Rigid3" vertexMass="1 1 [1 0 0]"/>)")),
        HasSubstr(
            "test.scn:4: DiagonalMass: attribute 'vertexMass': a Rigid3d DiagonalMass takes 11 numbers per frame"));
}

TEST(MultiMappingComponents, MeshTopologyTakesTheInitialisedPointsOfAMechanicalObject) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Frames">
    <MechanicalObject template="Rigid3" name="frames" position="1 0 0 0 0 0 1  0 1 0 0 0 0 1" translation="0 0 5" dx="0 0 0 0 0 0"/>
    <MeshTopology name="topology" src="@frames"/>
  </Node>
</Node>)";
    auto s = build(xml);
    const MeshTopology* t = s->states()[0].topology;
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->num_points(), 2u);
    // SOFA's MechanicalObject::parse: a dx that is not one number reads as 0, and any of dx dy dz
    // replaces the translation by (dx, dy, dz): (0, 0, 0) here
    const auto& f = dynamic_cast<const Rigid3Object&>(*multi_child(s->simulation().root(), 0).state());
    EXPECT_EQ(f.position[0].center, Vec3(1, 0, 0));
    EXPECT_THAT(::testing::PrintToString(s->warnings()),
                HasSubstr("test.scn:3: MechanicalObject 'frames': dx '0 0 0 0 0 0' is not one number: 0 used"));
    auto translated = build(multi_replaced(xml, R"( dx="0 0 0 0 0 0")", ""));
    EXPECT_EQ(
        dynamic_cast<const Rigid3Object&>(*multi_child(translated->simulation().root(), 0).state()).position[1].center,
        Vec3(0, 1, 5));
}

TEST(MultiMappingComponents, SimpleTesselatedTetraCutsATetrahedronInEight) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Coarse">
    <TetrahedronSetTopologyContainer name="coarse" position="0 0 0  2 0 0  0 2 0  0 0 2" tetrahedra="0 1 2 3"/>
    <MechanicalObject name="dofs"/>
    <Node name="Fine"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
      <TetrahedronSetTopologyContainer name="fine"/>
      <SimpleTesselatedTetraTopologicalMapping input="@../coarse" output="@fine"/>
      <MechanicalObject name="fineDofs"/>
      <UniformMass vertexMass="1"/>
    </Node>
  </Node>
</Node>)";
    auto s = build(xml);
    const Node& fine = multi_child(multi_child(s->simulation().root(), 0), 0);
    const auto& x = dynamic_cast<const Vec3Object&>(*fine.state());
    ASSERT_EQ(x.position.size(), 10u);  // 4 corners + 6 edge middles
    const MeshTopology* t = s->states()[1].topology;
    ASSERT_NE(t, nullptr);
    ASSERT_EQ(t->tetrahedra().size(), 8u);
    // the eight volumes add up to the coarse one (8/6), each corner tetrahedron an eighth of it
    double total = 0;
    for (const Tetrahedron& e : t->tetrahedra()) {
        const Vec3& p0 = x.position[std::size_t(e[0])];
        const double v = (x.position[std::size_t(e[1])] - p0)
                             .cross(x.position[std::size_t(e[2])] - p0)
                             .dot(x.position[std::size_t(e[3])] - p0) /
                         6;
        EXPECT_NEAR(std::abs(v), 8.0 / 6.0 / 8.0, 1e-15);
        total += std::abs(v);
    }
    EXPECT_NEAR(total, 8.0 / 6.0, 1e-14);
    // every middle point is the middle of two corners
    int middles = 0;
    for (std::size_t i = 4; i < 10; ++i)
        for (std::size_t p = 0; p < 4; ++p)
            for (std::size_t q = p + 1; q < 4; ++q)
                middles += x.position[i] == (x.position[p] + x.position[q]) / 2 ? 1 : 0;
    EXPECT_EQ(middles, 6);
    EXPECT_THAT(
        error_of(multi_replaced(xml, R"(input="@../coarse")", R"(input="@../dofs")")),
        HasSubstr("test.scn:7: SimpleTesselatedTetraTopologicalMapping: attribute 'input': must link to a topology"));
}

}  // namespace
