// The scene builder: what each SOFA component becomes, error messages on bad scenes, the
// built-in scene, and SOFA's regression reference for CompositeCollisionPipeline_none.scn.
#include "builder_scenes.hpp"
#include "penalty/io/error.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using namespace penalty::test_builder_scenes;
using namespace penalty;

using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

TEST(SceneBuilder, CubeOnFloorStatesRecordsAndContactPlacement) {
    auto s = build(kCubeOnFloor);
    ASSERT_EQ(s->states().size(), 2u);
    EXPECT_EQ(s->states()[0].node_path, "/Cube");
    EXPECT_EQ(s->states()[0].name, "cube");
    EXPECT_TRUE(s->states()[0].in_solver_subtree);
    EXPECT_FALSE(s->states()[0].mapped);
    EXPECT_NE(s->states()[0].mass, nullptr);
    EXPECT_EQ(s->states()[1].node_path, "/Floor");
    EXPECT_FALSE(s->states()[1].in_solver_subtree);
    // dy = 0.15 moved every point up, by 0.15 rounded to float as SOFA reads the short forms.
    const auto& cube = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    EXPECT_EQ(cube.position[0].y(), double(0.15f));
    EXPECT_EQ(cube.position[0].x(), double(0.3f));
    EXPECT_EQ(cube.position[7].y(), 1.0 + double(0.15f));
    ASSERT_EQ(s->pipelines().size(), 1u);
    EXPECT_EQ(s->pipelines()[0].intersection, IntersectionMethod::MinProximity);
    EXPECT_DOUBLE_EQ(s->pipelines()[0].pipeline->intersection().alarm_distance, 0.2);

    s->step();  // the 4 bottom points are within the alarm distance 0.2 of the floor
    const auto& entries = s->pipelines()[0].pipeline->graph_entries();
    ASSERT_EQ(entries.size(), 1u);
    // Static floor vs simulated cube: the force field is stored in the cube's node (implicit).
    EXPECT_EQ(entries[0].host->name(), "Cube");
    const auto contacts = s->contacts();
    ASSERT_EQ(contacts.size(), 1u);
    EXPECT_EQ(contacts[0].name, "floor_triangles-cube_points");
    EXPECT_EQ(contacts[0].field->size(), 4u);

    // The cube settles on the floor: after 2 s it rests with its bottom at the contact distance
    // minus the static penetration (k = 10·10/0.1 = 1000 N/m per contact, weight 9.81 N over
    // 4 contacts: mg/4k = 2.45 mm).
    scene::RunOptions run;
    run.steps = 200;
    const auto summary = scene::run_scene(*s, run);
    EXPECT_EQ(summary.steps, 200);
    EXPECT_NEAR(summary.simulated_time, 2.01, 1e-9);  // after the first step above
    for (int i : {0, 1, 4, 5}) EXPECT_NEAR(cube.position[std::size_t(i)].y(), 0.1 - 9.81 / 4000.0, 1e-6);
    EXPECT_LT(s->kinetic_energy(), 1e-3);
}

TEST(SceneBuilder, BothSimulatedContactGoesToThePipelineNodeAndIsExplicit) {
    // Two spheres, one solver each: the contact is stored at the root (no solver) → explicit.
    const std::string xml = R"(<Node name="root" gravity="0 0 0">
      <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
      <NewProximityIntersection alarmDistance="0.5" contactDistance="0.1"/>
      <CollisionResponse response="PenalityContactForceField"/>
      <Node name="A"><EulerImplicitSolver/><CGLinearSolver/>
        <MechanicalObject position="0 0 0" velocity="1 0 0"/><UniformMass totalMass="1"/>
        <SphereCollisionModel name="a" radius="0.5"/></Node>
      <Node name="B"><EulerImplicitSolver/><CGLinearSolver/>
        <MechanicalObject position="1.2 0 0"/><UniformMass totalMass="1"/>
        <SphereCollisionModel name="b" radius="0.5"/></Node>
    </Node>)";
    auto s = build(xml);
    s->step();
    const auto& entries = s->pipelines()[0].pipeline->graph_entries();
    ASSERT_EQ(entries.size(), 1u);
    EXPECT_EQ(entries[0].host, &s->simulation().root());
    // Momentum is conserved by the explicit exchange: m v_A + m v_B = 1 after any number of steps.
    for (int i = 0; i < 50; ++i) s->step();
    const auto& a = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    const auto& b = dynamic_cast<const Vec3Object&>(*s->states()[1].state);
    EXPECT_NEAR(a.velocity[0].x() + b.velocity[0].x(), 1.0, 1e-12);
    EXPECT_LT(a.velocity[0].x(), 0.5);  // the spheres pushed each other
}

