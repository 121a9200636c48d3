// Reliability (docs/reliability.md): one component of a kind per node, the divergence criterion,
// non-finite values inside a solve named by their source, a run of 0 steps, degenerate collision
// triangles, and every input the fuzzers found (fuzz/regressions/).
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

std::string build_error(const std::string& xml) {
    try {
        (void)build(xml);
    } catch (const io::LoadError& e) {
        return e.what();
    }
    return "no error";
}

// ---- one component of a kind per node -------------------------------------------------------------

TEST(OnePerNode, SecondMassIsRefusedNamingBothLines) {
    // Was a use after free: the second mass replaced the first while its init was still queued.
    EXPECT_EQ(build_error(R"(<Node name="root" dt="0.01">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <MechanicalObject position="0 0 0"/>
    <UniformMass totalMass="1"/>
    <UniformMass totalMass="1"/>
</Node>)"),
              "test.scn:6: UniformMass: a node holds one mass, and this node already has UniformMass at line 5");
}

TEST(OnePerNode, SecondLinearSolverIsRefused) {
    EXPECT_EQ(build_error(R"(<Node name="root">
    <EulerImplicitSolver/>
    <CGLinearSolver name="a"/>
    <CGLinearSolver name="b" iterations="3"/>
    <MechanicalObject position="0 0 0"/>
    <UniformMass totalMass="1"/>
</Node>)"),
              "test.scn:4: CGLinearSolver 'b': a node holds one linear solver, and this node already has "
              "CGLinearSolver 'a' at line 3");
}

TEST(OnePerNode, TheNodeApiRefusesReplacingAMassASolverOrAMapping) {
    Simulation sim;
    Node& n = sim.root();
    auto& x = n.add_state<Vec3Types>("x");
    x.position = {Vec3::Zero()};
    n.set_mass<UniformMass<Vec3Types>>(x);
    EXPECT_THROW((n.set_mass<UniformMass<Vec3Types>>(x)), std::invalid_argument);
    n.set_ode_solver<EulerImplicitSolver>();
    EXPECT_THROW(n.set_ode_solver<EulerExplicitSolver>(), std::invalid_argument);
}

TEST(Threads, AContactPipelineRefusesMoreThanItsMaximum) {
    Simulation sim;
    ContactPipelineOptions options;
    options.threads = kMaxDetectionThreads + 1;
    EXPECT_THROW(ContactPipeline(sim, IntersectionParams::min_proximity(), CollisionResponse(), nullptr, options),
                 std::invalid_argument);
    options.threads = 65537;  // TBB crashed on an arena this size
    EXPECT_THROW(ContactPipeline(sim, IntersectionParams::min_proximity(), CollisionResponse(), nullptr, options),
                 std::invalid_argument);
}

// ---- divergence ---------------------------------------------------------------------------------

// tests/scene/data/free_fall_beside_a_marker.scn (the Python tests read it too): a particle in
// free fall beside a static point 10 m away: the scene's box has diagonal 10 m and centre
// (5, 0, 0). Implicit Euler is exact on uniform acceleration: y_n = −g·h²·n(n+1)/2 after n steps
// (g = 10 m/s², h = 0.1 s: y_n = −0.05·n(n+1) m).
const std::string kFreeFall = [] {
    std::ifstream in(penalty::test::source_dir() / "tests" / "scene" / "data" / "free_fall_beside_a_marker.scn");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}();

// The error of 100 steps of a scene whose box has a 10 m diagonal, with divergence factor 0.5.
std::string error_at_half_the_scene_size(const std::string& xml) {
    auto s = build(xml);
    EXPECT_DOUBLE_EQ(scene::DivergenceBound(*s, 0.5).scene_size(), 10.0);
    scene::RunOptions run;
    run.steps = 100;
    run.divergence_factor = 0.5;
    return run_error<output::NonFiniteValueError>(*s, run);
}

TEST(Divergence, AStepLongerThanFTimesTheSceneSizeStopsTheRunAtTheRightStep) {
    // Step n (1-based) moves the particle by h·v_n = g·h²·n = 0.1·n m. F = 0.5: the limit is 5 m,
    // first passed by step n = 51, the step of index 50.
    const std::string message = error_at_half_the_scene_size(kFreeFall);
    EXPECT_THAT(message, HasSubstr("simulation diverged at step 50 (t = 5."));
    EXPECT_THAT(message, HasSubstr("state '/Particle/p' DOF 0 moved 5.09999999999999"));
    EXPECT_THAT(message, HasSubstr("m in one step, more than 0.5 times the initial scene size (10 m)"));
}

