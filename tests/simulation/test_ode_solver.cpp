// The Euler solvers (simulation/ode_solver.cpp): explicit and implicit Euler against closed-form
// motions, the implicit Euler's Newton variant.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace penalty {
namespace {

TEST(EulerImplicit, FreeFallIsExact) {
    Simulation sim;
    Node& body = sim.root().add_child("body");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    solver.cg.tolerance = 1e-12;
    solver.cg.threshold = 1e-20;
    auto& dofs = body.add_state<Vec3Types>();
    dofs.position = {Vec3(0, 10, 0), Vec3(1, 10, 0)};
    body.set_mass<UniformMass<Vec3Types>>(dofs).set_total_mass(4.0);
    sim.init();
    const double h = 0.01, g = 9.81;
    for (int n = 1; n <= 50; ++n) {
        sim.step();
        EXPECT_NEAR(dofs.velocity[0].y(), -g * h * n, 1e-12);
        EXPECT_NEAR(dofs.position[1].y(), 10 - g * h * h * n * (n + 1) / 2.0, 1e-12);
    }
    EXPECT_EQ(dofs.position[1].x(), 1.0);
}

TEST(EulerExplicit, FreeFallIsSymplecticEuler) {
    Simulation sim;
    sim.root().set_gravity(Vec3(0, 0, -2));
    sim.root().set_dt(0.1);
    Node& body = sim.root().add_child("body");
    body.set_ode_solver<EulerExplicitSolver>();
    auto& dofs = body.add_state<Vec3Types>();
    dofs.position = {Vec3::Zero()};
    body.set_mass<UniformMass<Vec3Types>>(dofs).set_vertex_mass(3.0);
    sim.init();
    for (int n = 1; n <= 10; ++n) {
        sim.step();
        EXPECT_NEAR(dofs.velocity[0].z(), -0.2 * n, 1e-13);
        EXPECT_NEAR(dofs.position[0].z(), -0.02 * n * (n + 1) / 2.0, 1e-13);
    }
}

TEST(EulerImplicitNewton, ConvergesOnStiffNonlinearSpringAndReportsIterations) {
    // A stiff spring rotating: Newton iterations converge the backward-Euler residual; the first
    // iterate equals the SOFA (one linear solve) step.
    auto make = [](bool newton_on, Simulation& sim) -> Vec3Object& {
        sim.root().set_gravity(Vec3::Zero());
        Node& anchor = sim.root().add_child("anchor");
        auto& a = anchor.add_state<Vec3Types>();
        a.position = {Vec3::Zero()};
        Node& n = sim.root().add_child("body");
        auto& s = n.set_ode_solver<EulerImplicitSolver>();
        s.cg.tolerance = 1e-14;
        s.cg.threshold = 1e-40;
        s.newton.enabled = newton_on;
        s.newton.max_iterations = 20;
        s.newton.tolerance = 1e-12;
        auto& x = n.add_state<Vec3Types>();
        x.position = {Vec3(1.3, 0, 0)};
        x.velocity = {Vec3(0, 5, 0)};
        n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(1.0);
        n.add_force_field<SpringForceField>(a, x).add_spring({0, 0, 1e4, 0, 1.0});
        sim.init();
        return x;
    };
    Simulation lin_sim, newton_sim;
    Vec3Object& xl = make(false, lin_sim);
    Vec3Object& xn = make(true, newton_sim);
    lin_sim.step();
    newton_sim.step();
    auto* solver = dynamic_cast<EulerImplicitSolver*>(newton_sim.root().children()[1]->ode_solver());
    ASSERT_NE(solver, nullptr);
    EXPECT_GE(solver->last_newton_iterations(), 3);
    EXPECT_LT(solver->last_newton_iterations(), 20);
    // Backward-Euler residual at the Newton solution: v1 − v0 − h f(x0 + h v1) / m = 0.
    const double h = 0.01;
    const Vec3 x1 = xn.position[0];
    const Vec3 v1 = xn.velocity[0];
    const double d = x1.norm();
    const Vec3 f = -1e4 * (d - 1.0) * x1 / d;
    EXPECT_LT((v1 - Vec3(0, 5, 0) - h * f).norm(), 1e-8);
    EXPECT_NEAR((x1 - Vec3(1.3, 0, 0) - h * v1).norm(), 0.0, 1e-12);
    // The linearised step is not a solution of the nonlinear residual.
    const Vec3 xl1 = xl.position[0];
    const Vec3 fl = -1e4 * (xl1.norm() - 1.0) * xl1 / xl1.norm();
    EXPECT_GT((xl.velocity[0] - Vec3(0, 5, 0) - h * fl).norm(), 1e-3);
}

/// One DOF on a spring (k = 100, L = 1, anchor at 0) with x0 = 1.1, v0 = 0.3, m = 2, no gravity:
/// one step of EulerImplicitSolver against the closed form of spec §10.2.
struct OneDofStep {
    double x, v;
};

OneDofStep one_dof_step(double rs, double rm, double vd, bool first_order, bool trapezoidal) {
    Simulation sim;
    sim.root().set_gravity(Vec3::Zero());
    Node& anchor = sim.root().add_child("anchor");
    auto& a = anchor.add_state<Vec3Types>();
    a.position = {Vec3::Zero()};
    Node& n = sim.root().add_child("body");
    auto& s = n.set_ode_solver<EulerImplicitSolver>();
    s.rayleigh_stiffness = rs;
    s.rayleigh_mass = rm;
    s.vdamping = vd;
    s.first_order = first_order;
    s.trapezoidal_scheme = trapezoidal;
    s.cg.tolerance = 1e-14;
    s.cg.threshold = 0;
    auto& x = n.add_state<Vec3Types>();
    x.position = {Vec3(1.1, 0, 0)};
    x.velocity = {Vec3(0.3, 0, 0)};
    n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(2.0);
    n.add_force_field<SpringForceField>(a, x).add_spring({0, 0, 100.0, 0.0, 1.0});
    sim.init();
    sim.step();
    EXPECT_EQ(x.velocity[0].y(), 0.0);
    return {x.position[0].x(), x.velocity[0].x()};
}

TEST(EulerImplicit, RayleighDampingFirstOrderTrapezoidalAndVdampingFollowTheFormulas) {
    const double h = 0.01, k = 100, m = 2, f = -10, v0 = 0.3, x0 = 1.1;
    {
        const double rs = 0.1, rm = 0.2, vd = 0.5;
        const double b = h * (f + (h + rs) * (-k) * v0 - rm * m * v0);
        const double a = (1 + h * rm) * m + h * (h + rs) * k;
        const double v1 = v0 + b / a;
        const auto r = one_dof_step(rs, rm, vd, false, false);
        EXPECT_NEAR(r.x, x0 + h * v1, 1e-14);
        EXPECT_NEAR(r.v, v1 * std::exp(-h * vd), 1e-14);
    }
    {
        const double rs = 0.05, rm = 0.3;
        const double b = h * (f + (0.5 * h + rs) * (-k) * v0 - rm * m * v0);
        const double a = (1 + 0.5 * h * rm) * m + 0.5 * h * (0.5 * h + rs) * k;
        const double v1 = v0 + b / a;
        const auto r = one_dof_step(rs, rm, 0, false, true);
        EXPECT_NEAR(r.v, v1, 1e-14);
        EXPECT_NEAR(r.x, x0 + h * v1, 1e-14);
    }
    {
        const double v1 = f / (m + h * k);  // first order: M v = f + h K v
        const auto r = one_dof_step(0, 0, 0, true, false);
        EXPECT_NEAR(r.v, v1, 1e-14);
        EXPECT_NEAR(r.x, x0 + h * v1, 1e-14);
    }
}

}  // namespace
}  // namespace penalty
