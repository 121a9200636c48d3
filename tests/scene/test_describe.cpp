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
#include <limits>
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

TEST(SceneBuilder, DescribeCountsThePairsPastItsLinesByKind) {
    // 25 sphere models, one node each under a solver node, and a static plane: 25·24/2 = 300
    // sphere pairs (self pairs dropped: no selfCollision) + 25 with the plane. The first 200
    // pairs get a line; the others are counted by types and outcome.
    std::string spheres;
    for (int i = 0; i < 25; ++i)
        spheres += "<Node name=\"S" + std::to_string(i) + "\"><MechanicalObject position=\"" + std::to_string(i) +
                   " 0 0\"/><UniformMass totalMass=\"1\"/><SphereCollisionModel radius=\"0.1\"/></Node>\n";
    const auto s = build(R"(<Node name="root">
  <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
  <NewProximityIntersection alarmDistance="0.2" contactDistance="0.1"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Balls"><EulerImplicitSolver/><CGLinearSolver/>
)" + spheres + R"(  </Node>
  <Node name="Plane"><MeshTopology position="0 -1 0  1 -1 0  0 -1 1" triangles="0 1 2"/><MechanicalObject/>
    <TriangleCollisionModel simulated="0" moving="0"/></Node>
</Node>)");
    const std::string text = scene::describe_scene(*s);
    const auto lines_with = [&](const std::string& what) {
        std::size_t n = 0;
        for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(lines_with(": penalty contact in /"), 200u);
    EXPECT_THAT(text, HasSubstr("  ... and 125 more model pairs (`penalty info --all-pairs` lists each):\n"));
    EXPECT_THAT(text, HasSubstr("  325 model pairs kept by the broad phase, 325 can make penalty contacts"));
    const std::string all = scene::describe_scene(*s, std::numeric_limits<std::size_t>::max());
    std::size_t every = 0;
    for (std::size_t at = all.find(": penalty contact in /"); at != std::string::npos;
         at = all.find(": penalty contact in /", at + 1))
        ++every;
    EXPECT_EQ(every, 325u);
    EXPECT_THAT(all, Not(HasSubstr("more model pairs")));
    // the counted pairs add up, each kind once: "N × Type - Type: outcome"
    std::size_t counted = 0;
    for (const std::string kind :
         {"Sphere - Sphere: penalty contact, implicit", "Sphere - Sphere: penalty contact, explicit",
          "Triangle - Sphere: penalty contact, implicit", "Triangle - Sphere: penalty contact, explicit"}) {
        const std::size_t at = text.find(" \u00d7 " + kind + "\n");
        if (at == std::string::npos) continue;
        const std::size_t line = text.rfind('\n', at) + 1;
        counted += std::stoul(text.substr(line, at - line));
    }
    EXPECT_EQ(counted, 125u);
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
