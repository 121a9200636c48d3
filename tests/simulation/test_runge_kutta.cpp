// RungeKutta2Solver / RungeKutta4Solver: their orders of convergence on an oscillator.
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

/// A 2 kg point on a rest spring of 50 N/m, released at 0.3 m, integrated to t = 1 s with `steps`
/// steps; returns |x − x_exact| with x_exact = 0.3 cos(5 t).
template <class Solver>
double oscillator_error(int steps) {
    Simulation sim;
    Node& root = sim.root();
    root.set_gravity(Vec3::Zero());
    root.set_dt(1.0 / steps);
    root.set_ode_solver<Solver>();
    auto& x = root.add_state<Vec3Types>("point");
    x.position = {Vec3(0, 0, 0)};
    x.rest_position = {Vec3(0, 0, 0)};
    root.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(2.0);
    root.add_force_field<RestShapeSpringsForceField<Vec3Types>>(x).set_stiffness({50.0});
    sim.init();
    x.position[0].x() = 0.3;
    for (int s = 0; s < steps; ++s) sim.step();
    return std::abs(x.position[0].x() - 0.3 * std::cos(5.0));
}

TEST(RungeKutta, TheClassicalSchemeHasGlobalOrderFourAndTheMidpointOrderTwo) {
    const double e4[3] = {oscillator_error<RungeKutta4Solver>(20), oscillator_error<RungeKutta4Solver>(40),
                          oscillator_error<RungeKutta4Solver>(80)};
    const double e2[3] = {oscillator_error<RungeKutta2Solver>(20), oscillator_error<RungeKutta2Solver>(40),
                          oscillator_error<RungeKutta2Solver>(80)};
    for (int i = 0; i < 2; ++i) {
        const double order4 = std::log2(e4[i] / e4[i + 1]);
        const double order2 = std::log2(e2[i] / e2[i + 1]);
        EXPECT_NEAR(order4, 4.0, 0.15) << "h = 1/" << 20 * (1 << i);
        EXPECT_NEAR(order2, 2.0, 0.15) << "h = 1/" << 20 * (1 << i);
    }
    EXPECT_LT(e4[2], 1e-6);
}

TEST(RungeKutta, AnExplicitSolverRefusesAConsistentMassMatrixAndAMasslessState) {
    for (const bool with_mass : {true, false}) {
        Simulation sim;
        Node& root = sim.root();
        root.set_ode_solver<RungeKutta4Solver>();
        auto& x = root.add_state<Vec3Types>("tetra");
        x.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
        MeshTopology t;
        t.set_tetrahedra({{0, 1, 2, 3}});
        if (with_mass) root.set_mass<MeshMatrixMass>(x, t);
        EXPECT_THROW(sim.init(), std::invalid_argument) << (with_mass ? "consistent mass" : "no mass");
    }
}

}  // namespace
}  // namespace penalty
