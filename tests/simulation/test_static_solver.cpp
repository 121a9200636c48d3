// StaticSolver (Newton-Raphson) against closed-form equilibria and its convergence order.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/mesh_matrix_mass.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/direct_linear_solver.hpp"
#include "penalty/simulation/runge_kutta.hpp"
#include "penalty/simulation/static_solver.hpp"
#include "penalty_test/function_stage.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

/// A vertical chain: point 0 fixed at y = 0, points 1..n below it, springs of stiffness k and rest
/// length L between neighbours, masses m, gravity g along −y.
struct HangingChain {
    Simulation sim;
    Vec3Object* chain = nullptr;
    StaticSolver* solver = nullptr;
    HangingChain(int n, double k, double rest, double m, double g) {
        Node& root = sim.root();
        root.set_gravity(Vec3(0, -g, 0));
        solver = &root.set_ode_solver<StaticSolver>();
        chain = &root.add_state<Vec3Types>("chain");
        for (int i = 0; i <= n; ++i) chain->position.emplace_back(0.1, -rest * i, 0.2);
        root.set_mass<UniformMass<Vec3Types>>(*chain).set_vertex_mass(m);
        auto& springs = root.add_force_field<SpringForceField>(*chain, *chain);
        for (int i = 0; i < n; ++i) springs.add_spring({i, i + 1, k, 0.0, rest});
        root.add_constraint<FixedProjectiveConstraint>(*chain).set_indices({0});
        // at rest length the springs have no transverse stiffness: hold x and z (force-free)
        auto& sideways = root.add_force_field<RestShapeSpringsForceField<Vec3Types>>(*chain);
        sideways.set_stiffness({1.0});
        sideways.set_active_directions({true, false, true});
        sideways.set_sofa_assembly(false);
    }
};

/// y of point i at equilibrium: spring j (above point j) carries the n − j + 1 masses below it.
double chain_equilibrium(int i, int n, double k, double rest, double m, double g) {
    double y = 0.0;
    for (int j = 1; j <= i; ++j) y -= rest + (n - j + 1) * m * g / k;
    return y;
}

TEST(StaticSolver, AHangingSpringChainReachesTheAnalyticDeflectionInOneNewtonStep) {
    for (const bool direct : {true, false}) {
        SCOPED_TRACE(direct ? "SparseLDLSolver" : "CGLinearSolver");
        const int n = 6;
        const double k = 250.0, rest = 0.3, m = 0.4, g = 9.81;
        HangingChain c(n, k, rest, m, g);
        if (direct) c.solver->linear.direct = std::make_shared<DirectLinearSolver>();
        c.solver->linear.cg.iterations = 200;
        c.solver->linear.cg.tolerance = 1e-14;
        c.solver->linear.cg.threshold = 1e-30;
        c.sim.init();
        c.sim.step();
        // a vertical chain is linear in y: one Newton iteration (SOFA's default count) is exact
        for (int i = 0; i <= n; ++i) {
            EXPECT_NEAR(c.chain->position[std::size_t(i)].y(), chain_equilibrium(i, n, k, rest, m, g), 1e-11) << i;
            EXPECT_NEAR(c.chain->position[std::size_t(i)].x(), 0.1, 1e-14);
        }
        EXPECT_EQ(c.solver->iterations(), 1);
        EXPECT_EQ(c.sim.root().state()->velocity_flat().norm(), 0.0);  // velocities are not touched
        c.sim.step();  // at equilibrium: SOFA's ConvergedEquilibrium, nothing moves
        EXPECT_EQ(c.solver->status(), NewtonStatus::converged_equilibrium);
    }
}

TEST(StaticSolver, RestShapeSpringsUnderGravitySettleAtMgOverK) {
    Simulation sim;
    Node& root = sim.root();
    root.set_gravity(Vec3(0, -10, 0));
    auto& solver = root.set_ode_solver<StaticSolver>();
    solver.linear.direct = std::make_shared<DirectLinearSolver>();
    auto& x = root.add_state<Vec3Types>("points");
    x.position = {Vec3(0, 0, 0), Vec3(1, 2, 3)};
    root.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(0.5);
    root.add_force_field<RestShapeSpringsForceField<Vec3Types>>(x).set_stiffness({20.0, 80.0});
    sim.init();
    sim.step();
    EXPECT_NEAR(x.position[0].y(), -0.5 * 10 / 20.0, 1e-14);
    EXPECT_NEAR(x.position[1].y(), 2 - 0.5 * 10 / 80.0, 1e-14);
}

TEST(StaticSolver, NewtonConvergesQuadraticallyOnANonlinearSpringTruss) {
    // A point held by two pre-tensioned springs to fixed anchors, pulled down by its weight:
    // geometric nonlinearity. Newton's residuals fall with order 2 until round-off.
    Simulation sim;
    Node& root = sim.root();
    root.set_gravity(Vec3(0, -9.81, 0));
    auto& solver = root.set_ode_solver<StaticSolver>();
    solver.linear.direct = std::make_shared<DirectLinearSolver>();
    solver.newton.max_iterations = 12;
    solver.newton.relative_successive = 0.0;
    solver.newton.relative_initial = 0.0;
    solver.newton.absolute_residual = 1e-13;
    auto& x = root.add_state<Vec3Types>("truss");
    x.position = {Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)};
    root.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(20.0);
    auto& springs = root.add_force_field<SpringForceField>(x, x);
    springs.add_spring({0, 1, 1000.0, 0.0, 0.9});
    springs.add_spring({1, 2, 1000.0, 0.0, 0.9});
    root.add_constraint<FixedProjectiveConstraint>(x).set_indices({0, 2});
    sim.init();
    sim.step();
    EXPECT_EQ(solver.status(), NewtonStatus::converged_absolute_residual);
    const std::vector<double>& r2 = solver.squared_residuals();
    ASSERT_GE(r2.size(), 5u);
    // orders p_k = log(r_{k+1}/r_k) / log(r_k/r_{k−1}) over the iterations with r above round-off
    std::vector<double> r;
    for (double v : r2) r.push_back(std::sqrt(v));
    int measured = 0;
    for (std::size_t i = 2; i < r.size(); ++i) {
        if (r[i] < 1e-9) break;
        const double p = std::log(r[i] / r[i - 1]) / std::log(r[i - 1] / r[i - 2]);
        if (r[i - 1] < 1e-1) {  // in the quadratic basin
            EXPECT_GT(p, 1.8) << "iteration " << i;
            ++measured;
        }
    }
    EXPECT_GE(measured, 1);
    // the equilibrium: vertical force balance 2·T·sin θ = m g with T = k (ℓ − L)
    const double y = x.position[1].y();
    const double length = std::sqrt(1 + y * y);
    EXPECT_NEAR(2 * 1000.0 * (length - 0.9) * (-y / length), 20.0 * 9.81, 1e-9);
}

}  // namespace
}  // namespace penalty
