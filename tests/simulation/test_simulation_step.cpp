// The step's stages (simulation_step.cpp): SOFA's multi-step animation loop.
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

TEST(MultiStepAnimationLoop, CollisionsAndIntegrationsPerStepAndSofasTime) {
    struct Falling {  // the stage goes before the simulation it is registered with
        std::unique_ptr<Simulation> sim;
        std::unique_ptr<test::FunctionStage> stage;
        Simulation* operator->() const { return sim.get(); }
    };
    const auto falling = [](int collisions, int integrations, bool sofa_time, int& hooks) {
        Falling f{std::make_unique<Simulation>(), nullptr};
        Node& root = f.sim->root();
        root.set_dt(0.06);
        root.set_ode_solver<EulerExplicitSolver>();
        auto& x = root.add_state<Vec3Types>("point");
        x.position = {Vec3(0, 1, 0)};
        root.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(1.0);
        f.sim->set_multi_step(collisions, integrations, sofa_time);
        f.stage = std::make_unique<test::FunctionStage>(*f.sim, [&hooks] { ++hooks; });
        f.sim->init();
        return f;
    };
    int hooks = 0;
    auto multi = falling(2, 3, true, hooks);
    multi->step();
    EXPECT_EQ(hooks, 2);
    EXPECT_NEAR(multi->time(), 0.03, 1e-15);  // SOFA: start + integrationSteps · dt/6
    int plain_hooks = 0;
    auto plain = falling(1, 1, true, plain_hooks);
    plain->root().set_dt(0.06 / (2 * 3));  // the sub-step, computed as Simulation does
    for (int i = 0; i < 6; ++i) plain->step();
    const auto& a = dynamic_cast<const Vec3Object&>(*multi->root().state());
    const auto& b = dynamic_cast<const Vec3Object&>(*plain->root().state());
    EXPECT_EQ(a.position[0], b.position[0]);  // six integrations of dt/6, the same operations
    EXPECT_EQ(a.velocity[0], b.velocity[0]);
    int exact_hooks = 0;
    auto exact = falling(2, 3, false, exact_hooks);
    exact->step();
    EXPECT_NEAR(exact->time(), 0.06, 1e-15);
    EXPECT_THROW(multi->set_multi_step(0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
