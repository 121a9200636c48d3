// The ODE solvers of the scene builder's integrators (builder/integrators.cpp): StaticSolver
// with its NewtonRaphsonSolver, RungeKutta2Solver and RungeKutta4Solver, on a chain of two
// springs (MeshSpringForceField, ks = 100/L) hanging from a fixed point under g = 10, 2 kg a
// point. StaticSolver finds the equilibrium y₁ = −1.4·L₁, y₂ = y₁ − 1.2·L₂ (L₁ = √0.91,
// L₂ = √0.62); the three solvers' states after 30 steps are SOFA HEAD's (2a278d8,
// `sofa-head SCENE 30 OUT --every 10`, %.17g), bit for bit. The Newton Data read with SOFA's
// defaults, and the refusals naming file, line, component and attribute.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/static_solver.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace penalty;

/// The hanging chain with `solver` (the ODE solver and what it needs) in its node.
std::string hanging_chain(const std::string& solver) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <DefaultAnimationLoop/>
  <Node name="Chain">
    )" + solver +
           R"(
    <MeshTopology name="topo" position="0 0 0  0.3 -0.9 0.1  0.5 -1.6 0.4" edges="0 1  1 2"/>
    <MechanicalObject name="dofs"/>
    <UniformMass vertexMass="2"/>
    <MeshSpringForceField stiffness="100" damping="0"/>
    <FixedProjectiveConstraint indices="0"/>
  </Node>
</Node>)";
}

const std::string kStatic = R"(<StaticSolver/>
    <NewtonRaphsonSolver maxNbIterationsNewton="10" absoluteResidualStoppingThreshold="1e-12"/>
    <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-20"/>)";

const std::vector<Vec3>& chain_positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Chain/dofs", false}, "position").state).position;
}

std::vector<Vec3> chain_after(const std::string& solver, int steps) {
    auto s = test::build(hanging_chain(solver));
    for (int k = 0; k < steps; ++k) s->step();
    return chain_positions(*s);
}

TEST(Integrators, StaticSolverFindsTheHangingChainsEquilibriumAsSofaHead) {
    // (the first steps' Newton iterations start from the rest shape, whose stiffness has no
    // transverse part: the chain gets there over the steps, as in SOFA)
    const double l1 = std::sqrt(0.91), l2 = std::sqrt(0.62);
    const std::vector<Vec3> x = chain_after(kStatic, 30);
    EXPECT_NEAR(x[1].y(), -1.4 * l1, 1e-15);
    EXPECT_NEAR(x[2].y(), -1.4 * l1 - 1.2 * l2, 1e-15);
    EXPECT_NEAR(x[1].x(), 0.0, 1e-15);
    EXPECT_NEAR(x[2].z(), 0.0, 1e-15);
    EXPECT_EQ(x[1], Vec3(2.4233807008389483e-27, -1.3355148819837239, 5.0991968913486203e-27));
    EXPECT_EQ(x[2], Vec3(-1.8011495946824186e-20, -2.2803958268651412, -3.6022985431299836e-20));
}

TEST(Integrators, RungeKuttaSolversSwingTheChainAsSofaHead) {
    const std::vector<Vec3> rk4 = chain_after("<RungeKutta4Solver/>", 30);
    EXPECT_EQ(rk4[1], Vec3(0.26655609463048963, -1.2306611318729823, 0.09522283387972845));
    EXPECT_EQ(rk4[2], Vec3(0.49408189698407035, -2.0293338135339787, 0.39154701369708783));
    const std::vector<Vec3> rk2 = chain_after("<RungeKutta2Solver/>", 30);
    EXPECT_EQ(rk2[1], Vec3(0.26656949708600636, -1.2307790911769307, 0.09515744831733644));
    EXPECT_EQ(rk2[2], Vec3(0.49415389174008512, -2.029586367970778, 0.39164557665731103));
}

const StaticSolver& static_solver_of(scene::Scene& s) {
    const auto* solver = dynamic_cast<const StaticSolver*>(s.simulation().root().children()[0]->ode_solver());
    if (solver == nullptr) throw std::logic_error("no StaticSolver");
    return *solver;
}