// SOFA's regular-grid mapper (BarycentricMapperRegularGridTopology::init) locates the output's
// positions with RegularGridTopology::findCube / findNearestCube, i.e. in the grid's written
// coordinates, while MechanicalObject::init moves the grid's copied positions by `translation`.
TEST(SceneBuilder, RegularGridStateAndBarycentricSurface) {
    const std::string xml = R"(<Node name="root">
      <Node name="Grid"><EulerImplicitSolver/><CGLinearSolver/>
        <RegularGridTopology nx="3" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="1" zmin="0" zmax="1"/>
        <MechanicalObject name="grid" translation="10 0 0"/>
        <UniformMass vertexMass="0.5"/>
        <RegularGridSpringForceField stiffness="100"/>
        <Node name="Surface">
          <MechanicalObject name="surface" position="0.5 0.5 0.5  1.5 0.25 0.75  2.5 0.5 -0.5" />
          <BarycentricMapping/>
        </Node>
        <Node name="Moved">
          <MechanicalObject name="moved" position="0.5 0.5 0.5" translation="10 0 0"/>
          <BarycentricMapping/>
        </Node>
      </Node>
    </Node>)";
    auto s = build(xml);
    ASSERT_EQ(s->states().size(), 3u);
    const auto& grid = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    ASSERT_EQ(grid.position.size(), 12u);
    EXPECT_DOUBLE_EQ(grid.position[0].x(), 10.0);
    EXPECT_DOUBLE_EQ(grid.position[2].x(), 12.0);
    EXPECT_TRUE(s->states()[1].mapped);
    EXPECT_TRUE(s->states()[1].in_solver_subtree);
    const auto& surface = dynamic_cast<const Vec3Object&>(*s->states()[1].state);
    // Written in the grid's coordinates: the points follow the translated grid. The third lies
    // outside the grid: nearest cell, extrapolated weights, which reproduce the affine motion.
    EXPECT_NEAR((surface.position[0] - Vec3(10.5, 0.5, 0.5)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((surface.position[1] - Vec3(11.5, 0.25, 0.75)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((surface.position[2] - Vec3(12.5, 0.5, -0.5)).norm(), 0.0, 1e-12);
    // A surface given the grid's translation itself is moved twice, as in SOFA.
    const auto& moved = dynamic_cast<const Vec3Object&>(*s->states()[2].state);
    EXPECT_NEAR((moved.position[0] - Vec3(20.5, 0.5, 0.5)).norm(), 0.0, 1e-12);
    // Free fall of the grid carries the surface: after one implicit step both moved by g·h².
    s->step();
    EXPECT_NEAR(surface.position[0].y(), 0.5 - 9.81 * 0.01 * 0.01, 1e-9);
}

TEST(SceneBuilder, RigidBodyWithIdentityMappedCollisionSphere) {
    const std::string xml = R"(<Node name="root" dt="0.01">
      <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="250" tolerance="1e-9" threshold="1e-9"/>
        <MechanicalObject name="rigid" template="Rigid3d" position="1 2 3 0 0 0 1"/>
        <UniformMass totalMass="2"/>
        <Node name="Collision"><MechanicalObject name="points"/>
          <SphereCollisionModel radius="0.5"/><IdentityMapping input="@../rigid" output="@points"/></Node>
      </Node>
    </Node>)";
    auto s = build(xml);
    ASSERT_EQ(s->states().size(), 2u);
    EXPECT_EQ(s->states()[1].node_path, "/Body/Collision");
    EXPECT_TRUE(s->states()[1].mapped);
    const auto& pts = dynamic_cast<const Vec3Object&>(*s->states()[1].state);
    ASSERT_EQ(pts.position.size(), 1u);
    EXPECT_EQ(pts.position[0], Vec3(1, 2, 3));
    // The sphere model's radius per DOF goes to the VTK writer; the rigid frame has no sphere.
    EXPECT_EQ(s->states()[1].radius, std::vector<double>{0.5});
    EXPECT_TRUE(s->states()[0].radius.empty());
    // Only the unmapped state of a solver subtree is exported (SOFA's regression selection).
    const auto exported = output::select_exported_states(s->states(), false);
    ASSERT_EQ(exported.size(), 1u);
    EXPECT_EQ(exported[0]->name, "rigid");
}

TEST(SceneBuilder, IncompletePipelineAndUnreadAttributesAreReported) {
    const std::string xml = R"(<Node name="root">
      <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
      <CollisionResponse/>
      <VisualStyle displayFlags="showAll"/>
      <Node name="A"><EulerImplicitSolver fancyOption="3"/><CGLinearSolver/>
        <MechanicalObject position="0 0 0"/><UniformMass vertexMass="1"/></Node>
    </Node>)";
    auto s = build(xml);
    EXPECT_TRUE(s->pipelines().empty());
    const auto w = s->warnings();
    EXPECT_THAT(w,
                ::testing::Contains(HasSubstr("ignored 1 component that does not change the numbers: VisualStyle x1")));
    EXPECT_THAT(w, ::testing::Contains(HasSubstr("test.scn:2: CollisionPipeline: no contact will be detected")));
    EXPECT_THAT(w, ::testing::Contains(
                       "test.scn:5: EulerImplicitSolver: attribute 'fancyOption' is not read by penalty (ignored)"));
}

TEST(SceneBuilder, ComponentsSofaNoLongerKnowsAreDroppedAsSofaDoes) {
    // SOFA HEAD has no CGImplicit (nor CGImplicitSolver, PlaneConstraint, BoxConstraint): its
    // factory creates nothing and the scene runs without it. Here the node then has no ODE
    // solver, so its point does not move, as in SOFA.
    auto s = build(R"(<Node name="root">
      <Node name="A"><CGImplicit iterations="40"/><PlaneConstraint plane="0 1 0 0"/>
        <MechanicalObject position="0 1 0"/><UniformMass vertexMass="1"/></Node>
    </Node>)");
    EXPECT_THAT(s->warnings(), ::testing::Contains(HasSubstr(
                                   "ignored 2 components that do not change the numbers: CGImplicit (unknown to SOFA, "
                                   "which drops it) x1, PlaneConstraint (unknown to SOFA, which drops it) x1")));
    for (int i = 0; i < 10; ++i) s->step();
    EXPECT_EQ(dynamic_cast<const Vec3Object&>(*s->states().front().state).position[0], Vec3(0, 1, 0));
}

TEST(SceneBuilder, PositionsLinkedFromATopologyOrAState) {
    auto s = build(R"(<Node name="root">
      <Node name="A"><MeshTopology name="topo" position="0 0 0  1 0 0  0 1 0" triangles="0 1 2"/>
        <MechanicalObject name="a" position="@topo.position" translation="0 0 1"/></Node>
      <Node name="B"><MechanicalObject name="b" position="@../A/a.position" scale="2"/></Node>
    </Node>)");
    const auto& a = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    const auto& b = dynamic_cast<const Vec3Object&>(*s->states()[1].state);
    ASSERT_EQ(a.position.size(), 3u);
    EXPECT_EQ(a.position[1], Vec3(1, 0, 1));
    ASSERT_EQ(b.position.size(), 3u);
    EXPECT_EQ(b.position[1], Vec3(2, 0, 2));  // a's transformed positions, scaled by 2
}

TEST(SceneBuilder, MechanicalObjectShortFormsAreReadAsFloatsAsSofaDoes) {
    // MechanicalObject::parse reads dx dy dz, rx ry rz, scale, sx sy sz with
    // getAttributeAsFloat (strtof): scale="0.7" scales by 0.699999988079071, dx="0.1" moves by
    // 0.100000001490116. The long forms (translation, rotation, scale3d) are doubles.
    const std::string xml = R"(<Node name="root">
      <Node name="A"><MechanicalObject name="a" position="1 2 3" scale="0.7" dx="0.1"/></Node>
      <Node name="B"><MechanicalObject name="b" position="1 2 3" scale3d="0.7 0.7 0.7" translation="0.1 0 0"/></Node>
      <Node name="C"><MechanicalObject name="c" position="1 2 3" scale3d="5 5 5" sy="0.7" rotation="0 0 90" rx="0"
                                        translation="9 9 9" dz="0.1"/></Node>
    </Node>)";
    const double s = double(0.7f), t = double(0.1f);
    ASSERT_NE(s, 0.7);
    ASSERT_NE(t, 0.1);
    auto sofa = build(xml);
    const auto& a = dynamic_cast<const Vec3Object&>(*sofa->states()[0].state).position[0];
    const auto& b = dynamic_cast<const Vec3Object&>(*sofa->states()[1].state).position[0];
    const auto& c = dynamic_cast<const Vec3Object&>(*sofa->states()[2].state).position[0];
    EXPECT_EQ(a, Vec3(1 * s + t, 2 * s, 3 * s));
    EXPECT_EQ(b, Vec3(1 * 0.7 + 0.1, 2 * 0.7, 3 * 0.7));
    // any of sx sy sz replaces scale3d (missing: 1), any of rx ry rz the rotation (missing: 0,
    // so the 90° about z is gone), any of dx dy dz the translation (missing: 0)
    EXPECT_EQ(c, Vec3(1, 2 * s, 3 + t));
    // the fix: the short forms in double, as the long forms
    scene::BuildOptions fixed;
    ASSERT_TRUE(enable_sofa_quirk_fix(fixed.sofa_quirk_fixes, "mechanical_object_float_short_forms"));
    auto in_double = build(xml, fixed);
    EXPECT_EQ(dynamic_cast<const Vec3Object&>(*in_double->states()[0].state).position[0], b);
    EXPECT_EQ(dynamic_cast<const Vec3Object&>(*in_double->states()[2].state).position[0], Vec3(1, 2 * 0.7, 3 + 0.1));
    // a value beyond float range is an error naming the attribute, not an infinite position
    EXPECT_THAT(error_of(R"(<Node name="root"><MechanicalObject position="1 2 3" dy="1e39"/></Node>)"),
                HasSubstr("'dy'"));
    EXPECT_THAT(error_of(R"(<Node name="root"><MechanicalObject position="1 2 3" dy="1e39"/></Node>)"),
                HasSubstr("beyond float range"));
}

