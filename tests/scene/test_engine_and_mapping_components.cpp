// The data engines (TransformEngine, TransformPosition, MergePoints), the selection engines
// (MeshROI, ProximityROI, ValuesFromPositions), the frame mappings (SkinningMapping,
// DeformableOnRigidFrameMapping, DistanceFromTargetMapping), a mass on a mapped state, springs
// between two nodes' states, Data links to values and broken Data links, built from scenes made
// here; bad attributes are errors naming the file, line, component and attribute.
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

using namespace penalty;
using ::testing::HasSubstr;

using penalty::test::build;
using penalty::test::error_of;

const Vec3Object& engine_state(const scene::Scene& s, std::size_t i = 0) {
    return dynamic_cast<const Vec3Object&>(*s.states()[i].state);
}

std::string with(std::string xml, const std::string& what, const std::string& by) {
    xml.replace(xml.find(what), what.size(), by);
    return xml;
}

// A state whose positions come from a data engine defined before it (or after it: SOFA's engines
// are evaluated when read).
const std::string kEngineScene = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    ENGINE
    <MechanicalObject name="dofs" position="@engine.output_position"/>
    <UniformMass vertexMass="1"/>
  </Node>
</Node>)";

TEST(DataEngineComponents, TransformEngineFeedsAStateScaledRotatedTranslated) {
    auto s = build(with(
        kEngineScene, "ENGINE",
        R"(<TransformEngine name="engine" input_position="0 0 0  1 0 0  0 2 0" scale="2 1 1" rotation="0 0 90" translation="5 0 0"/>)"));
    const Vec3Object& x = engine_state(*s);
    ASSERT_EQ(x.position.size(), 3u);
    EXPECT_NEAR((x.position[1] - Vec3(5, 2, 0)).norm(), 0, 1e-15);  // (1,0,0) → (2,0,0) → (0,2,0) → +5 x
    EXPECT_NEAR((x.position[2] - Vec3(3, 0, 0)).norm(), 0, 1e-15);
    EXPECT_EQ(x.position[0], Vec3(5, 0, 0));
}

TEST(DataEngineComponents, AnEngineAfterItsReaderIsBuiltWhenRead) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="@merge.points"/>
    <UniformMass vertexMass="1"/>
    <MergePoints name="merge" position1="0 0 0  1 1 1" position2="7 7 7"/>
  </Node>
</Node>)";
    auto s = build(xml);
    const Vec3Object& x = engine_state(*s);
    ASSERT_EQ(x.position.size(), 3u);
    EXPECT_EQ(x.position[2], Vec3(7, 7, 7));
}

TEST(DataEngineComponents, TransformPositionMethodsAndErrors) {
    auto s = build(with(
        kEngineScene, "ENGINE",
        R"(<TransformPosition name="engine" method="translation" translation="0 0 3" input_position="1 2 3  4 5 6" fixedIndices="1"/>)"));
    EXPECT_EQ(engine_state(*s).position[0], Vec3(1, 2, 6));
    EXPECT_EQ(engine_state(*s).position[1], Vec3(4, 5, 6));
    const std::string bad = error_of(
        with(kEngineScene, "ENGINE", R"(<TransformPosition name="engine" method="warp" input_position="1 2 3"/>)"));
    EXPECT_THAT(bad, HasSubstr("test.scn:3: TransformPosition 'engine': attribute 'method': unknown method 'warp'"));
    const std::string file = error_of(
        with(kEngineScene, "ENGINE",
             R"(<TransformPosition name="engine" method="fromFile" filename="no_such.tfm" input_position="1 2 3"/>)"));
    EXPECT_THAT(file, HasSubstr("TransformPosition 'engine': attribute 'filename'"));
    const std::string rigid = error_of(
        with(kEngineScene, "ENGINE", R"(<TransformEngine name="engine" template="Rigid3" input_position="1 2 3"/>)"));
    EXPECT_THAT(rigid, HasSubstr("TransformEngine 'engine': template 'Rigid3' is not supported"));
}

// A unit cube surface (the ROI mesh) and points inside and outside it.
const std::string kMeshRoi = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0.2 0.3 0.45  2 2 2  0.7 0.1 0.9  -0.3 0.5 0.5"/>
    <UniformMass vertexMass="1"/>
    <MeshROI name="roi" ROIposition="0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1"
             ROItriangles="0 2 3 0 3 1 4 5 7 4 7 6 0 1 5 0 5 4 2 6 7 2 7 3 0 4 6 0 6 2 1 3 7 1 7 5" ATTR/>
    <FixedProjectiveConstraint indices="@roi.indices"/>
  </Node>
</Node>)";

TEST(SelectionEngineComponents, MeshRoiSelectsThePointsInsideTheMesh) {
    auto s = build(with(kMeshRoi, "ATTR", ""));
    EXPECT_THAT(s->role(*s->file().root->children[0]->components[4]), HasSubstr("selects 2 of 4 points"));
    const std::string plain = with(kMeshRoi, "ATTR", "");
    EXPECT_THAT(error_of(with(plain, R"(ROIposition="0 0 0 1 0 0)", R"(ROIposition="0 0 0 1 0)")),
                HasSubstr("test.scn:5: MeshROI 'roi': attribute 'ROIposition': expected a multiple of 3 numbers"));
    const std::string outside = error_of(with(plain, R"(ROItriangles="0 2 3)", R"(ROItriangles="0 2 30)"));
    EXPECT_THAT(outside, HasSubstr("test.scn:5: MeshROI 'roi': ROI triangle 0 uses point 30"));
}

