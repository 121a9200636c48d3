// The solver components of scene files (direct linear solvers and their linear systems,
// StaticSolver with NewtonRaphsonSolver, the Runge-Kutta solvers, MultiStepAnimationLoop) and
// MeshMatrixMass / RestShapeSpringsForceField: what the builder makes of them, the project's
// scenes of tests/scene/data/solvers against closed forms, and bad values refused with file, line,
// component and attribute.
#include "penalty/mechanics/mesh_matrix_mass.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/direct_linear_solver.hpp"
#include "penalty/simulation/runge_kutta.hpp"
#include "penalty/simulation/static_solver.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::AllOf;
using ::testing::HasSubstr;

const std::filesystem::path kSolverScenes = penalty::test::source_dir() / "tests" / "scene" / "data" / "solvers";

std::unique_ptr<scene::Scene> load_solver_scene(const std::string& name) {
    return scene::load_scene(kSolverScenes / name, {});
}

/// The ODE solver of the first node named `node`.
template <class Solver>
Solver* solver_of(scene::Scene& s, const std::string& node) {
    Solver* found = nullptr;
    std::function<void(Node&)> visit = [&](Node& n) {
        if (found == nullptr && n.name() == node) found = dynamic_cast<Solver*>(n.ode_solver());
        for (const auto& c : n.children()) visit(*c);
    };
    visit(s.simulation().root());
    return found;
}

void run_steps(scene::Scene& s, int n) {
    for (int i = 0; i < n; ++i) s.step();
}

/// The state named `name` (a MechanicalObject of the file).
template <class State>
const State* state_named(const scene::Scene& s, const std::string& name) {
    for (const auto& r : s.states())
        if (r.name == name) return dynamic_cast<const State*>(r.state);
    return nullptr;
}

TEST(SolverComponents, DirectSolversTheirSystemsAndOrderingsAreRead) {
    auto s = load_solver_scene("hexa_beam_matrix_mass_ldl.scn");
    auto* implicit = solver_of<EulerImplicitSolver>(*s, "Beam");
    ASSERT_NE(implicit, nullptr);
    ASSERT_TRUE(implicit->direct_solver);
    EXPECT_EQ(implicit->direct_solver->method, FactorizationMethod::ldlt);
    EXPECT_EQ(implicit->direct_solver->ordering, FillOrdering::natural);  // orderingMethod="@ordering"
    EXPECT_FALSE(solver_of<EulerImplicitSolver>(*s, "LumpedBeam")->direct_solver);
    const std::string info = scene::describe_scene(*s);
    EXPECT_THAT(info, HasSubstr("direct solve of the assembled system: LDLT (Eigen), natural ordering"));
    EXPECT_THAT(info, HasSubstr("consistent mass matrix of the hexahedra, 320 kg in all"));
    EXPECT_THAT(info, HasSubstr("lumped mass matrix of the hexahedra"));
    run_steps(*s, 3);
    EXPECT_EQ(implicit->direct_solver->factorizations(), 3);
}

TEST(SolverComponents, TheTetrahedralCantileverBendsTheSameWithEveryDirectSolver) {
    auto s = load_solver_scene("tetra_direct_solvers.scn");
    run_steps(*s, 20);
    std::vector<const Vec3Object*> bars;
    for (const auto& st : s->states()) bars.push_back(dynamic_cast<const Vec3Object*>(st.state));
    ASSERT_EQ(bars.size(), 5u);
    // the bars are 0.3 m apart along z and identical: the same motion up to rounding
    for (std::size_t b = 1; b < bars.size(); ++b)
        for (std::size_t i = 0; i < bars[0]->position.size(); ++i)
            EXPECT_LT((bars[b]->position[i] - bars[0]->position[i] - Vec3(0, 0, 0.3 * double(b))).norm(), 1e-12)
                << "bar " << b << " point " << i;
    EXPECT_LT(bars[0]->position[3].y(), -1e-4);  // the free end went down
}

TEST(SolverComponents, TheStaticChainReachesEquilibrium) {
    auto s = load_solver_scene("static_sagging_chain.scn");
    auto* solver = solver_of<StaticSolver>(*s, "Chain");
    ASSERT_NE(solver, nullptr);
    EXPECT_EQ(solver->newton.max_iterations, 8);
    EXPECT_EQ(solver->newton.max_line_search_iterations, 3);
    EXPECT_TRUE(solver->linear.direct);
    run_steps(*s, 3);
    EXPECT_EQ(solver->status(), NewtonStatus::converged_equilibrium);
    EXPECT_LT(solver->squared_residuals().front(), 1e-18);
    auto relax = load_solver_scene("static_relaxation_cg.scn");
    auto* cg = solver_of<StaticSolver>(*relax, "Chain");
    EXPECT_EQ(cg->newton.max_iterations, 1);  // SOFA's NewtonRaphsonSolver created with its defaults
    EXPECT_FALSE(cg->linear.direct);
    EXPECT_EQ(cg->linear.cg.iterations, 4);
}

