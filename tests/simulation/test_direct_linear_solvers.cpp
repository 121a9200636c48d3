// The direct linear solvers inside the implicit Euler step.
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
#include <functional>
#include <memory>
#include <string>

namespace penalty {
namespace {

TEST(DirectSolvers, TheImplicitEulerStepEqualsTheTightCgStep) {
    // the same scene stepped with CG run to 1e-15 and with each direct solver
    const auto run = [](std::shared_ptr<DirectLinearSolver> direct) {
        Simulation sim;
        Node& body = sim.root();
        auto& solver = body.set_ode_solver<EulerImplicitSolver>();
        solver.rayleigh_stiffness = 0.1;
        solver.rayleigh_mass = 0.05;
        solver.cg.iterations = 1000;
        solver.cg.tolerance = 1e-15;
        solver.cg.threshold = 1e-30;
        solver.direct_solver = std::move(direct);
        auto& x = body.add_state<Vec3Types>("swing");
        for (int i = 0; i < 4; ++i) x.position.emplace_back(0.25 * i, -0.1 * i * i, 0.05 * i);
        body.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(0.2);
        auto& springs = body.add_force_field<SpringForceField>(x, x);
        for (int i = 0; i < 3; ++i) springs.add_spring({i, i + 1, 500.0, 0.0, 0.2});
        body.add_constraint<FixedProjectiveConstraint>(x).set_indices({0});
        sim.init();
        for (int s = 0; s < 10; ++s) sim.step();
        return x.position;
    };
    const std::vector<Vec3> cg = run(nullptr);
    for (FactorizationMethod method :
         {FactorizationMethod::ldlt, FactorizationMethod::llt, FactorizationMethod::lu, FactorizationMethod::qr}) {
        auto direct = std::make_shared<DirectLinearSolver>();
        direct->method = method;
        const std::vector<Vec3> x = run(direct);
        for (std::size_t i = 0; i < x.size(); ++i)
            EXPECT_LT((x[i] - cg[i]).norm(), 1e-12) << factorization_name(method) << " point " << i;
        EXPECT_EQ(direct->factorizations(), 10);
    }
}

/// Massless points on a line in the root node, stepped by an implicit Euler solver with a direct
/// solver of `method`; `add_fields` adds force fields over them before init.
struct MasslessPointsOnADirectSolver {
    Simulation sim;
    std::shared_ptr<DirectLinearSolver> direct = std::make_shared<DirectLinearSolver>();
    MasslessPointsOnADirectSolver(FactorizationMethod method, int points,
                                  const std::function<void(Node&, Vec3Object&)>& add_fields) {
        Node& body = sim.root();
        body.set_ode_solver<EulerImplicitSolver>().direct_solver = direct;
        direct->method = method;
        auto& x = body.add_state<Vec3Types>("massless");
        for (int i = 0; i < points; ++i) x.position.emplace_back(0.1 * i, 0.0, 0.0);
        add_fields(body, x);
        sim.init();
    }
    /// The first step fails with a SingularSystemError naming this solver, its message holding
    /// `message`.
    void expect_first_step_singular(const std::string& message) {
        try {
            sim.step();
            ADD_FAILURE() << factorization_name(direct->method) << ": no error";
        } catch (const SingularSystemError& e) {
            EXPECT_EQ(e.solver(), direct.get());
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
    }
};

// A solver over a state with neither mass nor force field assembles a matrix without a stored
// entry: every direct method reports it (SingularSystemError, naming the solver) at the first step.
// Eigen's SparseLU, given it, never returned (a fuzz finding: fuzz/regressions/
// zero_system_sparse_lu.scn).
TEST(DirectSolvers, AZeroSystemIsReportedSingularByEveryMethod) {
    for (FactorizationMethod method :
         {FactorizationMethod::ldlt, FactorizationMethod::llt, FactorizationMethod::lu, FactorizationMethod::qr})
        MasslessPointsOnADirectSolver(method, 8, [](Node&, Vec3Object&) {})
            .expect_first_step_singular(
                "the system matrix is zero: its 24 unknowns have no mass, stiffness nor constraint");
}

// A finite matrix that does not factorize is singular as well: massless points joined by springs
// of zero stiffness store zeros, which the factorizations that need a pivot refuse. A scene
// defect (SingularSystemError naming the solver), not a divergence; a non-finite matrix stays a
// NonFiniteSolveError (tests of the divergence checks).
TEST(DirectSolvers, AFiniteMatrixThatDoesNotFactorizeIsReportedSingular) {
    for (FactorizationMethod method : {FactorizationMethod::ldlt, FactorizationMethod::llt, FactorizationMethod::lu})
        MasslessPointsOnADirectSolver(method, 4, [](Node& body, Vec3Object& x) {
            auto& springs = body.add_force_field<SpringForceField>(x, x);
            springs.add_spring({0, 1, 0.0, 0.0, 0.1});
            springs.add_spring({2, 3, 0.0, 0.0, 0.1});
        }).expect_first_step_singular("the factorization failed: the system matrix is singular");
}

}  // namespace
}  // namespace penalty