// The same fall for the third DOF of a state whose first two are fixed, after a static marker and
// a static rigid frame: the check passes over every state (a rigid frame's centre too) and names
// the first DOF to move more than the limit; below the limit the run goes on.
const std::string kThirdDofFalls = R"(<Node name="root" dt="0.1" gravity="0 -10 0">
  <Node name="Marker"><MechanicalObject name="m" position="10 0 0"/></Node>
  <Node name="Frame"><MechanicalObject name="f" template="Rigid3d" position="5 0 0  0 0 0 1"/></Node>
  <Node name="Three">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="p" position="0 0 0  1 0 0  0 0 0"/>
    <UniformMass totalMass="3"/>
    <FixedConstraint indices="0 1"/>
  </Node>
</Node>)";

TEST(Divergence, TheFirstDofPastTheLimitIsNamedWhateverStateItIsIn) {
    const std::string message = error_at_half_the_scene_size(kThirdDofFalls);
    EXPECT_THAT(message, HasSubstr("simulation diverged at step 50 (t = 5."));
    EXPECT_THAT(message, HasSubstr("state '/Three/p' DOF 2 moved 5.09999999999999"));
    // a limit of 10 m: the last of 95 steps moves 9.5 m
    auto t = build(kThirdDofFalls);
    scene::RunOptions run;
    run.steps = 95;
    run.divergence_factor = 1.0;
    const scene::RunSummary summary = scene::run_scene(*t, run);
    EXPECT_EQ(summary.steps, 95);
    const auto* p = dynamic_cast<const Vec3Object*>(t->states()[2].state);
    ASSERT_NE(p, nullptr);
    EXPECT_NEAR(p->position[2].y(), -0.05 * 95 * 96, 1e-9);
    EXPECT_EQ(p->position[1], Vec3(1, 0, 0));
}

TEST(Divergence, AStateThatIsNotFiniteIsNamedWithItsDof) {
    // a static marker of five points whose fourth velocity (DOF 3) is not finite: no solver reads
    // it, so the run's own check after the step finds it (in one pass over the values, then the DOF)
    for (const double bad : {std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity()}) {
        auto s = build(R"(<Node name="root" dt="0.1" gravity="0 -10 0">
  <Node name="Particle">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="p" position="0 0 0"/>
    <UniformMass totalMass="1"/>
  </Node>
  <Node name="Marker"><MechanicalObject name="m" position="10 0 0  9 0 0  8 0 0  7 0 0  6 0 0"/></Node>
</Node>)");
        auto* marker = dynamic_cast<Vec3Object*>(s->states()[1].state);
        ASSERT_NE(marker, nullptr);
        marker->velocity[3].z() = bad;
        scene::RunOptions run;
        run.steps = 3;
        const std::string message = run_error<output::NonFiniteValueError>(*s, run);
        EXPECT_THAT(message,
                    HasSubstr("simulation diverged at step 0 (t = 0.1 s): state '/Marker/m' DOF 3 is not finite"));
    }
}

TEST(Divergence, StaticStatesAreCheckedAfterTheFirstStepOnlyUnlessCodeBetweenStepsMayMoveThem) {
    // kFreeFall's marker is static (no solver above it, not mapped): no step moves it, so the
    // run checks it after step 0 only, unless RunOptions::states_change_between_steps says that
    // the code run between the steps (here the progress callback, after step 2) may.
    for (const bool may_change : {false, true}) {
        for (const bool jump : {false, true}) {
            SCOPED_TRACE(std::string(may_change ? "may change" : "fixed") + (jump ? ", jump" : ", NaN"));
            auto s = build(kFreeFall);
            auto* marker = dynamic_cast<Vec3Object*>(s->states()[1].state);
            ASSERT_NE(marker, nullptr);
            ASSERT_FALSE(s->states()[1].mapped || s->states()[1].in_solver_subtree);
            ASSERT_TRUE(s->states()[0].in_solver_subtree);
            scene::RunOptions run;
            run.steps = 6;
            run.divergence_factor = 1.0;  // 10 m
            run.states_change_between_steps = may_change;
            std::int64_t steps_done = 0;
            const auto move_marker = [&](std::int64_t done, std::int64_t, const scene::RunSummary&) {
                steps_done = done;
                if (done != 3) return;
                if (jump) marker->position[0].x() += 50.0;
                else marker->velocity[0].z() = std::numeric_limits<double>::quiet_NaN();
            };
            std::string message = "no error";
            try {
                (void)scene::run_scene(*s, run, move_marker);
            } catch (const output::NonFiniteValueError& e) {
                message = e.what();
            }
            if (!may_change) {
                EXPECT_EQ(message, "no error");
                EXPECT_EQ(steps_done, 6);
                continue;
            }
            EXPECT_EQ(steps_done, 3);
            EXPECT_THAT(message, HasSubstr("simulation diverged at step 3 (t = 0.4"));
            EXPECT_THAT(message, HasSubstr(jump ? "state '/Marker/m' DOF 0 moved 50 m in one step"
                                                : "state '/Marker/m' DOF 0 is not finite"));
        }
    }
}