TEST(SceneBuilder, ErrorsNameFileLineComponentAndAttribute) {
    EXPECT_EQ(error_of(R"(<Node name="root">
  <FancyForceField/>
</Node>)"),
              "test.scn:2: unknown component 'FancyForceField' (not supported by penalty)");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject position="0 0 0"/>
  <UniformMass name="m"/>
</Node>)"),
              "test.scn:3: UniformMass 'm': needs vertexMass or totalMass (SOFA refuses a UniformMass without them)");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject position="0 0 0"/>
  <SphereCollisionModel name="s" contactStiffness="-1"/>
</Node>)"),
              "test.scn:3: SphereCollisionModel 's': attribute 'contactStiffness': must be >= 0, found '-1'");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject template="Vec2d" position="0 0"/>
</Node>)"),
              "test.scn:2: MechanicalObject: template 'Vec2d' is not supported (Vec3d or Rigid3d)");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject position="0 0 0  1 0 0"/>
  <TriangleCollisionModel/>
</Node>)"),
              "test.scn:3: TriangleCollisionModel: needs a topology (MeshTopology or RegularGridTopology) in its node "
              "or an ancestor "
              "node");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MinProximityIntersection alarmDistance="0.1" contactDistance="0.5"/>
  <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/><CollisionResponse/>
