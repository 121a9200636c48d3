// `penalty info`'s description of a built scene (scene/describe.cpp): what each component became,
// where contacts go, undetected pairs, disabled responses and explicit contacts.
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

TEST(SceneBuilder, DescribeShowsWhatEachComponentBecameAndWhereContactsGo) {
    const auto s = build(kCubeOnFloor);
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text, HasSubstr("Node / (root): dt 0.01 s, gravity (0, -9.81, 0) m/s^2\n"));
    EXPECT_THAT(text, HasSubstr("  Node /Cube\n"));  // dt and gravity inherited: not repeated
    EXPECT_THAT(text,
                HasSubstr("Vec3d state, 8 DOFs, translated (0.3, 0.15, 0.1); integrated by the ODE solver of /Cube\n"));
    EXPECT_THAT(text, HasSubstr("8 points, 12 edges, 6 quads, 1 hexahedron\n"));
    EXPECT_THAT(text, HasSubstr("mass 0.125 kg per DOF, 1 kg in all\n"));
    // 12 edges + 12 face diagonals + 4 cell diagonals of the hexahedron
    EXPECT_THAT(text, HasSubstr("28 springs between the topology's vertex pairs"));
    EXPECT_THAT(text,
                HasSubstr("implicit Euler over this subtree (8 DOFs in 1 state), Rayleigh stiffness 0.1 mass 0.1\n"));
    EXPECT_THAT(text, HasSubstr("at most 25 iterations, tolerance 1e-09, threshold 1e-09\n"));
    EXPECT_THAT(text, HasSubstr("Vec3d state, 4 DOFs; static: in no solver's subtree, never moves\n"));
    EXPECT_THAT(
        text,
        HasSubstr(
            "2 triangles, static obstacle (simulated=0, moving=0), contactStiffness 10; pipeline CollisionPipeline\n"));
    EXPECT_THAT(text, HasSubstr("collision pipeline: MinProximity (alarm 0.2 m, contact 0.1 m), 2 collision models, "
                                "response PenalityContactForceField\n"));
    EXPECT_THAT(text, HasSubstr("  floor_triangles (Triangle, /Floor) - cube_points (Point, /Cube): penalty contact in "
                                "/Cube, implicit (solver of /Cube)\n"));
    EXPECT_THAT(
        text,
        HasSubstr(
            "  1 model pair kept by the broad phase, 1 can make penalty contacts; 1 excluded (both non-simulated); "
            "1 excluded (same node without selfCollision)\n"));
}

TEST(SceneBuilder, DescribeNamesUndetectedPairsDisabledResponsesAndExplicitContacts) {
    const auto s = build(R"(<Node name="root">
  <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.2" contactDistance="0.1"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <RequiredPlugin name="plugins"/>
  <Node name="A"><EulerImplicitSolver/><CGLinearSolver/>
    <MeshTopology position="0 0 0  1 0 0  0 1 0" triangles="0 1 2"/><MechanicalObject/><UniformMass totalMass="1"/>
    <TriangleCollisionModel name="ta"/><PointCollisionModel name="pa" contactResponse="nullptr"/></Node>
  <Node name="B"><Gravity gravity="0 0 -1"/><EulerImplicitSolver/><CGLinearSolver/>
    <MeshTopology position="0 0 1  1 0 1  0 1 1" triangles="0 1 2"/><MechanicalObject/><UniformMass totalMass="1"/>
    <TriangleCollisionModel name="tb"/><PointCollisionModel name="pb"/></Node>
</Node>)");
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text, HasSubstr("  Node /B: gravity (0, 0, -1) m/s^2\n"));
    EXPECT_THAT(text, HasSubstr("RequiredPlugin 'plugins'"));
    EXPECT_THAT(text, HasSubstr("ignored (plugin loading)\n"));
    EXPECT_THAT(text,
                HasSubstr("  ta (Triangle, /A) - tb (Triangle, /B): not detected: MinProximity ignores this pair"));
    EXPECT_THAT(text,
                HasSubstr("  ta (Triangle, /A) - pb (Point, /B): penalty contact in /, explicit (no solver above it"));
    EXPECT_THAT(text, HasSubstr("  tb (Triangle, /B) - pa (Point, /A): detected; no response (nullptr): no contact\n"));
    EXPECT_THAT(text, HasSubstr("  pa (Point, /A) - pb (Point, /B): detected; no response (nullptr): no contact\n"));
    EXPECT_THAT(text, HasSubstr("  4 model pairs kept by the broad phase, 1 can make penalty contacts; 6 excluded "
                                "(same node without selfCollision)\n"));
    EXPECT_THAT(text, HasSubstr(" physics components, 0 loaders, 1 ignored\n"));
}

}  // namespace
