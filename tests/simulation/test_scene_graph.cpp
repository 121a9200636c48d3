// Rigid bodies in the scene graph: torque-free rotation and free fall, a rigid-mapped spring pendulum.
#include "penalty/mechanics/external_loads.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/penalty_interaction.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace penalty {
namespace {

TEST(RigidBody, TorqueFreeRotationAndFreeFall) {
    Simulation sim;
    Node& n = sim.root().add_child("rigid");
    auto& s = n.set_ode_solver<EulerImplicitSolver>();
    s.cg.tolerance = 1e-14;
    s.cg.threshold = 1e-30;
    auto& x = n.add_state<Rigid3Types>();
    x.position = {RigidFrame{}};
    x.velocity = {RigidDeriv{Vec3::Zero(), Vec3(0, 0, 2.0)}};  // 2 rad/s about z
    n.set_mass<UniformMass<Rigid3Types>>(x).set_vertex_mass(3.0);
    sim.init();
    const int steps = 100;
    for (int i = 0; i < steps; ++i) sim.step();
    // Centre: exact free fall; angular velocity unchanged; orientation ≈ 2 rad about z
    // (first-order quaternion update: error O(h) in angle over the run).
    EXPECT_NEAR(x.position[0].center.y(), -9.81 * 0.01 * 0.01 * steps * (steps + 1) / 2.0, 1e-10);
    EXPECT_NEAR(x.velocity[0].angular.z(), 2.0, 1e-14);
    const Eigen::AngleAxisd aa(x.position[0].orientation);
    EXPECT_NEAR(aa.angle(), 2.0, 2e-3);
    EXPECT_NEAR(std::abs(aa.axis().z()), 1.0, 1e-12);
    EXPECT_NEAR(x.position[0].orientation.norm(), 1.0, 1e-14);
}

TEST(RigidBody, RigidMappedSpringPendulumSwingsAndStaysBounded) {
    // A rigid body hanging from a static anchor by a spring attached to a rigid-mapped point:
    // exercises Jᵀ torque through RigidMapping inside an implicit solve.
    Simulation sim;
    Node& anchor = sim.root().add_child("anchor");
    auto& a = anchor.add_state<Vec3Types>();
    a.position = {Vec3(0, 0, 0)};
    Node& body = sim.root().add_child("body");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    solver.cg.tolerance = 1e-12;
    solver.cg.threshold = 1e-30;
    auto& r = body.add_state<Rigid3Types>();
    r.position = {RigidFrame{Vec3(1, -1, 0), Quat::Identity()}};
    body.set_mass<UniformMass<Rigid3Types>>(r).set_vertex_mass(1.0);
    Node& pt = body.add_child("attach");
    auto& p = pt.add_state<Vec3Types>();
    pt.set_mapping<RigidMapping>(r, p).set_points({Vec3(-0.5, 0.5, 0)});
    body.add_force_field<SpringForceField>(a, p).add_spring({0, 0, 500.0, 0.0, 0.5});
    sim.init();
    double max_omega = 0;
    for (int i = 0; i < 100; ++i) {
        sim.step();
        max_omega = std::max(max_omega, r.velocity[0].angular.norm());
        ASSERT_TRUE(r.position[0].center.allFinite());
    }
    EXPECT_GT(max_omega, 0.1);  // the off-centre spring makes it rotate
    EXPECT_LT(r.position[0].center.norm(), 3.0);
    // The mapped point follows the frame after the step.
    EXPECT_TRUE(p.position[0].isApprox(r.position[0].center + r.position[0].orientation * Vec3(-0.5, 0.5, 0), 1e-12));
}

}  // namespace
}  // namespace penalty