</Node>)"),
              "test.scn:2: MinProximityIntersection: attribute 'contactDistance': must not exceed alarmDistance");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject position="0 0 0"/>
  <FixedProjectiveConstraint indices="0 3"/>
</Node>)"),
              "test.scn:3: FixedProjectiveConstraint: attribute 'indices': index 3 out of range (1 DOFs)");
    EXPECT_EQ(error_of(R"(<Node name="root" dt="-0.1"/>)"), "test.scn:1: Node 'root': attribute 'dt': must be > 0");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject position="0 0 0"/>
  <MechanicalObject position="0 0 0"/>
</Node>)"),
              "test.scn:3: MechanicalObject: a node holds one mechanical state, and this node already has "
              "MechanicalObject at line 2");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject position="0 nan 0"/>
</Node>)"),
              "test.scn:2: MechanicalObject: attribute 'position': expected a number, found 'nan'");
    EXPECT_THAT(
        error_of(R"(<Node name="root">
  <MeshOBJLoader name="l" filename="no/such/mesh.obj"/>
  <MeshTopology src="@l"/>
</Node>)"),
        HasSubstr("test.scn:2: MeshOBJLoader 'l': attribute 'filename': cannot find data file 'no/such/mesh.obj'"));
    EXPECT_EQ(error_of(R"(<Node name="root">
  <Node name="A"><MechanicalObject position="0 0 0"/><IdentityMapping input="@../nothing"/></Node>
</Node>)"),
              "test.scn:2: IdentityMapping: attribute 'input': broken link '@../nothing': no node or component named "
              "'nothing' in node '/'");
    EXPECT_EQ(
        error_of(R"(<Node name="root">
  <MechanicalObject position="0 0 0  1 0 0  0 1 0"/>
  <MeshTopology triangles="0 1 5"/>
  <TriangleCollisionModel/>
</Node>)"),
        "test.scn:4: TriangleCollisionModel: TriangleModel 'TriangleCollisionModel': element 0: vertex index 5 out "
        "of range (state has 3 points)");
}

}  // namespace
