// The diagnostics of a non-finite solve (simulation/force_diagnostics.cpp): which contribution is not
// finite, or the largest force when a finite one overflowed the solve.
#include "penalty/io/error.hpp"
#include "penalty/io/mesh.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/output/format.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::run_error;
using ::testing::HasSubstr;

TEST(NonFiniteSolve, AnOverflowAtTheFirstStepIsInvalidInputNamingTheComponentAndAttributes) {
    // m·g = 1e200 N is finite, |b|² = (h·m·g)² overflows in the CG solve.
    auto s = build(R"(<Node name="root" dt="0.01" gravity="0 -1e100 0">
  <Node name="Ball">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <MechanicalObject name="p" position="0 0 0"/>
    <UniformMass name="mass" totalMass="1e100"/>
  </Node>
</Node>)");
    const std::string message = run_error<io::LoadError>(*s, scene::RunOptions{});
    EXPECT_THAT(message,
                HasSubstr("test.scn:6: UniformMass 'mass': CGLinearSolver: the right-hand side is not finite"));
    EXPECT_THAT(message, HasSubstr("the largest force (1e+200 N) is the gravity force m·g on state 'p'"));
    EXPECT_THAT(message, HasSubstr("attribute 'totalMass' = 1e100, node / attribute 'gravity' = 0 -1e100 0"));
}

TEST(NonFiniteSolve, AnOverflowDuringTheRunIsADivergenceNamingTheForceField) {
    // An explicit spring of 1e100 N/m stretched 1 m: the particle is thrown to 1e100 m, then
    // 1e200 m, and the force k·Δx overflows while the states are still finite.
    auto s = build(R"(<Node name="root" dt="1" gravity="0 0 0">
  <Node name="A">
    <EulerExplicitSolver/>
    <MechanicalObject name="p" position="0 0 0  2 0 0" rest_position="0 0 0  1 0 0"/>
    <MeshTopology edges="0 1"/>
    <UniformMass vertexMass="1"/>
    <MeshSpringForceField name="springs" stiffness="1e100"/>
  </Node>
</Node>)");
    scene::RunOptions run;
    run.steps = 20;
    run.divergence_factor = 0.0;
    const std::string message = run_error<output::NonFiniteValueError>(*s, run);
    EXPECT_THAT(message, HasSubstr("simulation diverged at step "));
    EXPECT_THAT(message, HasSubstr("from MeshSpringForceField 'springs' (test.scn:7)"));
}

}  // namespace