TEST(Integrators, NewtonDataAreReadWithSofasDefaults) {
    auto s = test::build(hanging_chain(R"(<StaticSolver/>
    <NewtonRaphsonSolver maxNbIterationsNewton="7" relativeSuccessiveStoppingThreshold="1e-3"
        relativeInitialStoppingThreshold="2e-3" absoluteResidualStoppingThreshold="3e-3"
        relativeEstimateDifferenceThreshold="4e-3" absoluteEstimateDifferenceThreshold="5e-3"
        maxNbIterationsLineSearch="3" lineSearchCoefficient="0.25"/>
    <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-20"/>)"));
    const NewtonRaphsonParameters& p = static_solver_of(*s).newton;
    EXPECT_EQ(p.max_iterations, 7);
    EXPECT_EQ(p.relative_successive, 1e-3);
    EXPECT_EQ(p.relative_initial, 2e-3);
    EXPECT_EQ(p.absolute_residual, 3e-3);
    EXPECT_EQ(p.relative_estimate_difference, 4e-3);
    EXPECT_EQ(p.absolute_estimate_difference, 5e-3);
    EXPECT_EQ(p.max_line_search_iterations, 3);
    EXPECT_EQ(p.line_search_coefficient, 0.25);
    // without a NewtonRaphsonSolver, SOFA's defaults
    auto defaults = test::build(hanging_chain(R"(<StaticSolver/>
    <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-20"/>)"));
    const NewtonRaphsonParameters& d = static_solver_of(*defaults).newton;
    EXPECT_EQ(d.max_iterations, 1);
    EXPECT_EQ(d.relative_successive, 1e-5);
    EXPECT_EQ(d.absolute_residual, 1e-5);
    EXPECT_EQ(d.relative_estimate_difference, 0.0);
    EXPECT_EQ(d.max_line_search_iterations, 1);
    EXPECT_EQ(d.line_search_coefficient, 0.5);
}

TEST(Integrators, StaticSolversDeprecatedNewtonDataGoToItsNewtonSolver) {
    // StaticSolver::init without a NewtonRaphsonSolver: each deprecated attribute given is copied
    // into the Newton solver it makes; relative_residual_tolerance_threshold goes, as SOFA's, to
    // relativeEstimateDifferenceThreshold (after relative_correction_tolerance_threshold)
    auto s =
        test::build(hanging_chain(R"(<StaticSolver newton_iterations="4" absolute_correction_tolerance_threshold="5e-3"
        relative_correction_tolerance_threshold="4e-3" absolute_residual_tolerance_threshold="3e-3"
        relative_residual_tolerance_threshold="2e-3"/>
    <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-20"/>)"));
    const NewtonRaphsonParameters& p = static_solver_of(*s).newton;
    EXPECT_EQ(p.max_iterations, 4);
    EXPECT_EQ(p.absolute_estimate_difference, 5e-3);
    EXPECT_EQ(p.absolute_residual, 3e-3);
    EXPECT_EQ(p.relative_estimate_difference, 2e-3);
    EXPECT_EQ(p.relative_successive, 1e-5);  // not set by any of them: SOFA's default
    // one given alone leaves the others at SOFA's defaults
    auto one = test::build(hanging_chain(R"(<StaticSolver newton_iterations="6"/>
    <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-20"/>)"));
    EXPECT_EQ(static_solver_of(*one).newton.max_iterations, 6);
    EXPECT_EQ(static_solver_of(*one).newton.absolute_residual, 1e-5);
    EXPECT_EQ(test::error_of(hanging_chain(R"(<StaticSolver newton_iterations="-2"/>
    <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-20"/>)")),
              "test.scn:4: StaticSolver: attribute 'newton_iterations': must be between 0 and 1000000");
}

TEST(Integrators, BadNewtonDataAreRefusedNamingTheAttribute) {
    const auto newton = [](const std::string& attributes) {
        return test::error_of(hanging_chain("<StaticSolver/>\n    <NewtonRaphsonSolver " + attributes +
                                            "/>\n    <CGLinearSolver iterations=\"100\" tolerance=\"1e-20\" "
                                            "threshold=\"1e-20\"/>"));
    };
    EXPECT_EQ(newton(R"(lineSearchCoefficient="2")"),
              "test.scn:5: NewtonRaphsonSolver: attribute 'lineSearchCoefficient': must be in (0, 1]");
    EXPECT_EQ(newton(R"(maxNbIterationsNewton="-1")"),
              "test.scn:5: NewtonRaphsonSolver: attribute 'maxNbIterationsNewton': must be between 0 and 1000000");
    EXPECT_EQ(newton(R"(updateStateWhenDiverged="0")"),
              "test.scn:5: NewtonRaphsonSolver: attribute 'updateStateWhenDiverged': 0 is not supported (SOFA ignores "
              "it)");
    EXPECT_EQ(test::error_of(hanging_chain(R"(<StaticSolver linearSolver="@dofs"/>)")),
              "test.scn:4: StaticSolver: attribute 'linearSolver': must link to a linear solver (CGLinearSolver, "
              "SparseLDLSolver, ...)");
}

}  // namespace
