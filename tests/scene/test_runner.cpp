// The run loop (scene/runner.cpp): states written every M steps plus the last, CG and Newton
// iterations reported, a divergence stops the run naming state and step.
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

TEST(SceneBuilder, RunnerWritesStatesEveryMStepsPlusTheLast) {
    auto s = build(kCubeOnFloor);
    scene::RunOptions run;
    run.steps = 8;
    run.export_every = 3;
    run.states_directory = temp_dir("every");
    run.stats_file = *run.states_directory / "stats.csv";
    const auto summary = scene::run_scene(*s, run);
    ASSERT_EQ(summary.state_files.size(), 1u);  // the floor is outside every solver subtree
    EXPECT_EQ(summary.state_files[0].filename(), "0_cube_mstate.txt");
    const auto samples = output::read_state_file(summary.state_files[0]);
    ASSERT_EQ(samples.size(), 4u);  // steps 0, 3, 6 and the last, 7: T = 0, 0.03, 0.06, 0.07
    EXPECT_DOUBLE_EQ(samples[0].time, 0.0);
    EXPECT_NEAR(samples[1].time, 0.03, 1e-12);
    EXPECT_NEAR(samples[2].time, 0.06, 1e-12);
    EXPECT_NEAR(samples[3].time, 0.07, 1e-12);
    EXPECT_EQ(samples[0].x.size(), 24u);
    EXPECT_EQ(samples[0].x[1], double(0.15f));  // dy="0.15", read as a float as SOFA reads it
    std::filesystem::remove_all(*run.states_directory);
}

TEST(SceneBuilder, RunnerReportsCgAndNewtonIterations) {
    // Two free particles, one solver each; B runs Newton. Free fall is linear: CG on the
    // diagonal system M dv = h f is exact after one update, and stops when iteration 2 finds a
    // zero residual; SOFA's nb_iter counts the iterations started, so 2 per solve, 4 per step.
    // Newton meets its tolerance at its second iterate (the first update is exact).
    const std::string xml = R"(<Node name="root" dt="0.01">
      <Node name="A"><EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-30"/>
        <MechanicalObject name="a" position="0 0 0"/><UniformMass vertexMass="1"/></Node>
      <Node name="B"><EulerImplicitSolver newton="1" newtonIterations="5"/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-30"/>
        <MechanicalObject name="b" position="1 0 0"/><UniformMass vertexMass="1"/></Node>
    </Node>)";
    auto s = build(xml);
    EXPECT_TRUE(s->uses_cg());
    EXPECT_TRUE(s->uses_newton());
    scene::RunOptions run;
    run.steps = 4;
    run.stats_file = temp_dir("solver_stats") / "stats.csv";
    const auto summary = scene::run_scene(*s, run);
    EXPECT_TRUE(summary.cg);
    EXPECT_TRUE(summary.newton);
    EXPECT_EQ(s->last_solver_stats().newton_iterations, 2);
    EXPECT_FALSE(s->last_solver_stats().newton_unconverged);
    EXPECT_EQ(s->last_solver_stats().cg_iterations, 4);
    EXPECT_FALSE(s->last_solver_stats().cg_limit_reached);
    EXPECT_DOUBLE_EQ(summary.mean_newton_iterations, 2.0);
    EXPECT_EQ(summary.max_cg_iterations, 4);
    EXPECT_EQ(summary.cg_limit_steps, 0);
    EXPECT_EQ(summary.newton_unconverged_steps, 0);
    const std::string text = scene::format_summary(summary);
    EXPECT_THAT(text, HasSubstr("CG iterations per step: mean 4.0, max 4; iteration limit reached in 0 steps\n"));
    EXPECT_THAT(text, HasSubstr("Newton iterations per step: mean 2.00, max 2; not converged in 0 steps\n"));
    std::ifstream csv(*run.stats_file);
    std::string header, row;
    std::getline(csv, header);
    std::getline(csv, row);
    EXPECT_TRUE(header.ends_with(",cg_iterations,newton_iterations")) << header;
    EXPECT_TRUE(row.ends_with(",4,2")) << row;
    // A CG limit of 1 iteration on a coupled system is reached and counted.
    auto stiff = build(R"(<Node name="root" dt="0.01">
      <Node name="A"><EulerImplicitSolver/><CGLinearSolver iterations="1" tolerance="1e-12" threshold="1e-30"/>
        <MechanicalObject name="a" position="0 0 0  1 0 0  0 1 0"/><MeshTopology triangles="0 1 2"/>
        <UniformMass vertexMass="1"/><MeshSpringForceField stiffness="100"/></Node>
    </Node>)");
    run.steps = 3;
    run.stats_file.reset();
    const auto limited = scene::run_scene(*stiff, run);
    EXPECT_EQ(limited.cg_limit_steps, 3);
    EXPECT_FALSE(limited.newton);
    EXPECT_THAT(scene::format_summary(limited), ::testing::Not(HasSubstr("Newton")));
    std::filesystem::remove_all(run.stats_file ? run.stats_file->parent_path() : temp_dir("solver_stats"));
}

TEST(SceneBuilder, DivergenceStopsTheRunNamingStateAndStep) {
    // A spring far too stiff for explicit Euler: the positions blow up to inf/NaN.
    const std::string xml = R"(<Node name="root" dt="0.1" gravity="0 0 0">
      <Node name="A"><EulerExplicitSolver/>
        <MechanicalObject name="p" position="0 0 0  1.5 0 0" rest_position="0 0 0  1 0 0"/><MeshTopology edges="0 1"/>
        <UniformMass vertexMass="0.001"/><MeshSpringForceField stiffness="1e6"/></Node>
    </Node>)";
    auto s = build(xml);
    scene::RunOptions run;
    run.steps = 2000;
    try {
        (void)scene::run_scene(*s, run);
        FAIL() << "no divergence reported";
    } catch (const std::runtime_error& e) {
        EXPECT_THAT(e.what(), HasSubstr("simulation diverged at step "));
        EXPECT_THAT(e.what(), HasSubstr("state '/A/p' DOF "));
        EXPECT_THAT(e.what(), HasSubstr("try a smaller --dt"));
    }
}

}  // namespace
