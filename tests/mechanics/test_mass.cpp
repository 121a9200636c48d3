// UniformMass (mechanics/mass.cpp): SOFA's vertex and total mass rules; a Rigid3 mass and inertia.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cstring>
#include <limits>
#include <random>

namespace penalty {
namespace {

TEST(UniformMass, VertexAndTotalMassRules) {
    Vec3Object s;
    s.position = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    s.velocity = {Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), Vec3(0, 2, 0)};
    s.init();
    UniformMass<Vec3Types> m(s);
    EXPECT_THROW(m.init(), std::invalid_argument);
    m.set_vertex_mass(3.0);
    m.init();
    EXPECT_EQ(m.vertex_mass(), 3.0);
    m.set_total_mass(2.0);  // totalMass wins
    m.init();
    EXPECT_EQ(m.vertex_mass(), 0.5);
    EXPECT_NEAR(m.kinetic_energy(), 0.5 * 0.5 * 5.0, 1e-15);
    m.add_gravity_force(Vec3(0, -10, 0));
    EXPECT_EQ(s.force[2], Vec3(0, -5, 0));
    EXPECT_NEAR(m.gravity_potential_energy(Vec3(0, -10, 0)), 0.5 * 10 * 1.0, 1e-15);
    EXPECT_THROW(m.set_total_mass(0.0), std::invalid_argument);
    EXPECT_THROW(m.set_vertex_mass(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

TEST(UniformMass, Rigid3MassAndInertia) {
    Rigid3Object s;
    s.position.resize(1);
    s.init();
    UniformMass<Rigid3Types> m(s);
    m.set_vertex_mass(2.0);
    Mat3 j = Mat3::Identity();
    j(2, 2) = 3.0;
    m.set_inertia(j);
    m.init();
    s.dx[0].linear = Vec3(1, 0, 0);
    s.dx[0].angular = Vec3(0, 0, 1);
    m.add_mdx(0.5);
    EXPECT_EQ(s.df[0].linear, Vec3(1, 0, 0));
    EXPECT_EQ(s.df[0].angular, Vec3(0, 0, 3));
    Eigen::VectorXd in(6), out(6);
    in << 2, 0, 0, 0, 0, 6;
    m.apply_inverse(in, out);
    EXPECT_NEAR(out[0], 1.0, 1e-15);
    EXPECT_NEAR(out[5], 1.0, 1e-15);
    m.add_gravity_force(Vec3(0, -1, 0));
    EXPECT_EQ(s.force[0].linear, Vec3(0, -2, 0));
    EXPECT_EQ(s.force[0].angular, Vec3::Zero());
    EXPECT_THROW(m.set_inertia(-Mat3::Identity()), std::invalid_argument);
}

// A large state's M·dx on threads (each DOF its own range's): the bits of one thread.
TEST(UniformMass, AddMdxOnThreadsIsTheBitsOfOneThread) {
    Vec3Object s;
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    s.position.resize(detail::OrderedScatter::kMinElements + 777);
    for (Vec3& x : s.position) x = Vec3(u(rng), u(rng), u(rng));
    s.init();
    UniformMass<Vec3Types> m(s);
    m.set_total_mass(3.7);
    m.init();
    for (Vec3& d : s.dx) d = Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> start(s.dx.size());
    for (Vec3& d : start) d = Vec3(u(rng), u(rng), u(rng));
    const auto product = [&](int threads) {
        s.df.assign(start.begin(), start.end());
        tbb::task_arena(threads).execute([&] { m.add_mdx(-0.37); });
        return std::vector<Vec3>(s.df.begin(), s.df.end());
    };
    const std::vector<Vec3> one = product(1);
    EXPECT_NE(std::memcmp(one.data(), start.data(), one.size() * sizeof(Vec3)), 0);
    for (const int threads : {2, 8}) {
        const std::vector<Vec3> many = product(threads);
        EXPECT_EQ(std::memcmp(many.data(), one.data(), one.size() * sizeof(Vec3)), 0) << threads << " threads";
    }
}

}  // namespace
}  // namespace penalty
