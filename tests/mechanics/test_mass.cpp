// UniformMass (mechanics/mass.cpp): SOFA's vertex and total mass rules; a Rigid3 mass and inertia.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace penalty