TEST(SolverComponents, RungeKuttaSolversAndRestShapeSpringsAreBuilt) {
    auto s = load_solver_scene("runge_kutta_rest_springs.scn");
    EXPECT_NE(solver_of<RungeKutta4Solver>(*s, "RK4"), nullptr);
    EXPECT_NE(solver_of<RungeKutta2Solver>(*s, "RK2"), nullptr);
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("explicit Runge-Kutta of order 4"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("3 springs to the rest positions"));
    run_steps(*s, 10);
    // point 2 of RK4 is not held: it falls freely (RK4 is exact on constant acceleration)
    const auto* p = state_named<Vec3Object>(*s, "points4");
    const double t = 10 * 0.005;
    EXPECT_NEAR(p->position[2].y(), -0.5 * 9.81 * t * t, 1e-14);
    EXPECT_NEAR(p->position[2].z(), -t, 1e-14);
}

TEST(SolverComponents, RigidRestSpringsFollowTheExternalRestShape) {
    auto s = load_solver_scene("rigid_rest_springs.scn");
    EXPECT_THAT(scene::describe_scene(*s),
                HasSubstr("2 springs (translation and rotation) to the external state's frames"));
    run_steps(*s, 1500);
    // damped (Rayleigh): after 15 s the frames rest at their anchors, sagged by m g / k (m = 1 kg)
    const auto* frames = state_named<Rigid3Object>(*s, "frames");
    ASSERT_NE(frames, nullptr);
    EXPECT_NEAR(frames->position[1].center.x(), 2.0, 1e-3);  // frame 1 → anchor 1 at (2, 1, 0)
    EXPECT_NEAR(frames->position[1].center.y(), 1.0 - 1.0 * 9.81 / 80.0, 1e-3);
    EXPECT_NEAR(frames->position[2].center.x(), 0.0, 1e-3);  // frame 2 → anchor 0 at (0, 1, 0)
}

TEST(SolverComponents, MultiStepAnimationLoopSetsTheSimulationsSubsteps) {
    auto s = build(R"(<Node name="root" dt="0.04" gravity="0 -10 0">
      <MultiStepAnimationLoop collisionSteps="2" integrationSteps="2"/>
      <Node name="P"><EulerExplicitSolver/><MechanicalObject position="0 0 0"/><UniformMass totalMass="1"/></Node>
    </Node>)");
    EXPECT_EQ(s->simulation().collision_steps(), 2);
    EXPECT_EQ(s->simulation().integration_steps(), 2);
    s->step();
    EXPECT_NEAR(s->simulation().time(), 0.02, 1e-15);  // SOFA's time: dt / collisionSteps a step
    auto exact =
        build(R"(<Node name="root" dt="0.04"><MultiStepAnimationLoop collisionSteps="2" exactTime="1"/></Node>)");
    exact->step();
    EXPECT_NEAR(exact->simulation().time(), 0.04, 1e-15);
}

TEST(SolverComponents, MeshMatrixMassAndRestSpringsOfAScene) {
    auto s = build(R"(<Node name="root" dt="0.01" gravity="0 -10 0">
      <Node name="Body"><EulerImplicitSolver/><SparseLDLSolver/>
        <MechanicalObject name="body" position="0 0 0  1 0 0  0 1 0  0 0 1"/>
        <MeshTopology tetrahedra="0 1 2 3"/>
        <MeshMatrixMass massDensity="6"/>
        <RestShapeSpringsForceField points="0 1 2 3" stiffness="1e4"/>
      </Node></Node>)");
    const auto* mass = dynamic_cast<const MeshMatrixMass*>(s->states()[0].mass);
    ASSERT_NE(mass, nullptr);
    EXPECT_NEAR(mass->total_mass(), 1.0, 1e-15);  // ρ V = 6 · 1/6
    EXPECT_NEAR(mass->vertex_masses()[0], 0.1, 1e-15);
    EXPECT_NEAR(mass->edge_masses()[0], 0.05, 1e-15);
    run_steps(*s, 200);
    // damped by the implicit scheme: at rest where k x = (row sum of M) g = (ρV/4) g
    const auto* x = state_named<Vec3Object>(*s, "body");
    EXPECT_NEAR(x->position[1].y(), -0.25 * 10 / 1e4, 1e-9);
}

// ---- bad values: file, line, component and attribute --------------------------------------
std::string body_with(const std::string& components) {
    return R"(<Node name="root">
  <Node name="B"><EulerImplicitSolver/>
    <MechanicalObject position="0 0 0  1 0 0  0 1 0  0 0 1"/>
    <MeshTopology tetrahedra="0 1 2 3"/>
)" + components +
           "\n  </Node>\n</Node>";
}