TEST(Divergence, TheCheckCanBeTurnedOffAndTheFallIsExact) {
    auto s = build(kFreeFall);
    scene::RunOptions run;
    run.steps = 100;
    run.divergence_factor = 0.0;
    (void)scene::run_scene(*s, run);
    const auto* p = dynamic_cast<const Vec3Object*>(s->states()[0].state);
    ASSERT_NE(p, nullptr);
    EXPECT_NEAR(p->position[0].y(), -0.05 * 100 * 101, 1e-9 * 505);
    scene::RunOptions bad;
    bad.divergence_factor = std::nan("");
    EXPECT_THROW((void)scene::run_scene(*s, bad), std::invalid_argument);
}

TEST(Divergence, TheDefaultLetsALongFreeFallGo) {
    // 2000 steps: the particle falls 2·10⁵ m (2·10⁴ scene sizes); its last step is 200 m, 20
    // scene sizes, inside the default F = 100.
    auto s = build(kFreeFall);
    scene::RunOptions run;
    run.steps = 2000;
    EXPECT_EQ(scene::run_scene(*s, run).steps, 2000);
}

TEST(Divergence, AHugeTimeStepThatDropsABodyThroughTheFloorIsCaught) {
    // Implicit Euler with dt = 1000 s: the first step moves the particle g·dt² = 10⁷ m.
    auto s = scene::build_scene(io::parse_scene_string(kFreeFall, "test.scn"), [] {
        scene::BuildOptions o;
        o.dt = 1000.0;
        return o;
    }());
    scene::RunOptions run;
    run.steps = 3;
    EXPECT_THAT(run_error<output::NonFiniteValueError>(*s, run),
                HasSubstr("simulation diverged at step 0 (t = 1000 s)"));
}

TEST(Divergence, EnergyCreatedFromNothingIsCaught) {
    // An explicit spring of 10⁴ N/m between two 1 kg particles, stretched 0.5 m: ω = √(k/m_eff) =
    // 141 rad/s and dt = 0.0145 s, ω·dt = 2.05 > 2: symplectic Euler is unstable, its amplification
    // is |λ| = 1.56 per step (energy ×2.4), while each step stays short. E_ref = ½·k·0.5² = 1250 J
    // (no gravity, at rest): the run stops once the energy grew by 10·F·E_ref = 1.25e6 J, about
    // 8 steps in, long before any NaN or any step of 100 scene sizes.
    auto s = build(R"(<Node name="root" dt="0.0145" gravity="0 0 0">
  <Node name="A">
    <EulerExplicitSolver/>
    <MechanicalObject name="p" position="0 0 0  1.5 0 0" rest_position="0 0 0  1 0 0"/>
    <MeshTopology edges="0 1"/>
    <UniformMass vertexMass="1"/>
    <MeshSpringForceField name="springs" stiffness="10000"/>
  </Node>
</Node>)");
    scene::RunOptions run;
    run.steps = 1000;
    const std::string message = run_error<output::NonFiniteValueError>(*s, run);
    EXPECT_THAT(message, HasSubstr("the energy grew by"));
    EXPECT_THAT(message, HasSubstr("more than 1000 times the scene's energy scale (1250 J"));
    EXPECT_THAT(message, ::testing::MatchesRegex(".*diverged at step [5-9] .*"));
}

// ---- non-finite values inside a solve -------------------------------------------------------------

// ---- a run of 0 steps -------------------------------------------------------------------------

TEST(Divergence, ADirectSolverOverStatesWithoutMassIsASceneErrorNamingTheSolver) {
    // no mass, no force field: the assembled system is zero. Not a divergence (no smaller dt
    // helps): bad input naming the direct solver's component and line. A mass makes it run.
    const std::string body = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="Cube">
    <EulerImplicitSolver/>
    <EigenSparseLU name="lu"/>
    <MechanicalObject name="cube" position="0 0 0  1 0 0  0 1 0"/>
)";
    auto massless = build(body + "  </Node>\n</Node>");
    scene::RunOptions run;
    run.steps = 3;
    EXPECT_EQ(run_error<io::SceneError>(*massless, run),
              "test.scn:4: EigenSparseLU 'lu': step 0: direct linear solver (LU): the system matrix is zero: its 9 "
              "unknowns have no mass, stiffness nor constraint (give their states a mass)");
    auto with_mass = build(body + "    <UniformMass totalMass=\"1\"/>\n  </Node>\n</Node>");
    EXPECT_NO_THROW((void)scene::run_scene(*with_mass, run));
}

