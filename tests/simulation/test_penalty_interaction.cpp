// Worked example E with the real PenaltyForceField of the response layer, through the adapter.

#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/penalty_interaction.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/function_stage.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

TEST(PenaltyInteraction, WorkedExampleEImplicitWithPenaltyForceField) {
    Simulation sim;
    Node& body = sim.root().add_child("sphere");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    solver.cg.tolerance = 1e-9;
    solver.cg.threshold = 1e-9;
    auto& sphere = body.add_state<Vec3Types>("sphere");
    sphere.position = {Vec3(0.2, 0.9, 0.3)};
    body.set_mass<UniformMass<Vec3Types>>(sphere).set_vertex_mass(1.0);
    Node& floor_node = sim.root().add_child("floor");
    auto& floor = floor_node.add_state<Vec3Types>("floor");
    floor.position = {Vec3(0.2, 0.0, 0.3)};
    // Static vs simulated: the contact sits in the simulated object's subtree (implicit).
    PenaltyForceField field;
    auto& contact = body.add_force_field<PenaltyInteraction>(floor, sphere, field);
    const test::FunctionStage detection(sim, [&] {
        // Detection at the start of the step: the projection onto the floor follows the sphere.
        floor.position[0] = Vec3(sphere.position[0].x(), 0.0, sphere.position[0].z());
        contact.field().clear(1);
        contact.field().add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3(0, 1, 0), 1.0,
                                    100.0);
    });
    sim.init();
    const double v[5] = {0.0018811881188119, 0.0037251249877462, 0.0055139226303769, 0.0072304161118887,
                         0.0088583263300995};
    const double y[5] = {0.9000188118811882, 0.9000560631310656, 0.9001112023573693, 0.9001835065184882,
                         0.9002720897817892};
    for (int s = 0; s < 5; ++s) {
        sim.step();
        EXPECT_NEAR(sphere.velocity[0].y(), v[s], 1e-12) << "step " << s + 1;
        EXPECT_NEAR(sphere.position[0].y(), y[s], 1e-12) << "step " << s + 1;
    }
    EXPECT_GT(contact.potential_energy(), 0.0);
}

}  // namespace
}  // namespace penalty