TEST(SolverComponents, BadValuesNameFileLineComponentAndAttribute) {
    EXPECT_THAT(error_of(body_with(R"(    <MeshMatrixMass massDensity="1 2"/>)")),
                AllOf(HasSubstr("test.scn:5"), HasSubstr("MeshMatrixMass"), HasSubstr("massDensity")));
    EXPECT_THAT(error_of(body_with(R"(    <MeshMatrixMass massDensity="-3"/>)")),
                AllOf(HasSubstr("test.scn:5"), HasSubstr("massDensity"), HasSubstr(">= 0")));
    EXPECT_THAT(error_of(body_with(R"(    <MeshMatrixMass totalMass="nan"/>)")),
                AllOf(HasSubstr("test.scn:5"), HasSubstr("totalMass")));
    EXPECT_THAT(error_of(body_with(R"(    <MeshMatrixMass vertexMass="1 1 1 1"/>)")),
                AllOf(HasSubstr("MeshMatrixMass"), HasSubstr("lumping or edgeMass")));
    EXPECT_THAT(
        error_of(body_with(R"(    <UniformMass totalMass="1"/><RestShapeSpringsForceField stiffness="10 -1"/>)")),
        AllOf(HasSubstr("test.scn:5"), HasSubstr("RestShapeSpringsForceField"), HasSubstr("stiffness")));
    EXPECT_THAT(
        error_of(body_with(R"(    <UniformMass totalMass="1"/><RestShapeSpringsForceField activeDirections="1 0"/>)")),
        AllOf(HasSubstr("activeDirections"), HasSubstr("3 flags")));
    EXPECT_THAT(error_of(body_with(
                    R"(    <UniformMass totalMass="1"/><RestShapeSpringsForceField activeDirections="1 2 0"/>)")),
                AllOf(HasSubstr("activeDirections"), HasSubstr("0 or 1")));
    EXPECT_THAT(error_of(body_with(R"(    <UniformMass totalMass="1"/><RestShapeSpringsForceField points="0 7"/>)")),
                AllOf(HasSubstr("RestShapeSpringsForceField"), HasSubstr("point 7 is out of range")));
    EXPECT_THAT(error_of(body_with(
                    R"(    <UniformMass totalMass="1"/><RestShapeSpringsForceField external_rest_shape="@B"/>)")),
                AllOf(HasSubstr("external_rest_shape"), HasSubstr("MechanicalObject")));
    EXPECT_THAT(
        error_of(body_with(R"(    <UniformMass totalMass="1"/><RestShapeSpringsForceField angularStiffness="3"/>)")),
        AllOf(HasSubstr("angularStiffness"), HasSubstr("Rigid3d")));
    EXPECT_THAT(error_of(R"(<Node name="root"><MultiStepAnimationLoop collisionSteps="0"/></Node>)"),
                AllOf(HasSubstr("test.scn:1"), HasSubstr("MultiStepAnimationLoop"), HasSubstr("collisionSteps")));
    EXPECT_THAT(
        error_of(R"(<Node name="root"><Node name="S"><StaticSolver/><NewtonRaphsonSolver lineSearchCoefficient="2"/>
      <CGLinearSolver/><MechanicalObject position="0 0 0"/><UniformMass totalMass="1"/></Node></Node>)"),
        AllOf(HasSubstr("test.scn:1"), HasSubstr("NewtonRaphsonSolver"), HasSubstr("lineSearchCoefficient")));
    EXPECT_THAT(
        error_of(R"(<Node name="root"><Node name="S"><StaticSolver/><NewtonRaphsonSolver maxNbIterationsNewton="-1"/>
      <CGLinearSolver/><MechanicalObject position="0 0 0"/><UniformMass totalMass="1"/></Node></Node>)"),
        AllOf(HasSubstr("NewtonRaphsonSolver"), HasSubstr("maxNbIterationsNewton")));
    EXPECT_THAT(error_of(R"(<Node name="root"><Node name="S"><StaticSolver/>
      <MechanicalObject position="0 0 0"/><UniformMass totalMass="1"/></Node></Node>)"),
                AllOf(HasSubstr("StaticSolver"), HasSubstr("linear solver")));
    EXPECT_THAT(error_of(R"(<Node name="root"><Node name="S"><EulerImplicitSolver/><SparseLDLSolver linearSystem="@S"/>
      <MechanicalObject position="0 0 0"/><UniformMass totalMass="1"/></Node></Node>)"),
                AllOf(HasSubstr("SparseLDLSolver"), HasSubstr("linearSystem")));
    EXPECT_THAT(error_of(R"(<Node name="root"><Node name="S"><RungeKutta4Solver/>
      <MechanicalObject position="0 0 0  1 0 0  0 1 0  0 0 1"/><MeshTopology tetrahedra="0 1 2 3"/><MeshMatrixMass/></Node></Node>)"),
                AllOf(HasSubstr("RungeKutta4Solver"), HasSubstr("lumping")));
}

}  // namespace