TEST(ZeroSteps, TheStateFilesHoldTheInitialState) {
    auto s = build(kFreeFall);
    const auto dir = std::filesystem::temp_directory_path() / "penalty_zero_steps";
    std::filesystem::remove_all(dir);
    scene::RunOptions run;
    run.steps = 0;
    run.states_directory = dir;
    const scene::RunSummary summary = scene::run_scene(*s, run);
    ASSERT_EQ(summary.state_files.size(), 1u);
    const auto samples = output::read_state_file(summary.state_files[0]);
    ASSERT_EQ(samples.size(), 1u);
    EXPECT_EQ(samples[0].time, 0.0);
    EXPECT_THAT(samples[0].x, ::testing::ElementsAre(0.0, 0.0, 0.0));
    std::filesystem::remove_all(dir);
}

// ---- degenerate collision triangles ---------------------------------------------------------------

TEST(DegenerateTriangles, ACollisionModelWithZeroAreaTrianglesIsReported) {
    // Triangle 1 repeats a corner, triangle 2 is collinear: 2 of 3 have no area.
    auto s = build(R"(<Node name="root">
  <Node name="Floor">
    <MechanicalObject position="0 0 0  1 0 0  0 0 1  2 0 0"/>
    <MeshTopology triangles="0 2 1  0 1 1  0 1 3"/>
    <TriangleCollisionModel name="floor" simulated="0" moving="0"/>
  </Node>
</Node>)");
    bool found = false;
    for (const std::string& w : s->warnings())
        found = found ||
                w == "test.scn:5: TriangleCollisionModel 'floor': 2 of 3 triangles have zero area (first: triangle 1); "
                     "they make no reliable contact";
    EXPECT_TRUE(found);
}

// ---- inline arrays and numbers ----------------------------------------------------------------

TEST(InlineArrays, AListAboveTheCapIsRefusedBeforeParsing) {
    std::string many;
    many.reserve(3 * (io::kMaxInlineValues / 3 + 1) * 2);
    for (std::size_t i = 0; i < io::kMaxInlineValues / 3 + 1; ++i) many += "0 0 0 ";
    EXPECT_EQ(build_error("<Node name=\"root\"><MechanicalObject name=\"m\" position=\"" + many + "\"/></Node>"),
              "test.scn:1: MechanicalObject 'm': attribute 'position': 1000002 values, more than penalty's limit of "
              "1000000 in one attribute (put large data in a mesh file)");
}

TEST(Numbers, AMagnitudeAbove1e100IsRefusedWhereItIsWritten) {
    EXPECT_EQ(build_error(R"(<Node name="root" dt="1e300"><MechanicalObject position="0 0 0"/></Node>)"),
              "test.scn:1: Node 'root': attribute 'dt': '1e300': magnitude above 1e100 (penalty's limit for any "
              "number in a scene or mesh file)");
    EXPECT_EQ(build_error(R"(<Node name="root" dt="1e100"><MechanicalObject position="0 -1e100 0"/></Node>)"),
              "no error");
}

// ---- inputs the fuzzers found -------------------------------------------------------------------

/// Every file in fuzz/regressions/: a scene (`.scn`) is built and stepped 3 times, a mesh is
/// parsed; each must end normally or with a documented error, never a crash or a sanitizer report
/// (the ASan suite runs this too).
TEST(FuzzRegressions, EveryFoundInputIsHandled) {
    const std::filesystem::path dir = penalty::test::source_dir() / "fuzz" / "regressions";
    int inputs = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const std::filesystem::path p = entry.path();
        const std::string ext = p.extension().string();
        if (ext == ".md") continue;
        std::ifstream in(p, std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        ++inputs;
        SCOPED_TRACE(p.filename().string());
        try {
            if (ext == ".scn") {
                scene::BuildOptions options;
                options.max_dofs = 5'000;
                options.max_cg_iterations = 200;
                auto s = scene::build_scene(io::parse_scene_string(text.str(), p.filename().string()), options);
                (void)scene::describe_scene(*s);
                scene::RunOptions run;
                run.steps = 3;
                (void)scene::run_scene(*s, run);
            } else if (ext == ".obj") {
                (void)io::parse_obj(text.str(), p);
            } else if (ext == ".msh") {
                (void)io::parse_gmsh(text.str(), p);
            } else if (ext == ".sph") {
                (void)io::parse_sph(text.str(), p);
            } else if (ext == ".vtk") {
                (void)io::parse_vtk_legacy(text.str(), p);
            } else {
                ADD_FAILURE() << "unknown regression input kind " << ext;
            }
        } catch (const io::LoadError&) {
        } catch (const output::NonFiniteValueError&) {
        } catch (const NonFiniteSolveError&) {
        }
    }
    EXPECT_GE(inputs, 1) << "fuzz/regressions/ holds no input";
}

}  // namespace
