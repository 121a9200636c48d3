// The data engines (TransformEngine, TransformPosition, MergePoints), the selection engines
// (MeshROI, ProximityROI, ValuesFromPositions), the frame mappings (SkinningMapping,
// DeformableOnRigidFrameMapping, DistanceFromTargetMapping), a mass on a mapped state, springs
// between two nodes' states, Data links to values and broken Data links, built from scenes made
// here; bad attributes are errors naming the file, line, component and attribute.
#include "engine_and_mapping_scenes.hpp"
#include "penalty/io/error.hpp"
#include "penalty/mechanics/frame_mappings.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/output/state_record.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty::test_engine_scenes;
using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

TEST(MappedMassComponents, AMassOnAMappedStateActsThroughTheMapping) {
    auto s = build(kMappedMass);
    s->step();
    const auto& frame = dynamic_cast<const Rigid3Object&>(*s->states()[0].state);
    // total mass 3 kg: gravity gives −10 m/s² in y (every mass falls alike), the 6 N push on point
    // 0 (on the frame's x axis: no torque) 2 m/s² in x (6 N / 3 kg, not 6 N / 1 kg); one implicit
    // step of h = 0.01 s (no stiffness): v = a·h
    EXPECT_NEAR(frame.velocity[0].linear.y(), -10 * 0.01, 1e-12);
    EXPECT_NEAR(frame.velocity[0].linear.x(), 2 * 0.01, 1e-12);
    EXPECT_NEAR(frame.velocity[0].angular.norm(), 0.0, 1e-12);  // symmetric points: no torque
}

TEST(MappedMassComponents, TheExplicitSolverRefusesAMappedMass) {
    std::string xml =
        with(kMappedMass, R"(<EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>)", "<EulerExplicitSolver/>");
    xml = with(xml, R"(<CGLinearSolver iterations="50" tolerance="1e-14" threshold="1e-30"/>)", "");
    try {
        auto s = build(xml);
        s->step();
        FAIL() << "no error";
    } catch (const std::exception& e) {
        EXPECT_THAT(e.what(), HasSubstr("a mass on a mapped state needs an implicit solver"));
    }
}

TEST(LinkComponents, DataLinksToValuesAndBrokenDataLinks) {
    // a MechanicalObject's translation linked to a loader's (unwritten: its default 0 0 0) and to
    // another component's written value
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <TransformEngine name="shift" translation="0 5 0" input_position="0 0 0  1 1 1"/>
    <MechanicalObject name="dofs" position="1 1 1" translation="@shift.translation" rotation="@shift.rotation"/>
    <UniformMass vertexMass="1"/>
    <FixedProjectiveConstraint indices="@missing.indices"/>
  </Node>
</Node>)";
    auto s = build(xml);
    EXPECT_EQ(engine_state(*s).position[0], Vec3(1, 6, 1));
    // the broken Data link leaves `indices` unset, as SOFA: nothing fixed, and a note says so
    bool noted = false;
    for (const std::string& w : s->warnings()) noted = noted || w.find("@missing.indices") != std::string::npos;
    EXPECT_TRUE(noted);
    EXPECT_THAT(error_of(with(xml, R"(translation="@shift.translation")", R"(translation="@shift.input_position")")),
                HasSubstr("MechanicalObject 'dofs': attribute 'translation': expected 3 numbers"));
}

TEST(LinkComponents, ARegularGridTakesAnotherGridsDataThroughSrc) {
    // SOFA's DataDisplay.scn: RegularGridTopology src="@/Mesh/Grid" copies n, min, max (and p0)
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Mesh"><RegularGridTopology name="Grid" nx="3" ny="4" nz="1" xmin="0" xmax="2" ymin="0" ymax="3" zmin="0" zmax="1"/>
  </Node>
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <RegularGridTopology name="copy" src="@/Mesh/Grid"/>
    <MechanicalObject name="dofs"/>
    <UniformMass vertexMass="1"/>
  </Node>
</Node>)";
    auto s = build(xml);
    const Vec3Object& x = engine_state(*s);
    ASSERT_EQ(x.position.size(), 12u);
    EXPECT_EQ(x.position[11], Vec3(2, 3, 0));  // nz = 1: the plane z = zmin
    // a value given on the copy wins over the source's
    auto t = build(with(xml, R"(src="@/Mesh/Grid")", R"(src="@/Mesh/Grid" n="2 2 1")"));
    EXPECT_EQ(engine_state(*t).position.size(), 4u);
    EXPECT_THAT(
        error_of(with(xml, R"(src="@/Mesh/Grid")", R"(src="@/Body/dofs")")),
        HasSubstr("RegularGridTopology 'copy': attribute 'src': must link to a RegularGridTopology built before"));
}

TEST(LinkComponents, AMappingOntoANodeWithoutAStateIsNotCreated) {
    // SOFA's DataDisplay.scn: IdentityMapping output="@." in a node without a MechanicalObject;
    // SOFA's link finds no state, Mapping::canCreate fails and the scene runs without it
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 0 0"/>
    <UniformMass vertexMass="1"/>
    <Node name="Data"><IdentityMapping input="@.." output="@."/></Node>
  </Node>
</Node>)";
    auto s = build(xml);
    bool noted = false;
    for (const std::string& w : s->warnings())
        noted = noted || w.find("IdentityMapping (output node without a state: SOFA does not create it) x1") !=
                             std::string::npos;
    EXPECT_TRUE(noted);
    // with a state in that node, the mapping is built
    auto t = build(with(xml, R"(<Node name="Data">)", R"(<Node name="Data"><MechanicalObject name="copy"/>)"));
    EXPECT_EQ(t->states().size(), 2u);
}

TEST(LinkComponents, SpringsBetweenStatesOfNodesBelow) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Pair"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="50" tolerance="1e-14" threshold="1e-30"/>
    <Node name="A"><MechanicalObject name="a" position="0 0 0"/><UniformMass vertexMass="1"/></Node>
    <Node name="B"><MechanicalObject name="b" position="2 0 0"/><UniformMass vertexMass="1"/></Node>
    <SpringForceField object1="@A/a" object2="@B/b" spring="0 0 100 0 1"/>
  </Node>
</Node>)";
    auto s = build(xml);
    s->step();
    // a spring of rest length 1 stretched to 2 pulls both points together, symmetrically
    const Vec3Object& a = engine_state(*s, 0);
    const Vec3Object& b = engine_state(*s, 1);
    EXPECT_GT(a.velocity[0].x(), 0.0);
    EXPECT_NEAR(a.velocity[0].x(), -b.velocity[0].x(), 1e-14);
    EXPECT_THAT(error_of(with(xml, R"(object2="@B/b")", R"(object2="@B/nothing")")), HasSubstr("SpringForceField"));
}

}  // namespace
