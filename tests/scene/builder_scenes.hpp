#pragma once
// The scenes of the scene builder's tests (test_scene_builder.cpp, test_describe.cpp, test_runner.cpp,
// test_collision_pipelines.cpp, test_default_scene.cpp): a cube on a floor, temporary folders.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <string>
#include "penalty/io/error.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

namespace penalty::test_builder_scenes {

using namespace penalty;
using penalty::scene::build_scene;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

inline std::filesystem::path temp_dir(const std::string& name) {
    const auto d =
        std::filesystem::temp_directory_path() /
        ("penalty_scene_test_" + name + "_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::remove_all(d);
    return d;
}

// A cube of 8 springs-connected points (SOFA's tutorial cube) over a static floor of 2 triangles;
// dx, dz keep the bottom points off the floor's diagonal edge x = z, where MinProximity rejects
// Triangle–Point contacts (spec §12.1).
inline const std::string kCubeOnFloor = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.2" contactDistance="0.1"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Cube">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <MechanicalObject name="cube" position="0 0 0  1 0 0  0 1 0  1 1 0  0 0 1  1 0 1  0 1 1  1 1 1" dx="0.3" dy="0.15" dz="0.1"/>
    <MeshTopology hexas="0 1 3 2 4 5 7 6"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="100" damping="1"/>
    <PointCollisionModel name="cube_points"/>
  </Node>
  <Node name="Floor">
    <MeshTopology position="-5 0 -5  5 0 -5  5 0 5  -5 0 5" triangles="0 2 1  0 3 2"/>
    <MechanicalObject name="floor"/>
    <TriangleCollisionModel name="floor_triangles" simulated="0" moving="0"/>
  </Node>
</Node>)";

}  // namespace penalty::test_builder_scenes
