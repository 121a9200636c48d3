// Simulation (simulation/simulation.cpp): bad input to the graph and the solver throws; thread
// counts outside [0, kMaxThreads] are refused.
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

namespace penalty {
namespace {

TEST(Simulation, BadInputThrows) {
    Simulation sim;
    EXPECT_THROW(sim.root().set_dt(-1), std::invalid_argument);
    EXPECT_THROW(sim.root().set_gravity(Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)), std::invalid_argument);
    Node& n = sim.root().add_child("n");
    auto& x = n.add_state<Vec3Types>();
    x.position = {Vec3::Zero()};
    EXPECT_THROW(n.add_state<Vec3Types>(), std::invalid_argument);
    auto& m = n.set_mass<UniformMass<Vec3Types>>(x);
    EXPECT_THROW(m.set_vertex_mass(-1), std::invalid_argument);
    EXPECT_THROW(sim.init(), std::invalid_argument);  // neither vertexMass nor totalMass
    auto& s = n.set_ode_solver<EulerImplicitSolver>();
    s.rayleigh_stiffness = -0.1;
    m.set_vertex_mass(1);
    EXPECT_THROW(sim.init(), std::invalid_argument);
}

TEST(Simulation, ThreadsOutsideTheRangeAreRefused) {
    Simulation sim;
    EXPECT_THROW(sim.set_threads(-1), std::invalid_argument);
    EXPECT_THROW(sim.set_threads(kMaxThreads + 1), std::invalid_argument);
    sim.set_threads(kMaxThreads);
    EXPECT_EQ(sim.threads(), kMaxThreads);
}

}  // namespace
}  // namespace penalty