TEST(SelectionEngineComponents, ProximityRoiKeepsTheNearestPointsAndRefusesANegativeCount) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 -1 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 0 0  0.1 0 0  0.2 0 0  0.3 0 0  3 0 0"/>
    <UniformMass vertexMass="1"/>
    <ProximityROI name="roi" centers="0 0 0" radii="1" N="2"/>
    <FixedProjectiveConstraint indices="@roi.indices"/>
  </Node>
</Node>)";
    auto s = build(xml);
    s->step();
    const Vec3Object& x = engine_state(*s);
    EXPECT_EQ(x.position[0], Vec3(0, 0, 0));  // the two nearest are fixed
    EXPECT_EQ(x.position[1], Vec3(0.1, 0, 0));
    EXPECT_LT(x.position[2].y(), 0.0);  // the others fall
    EXPECT_THAT(error_of(with(xml, R"(N="2")", R"(N="-2")")),
                HasSubstr("test.scn:5: ProximityROI 'roi': attribute 'N': must be >= 0"));
}

// A rigid frame carrying mapped points that have a mass: the frame (1 kg) and 4 points (0.5 kg
// each) fall together under gravity, the points' mass acting through the mapping (Jᵀ M J).
const std::string kMappedMass = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Body"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="50" tolerance="1e-14" threshold="1e-30"/>
    <MechanicalObject template="Rigid3" name="frame" position="0 0 0 0 0 0 1"/>
    <UniformMass vertexMass="1"/>
    <Node name="Points"><MechanicalObject name="points" position="1 0 0  -1 0 0  0 0 1  0 0 -1"/>
      <UniformMass vertexMass="0.5"/>
      <ConstantForceField indices="0" forces="6 0 0"/>
      <RigidMapping/>
    </Node>
  </Node>
</Node>)";

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

TEST(FrameMappingComponents, DeformableOnRigidFrameMappingCarriesTheBody) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Frame"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject template="Rigid3" name="frame" position="1 2 3 0 0 0.7071067811865476 0.7071067811865476" velocity="0 0 0 0 0 1"/>
    <UniformMass vertexMass="1"/>
    <Node name="Local"><MechanicalObject name="local" position="1 0 0  0 1 0"/><UniformMass vertexMass="1"/>
      <Node name="World"><MechanicalObject name="world"/>
        <DeformableOnRigidFrameMapping input1="@.." input2="@../../frame" output="@world"/>
      </Node>
    </Node>
  </Node>
</Node>)";
    auto s = build(xml);
    const auto* world =
        dynamic_cast<const Vec3Object*>(s->simulation().root().children()[0]->children()[0]->children()[0]->state());
    ASSERT_NE(world, nullptr);
    EXPECT_NEAR((world->position[0] - Vec3(1, 3, 3)).norm(), 0, 1e-15);   // 90° about z, then +(1, 2, 3)
    EXPECT_NEAR((world->velocity[0] - Vec3(-1, 0, 0)).norm(), 0, 1e-15);  // ω × (R·u) = z × y
    EXPECT_THAT(error_of(with(xml, R"( input2="@../../frame")", "")),
                HasSubstr("DeformableOnRigidFrameMapping: attribute 'input2': needs the frames"));
}

TEST(FrameMappingComponents, DistanceFromTargetMappingOntoAVec1State) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="3 4 0  0 0 2"/><UniformMass vertexMass="1"/>
    <Node name="distances"><MechanicalObject template="Vec1" name="d"/>
      <DistanceFromTargetMapping input="@../dofs" output="@d" targetPositions="0 0 0  0 0 0" restLengths="1" GS/>
    </Node>
  </Node>
</Node>)";
    auto s = build(with(xml, "GS", ""));
    const auto* d = dynamic_cast<const Vec1Object*>(s->simulation().root().children()[0]->children()[0]->state());
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->position, (std::vector<double>{4.0, 2.0}));  // |(3,4,0)| − 1, |(0,0,2)| − 0
    // the Vec1d state is recorded; SOFA's regression selection leaves it out (mapped)
    ASSERT_EQ(s->states().size(), 2u);
    EXPECT_EQ(output::select_exported_states(s->states(), false).size(), 1u);
    ASSERT_EQ(output::select_exported_states(s->states(), true).size(), 2u);
    EXPECT_EQ(output::format_positions(*s->states()[1].state), "4 2");
    s->step();
    EXPECT_THAT(
        error_of(with(xml, "GS", R"(geometricStiffness="Sometimes")")),
        HasSubstr("DistanceFromTargetMapping: attribute 'geometricStiffness': expected None, Exact or Stabilized"));
}

TEST(FrameMappingComponents, SkinningMappingFollowsTheFrames) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Frames"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject template="Rigid3" name="frames" position="0 0 0 0 0 0 1  4 0 0 0 0 0 1" velocity="1 0 0 0 0 0  1 0 0 0 0 0"/>
    <UniformMass vertexMass="1"/>
    <Node name="Skin"><MechanicalObject name="skin" position="1 0 0  3 1 0"/>
      <SkinningMapping nbRef="2" WEIGHTS/>
    </Node>
  </Node>
</Node>)";
    auto s = build(with(xml, "WEIGHTS", ""));
    s->step();
    const auto* skin = dynamic_cast<const Vec3Object*>(s->simulation().root().children()[0]->children()[0]->state());
    ASSERT_NE(skin, nullptr);
    // both frames translate by 0.01 in x: every skinned point follows (weights sum to 1)
    EXPECT_NEAR((skin->position[0] - Vec3(1.01, 0, 0)).norm(), 0, 1e-14);
    EXPECT_NEAR((skin->position[1] - Vec3(3.01, 1, 0)).norm(), 0, 1e-14);
    EXPECT_THAT(error_of(with(xml, "WEIGHTS", R"(indices="[0 1] [1]" weight="[0.5 0.5] [1 0]")")),
                HasSubstr("SkinningMapping: attribute 'weight': point 1: one weight per index"));
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
