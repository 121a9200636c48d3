// The collision pipelines of a scene (scene/builder/collision_pipelines.cpp): a composite pipeline runs
// each sub-pipeline with its own method; CompositeCollisionPipeline with `none` reproduces SOFA's reference.
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

TEST(SceneBuilder, CompositePipelineRunsEachSubPipelineWithItsOwnMethod) {
    const std::string xml = R"(<Node name="root">
      <Node name="A"><MechanicalObject position="0 0 0"/><SphereCollisionModel name="a" simulated="0"/></Node>
      <Node name="B"><MechanicalObject position="5 0 0"/><SphereCollisionModel name="b"/></Node>
      <BruteForceBroadPhase name="bp"/><BVHNarrowPhase name="np"/>
      <NewProximityIntersection name="i1" alarmDistance="2" contactDistance="1"/>
      <MinProximityIntersection name="i2" alarmDistance="3" contactDistance="1"/>
      <CollisionResponse name="r"/>
      <SubCollisionPipeline name="p1" collisionModels="@A/a" broadPhaseDetection="@bp" narrowPhaseDetection="@np"
        intersectionMethod="@i1" contactManager="@r"/>
      <SubCollisionPipeline name="p2" collisionModels="@B/b" broadPhaseDetection="@bp" narrowPhaseDetection="@np"
        intersectionMethod="@i2" contactManager="@r"/>
      <CompositeCollisionPipeline subCollisionPipelines="@p1 @p2"/>
    </Node>)";
    auto s = build(xml);
    ASSERT_EQ(s->pipelines().size(), 2u);
    EXPECT_EQ(s->pipelines()[0].name, "p1");
    EXPECT_EQ(s->pipelines()[0].intersection, IntersectionMethod::NewProximity);
    EXPECT_EQ(s->pipelines()[1].intersection, IntersectionMethod::MinProximity);
    EXPECT_DOUBLE_EQ(s->pipelines()[1].pipeline->intersection().alarm_distance, 3.0);
}

// SOFA's regression reference (kept outside the repository, in ../shared): two rigid spheres
// falling on fixed tori, 200 steps, compared by SOFA's criterion.
TEST(SceneBuilder, CompositeCollisionPipelineNoneReproducesSofaReference) {
    const std::filesystem::path shared = penalty::test::shared_dir();
    const auto scene_file = shared / "sofa/scenes/CompositeCollisionPipeline_none.scn";
    if (!std::filesystem::exists(scene_file)) GTEST_SKIP() << "no " << scene_file;
    scene::BuildOptions options;
    options.data_dirs.push_back(shared / "sofa");
    auto s = scene::load_scene(scene_file, options);
    scene::RunOptions run;
    run.steps = 200;
    run.states_directory = temp_dir("reference");
    const auto summary = scene::run_scene(*s, run);
    ASSERT_EQ(summary.state_files.size(), 2u);
    const auto refs = scene::reference_files(shared / "sofa/reference", scene_file, summary.state_files);
    EXPECT_EQ(refs[0].filename(), "CompositeCollisionPipeline_none.scn.reference_0_rigid_mstate.txt");
    const auto result = output::compare_with_reference(refs, summary.state_files, summary.values_per_dof);
    EXPECT_TRUE(result.messages.empty()) << result.messages.front();
    EXPECT_TRUE(result.passed());
    // The reference holds 6 significant digits: 5.7e-6 is its rounding, far below SOFA's 1e-4.
    EXPECT_LT(result.mean_error, 2e-5);
    EXPECT_GT(summary.max_contacts, 0u);
    std::filesystem::remove_all(*run.states_directory);
}

}  // namespace
