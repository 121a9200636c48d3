// A subtree's forces and products (subtree_products.cpp): compute_force as the external forces,
// the masses' gravity and the fields' forces, and apply_mbk's (m·M + k·K)·dx, against their
// closed forms for two points of 2 kg joined by a spring (ks 50, rest length 1), projected by a
// fixed point or not, accumulated or not; dot's sum.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace penalty {
namespace {

/// Two points (0,0,0) and (`length`,0,0) of 2 kg, a spring between them (ks 50, rest 1), g = (0, −10, 0);
/// point 0 fixed when `fixed`.
struct SpringPair {
    Simulation sim;
    Vec3Object* x = nullptr;
    SpringPair(double length, bool fixed) {
        Node& root = sim.root();
        root.set_gravity(Vec3(0, -10, 0));
        root.set_ode_solver<EulerImplicitSolver>();
        x = &root.add_state<Vec3Types>("pair");
        x->position = {Vec3(0, 0, 0), Vec3(length, 0, 0)};
        root.set_mass<UniformMass<Vec3Types>>(*x).set_vertex_mass(2.0);
        root.add_force_field<SpringForceField>(*x, *x).add_spring({0, 1, 50.0, 0.0, 1.0});
        if (fixed) root.add_constraint<FixedProjectiveConstraint>(*x).set_indices({0});
        sim.init();
    }
};

TEST(SubtreeProducts, TheForceIsTheExternalForceGravityAndTheSprings) {
    // stretched by 0.5: 25 N pulling the points together, 2·(−10) each, and an external force
    // of 7 N along z on point 1 (the state's external_force, where the sum starts)
    SpringPair s(1.5, false);
    s.x->external_force[1] = Vec3(0, 0, 7);
    SubtreeSystem sys(s.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    sys.compute_force(f);
    ASSERT_EQ(f.size(), 6);
    Eigen::VectorXd expected(6);
    expected << 25, -20, 0, -25, -20, 7;
    EXPECT_EQ(f, expected);
}

TEST(SubtreeProducts, TheProductIsTheMassAndStiffnessTimesDx) {
    // at the rest length the spring's K has no geometric part: K₀₀ = K₁₁ = −ks·x̂x̂ᵀ, K₀₁ = K₁₀ =
    // ks·x̂x̂ᵀ; (1.5·M − 0.4·K)·p with M = 2·I
    SpringPair s(1.0, false);
    SubtreeSystem sys(s.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    sys.compute_force(f);  // the spring keeps the derivative of its last force
    Eigen::VectorXd p(6);
    p << 0.5, -1, 2, -0.25, 3, 1;
    Eigen::VectorXd q;
    sys.apply_mbk(p, q, 1.5, 0.0, -0.4, false);
    // K·p: x components 50·(p₁ₓ − p₀ₓ) = −37.5 on point 0, +37.5 on point 1
    Eigen::VectorXd expected = 3.0 * p;
    expected[0] += -0.4 * -37.5;
    expected[3] += -0.4 * 37.5;
    EXPECT_LT((q - expected).cwiseAbs().maxCoeff(), 1e-13) << q.transpose();
    // accumulated into what is there
    Eigen::VectorXd sum = Eigen::VectorXd::Ones(6);
    sys.apply_mbk(p, sum, 1.5, 0.0, -0.4, false, true);
    EXPECT_LT((sum - (expected + Eigen::VectorXd::Ones(6))).cwiseAbs().maxCoeff(), 1e-13);
    // dot: Σ aᵢbᵢ
    EXPECT_EQ(sys.dot(p, p), 0.25 + 1 + 4 + 0.0625 + 9 + 1);
}

TEST(SubtreeProducts, AFixedPointsRowsAreProjectedOut) {
    SpringPair s(1.0, true);
    SubtreeSystem sys(s.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f;
    sys.compute_force(f);
    Eigen::VectorXd p(6);
    p << 0.5, -1, 2, -0.25, 3, 1;
    Eigen::VectorXd projected, free;
    sys.apply_mbk(p, projected, 1.5, 0.0, -0.4, true);
    sys.apply_mbk(p, free, 1.5, 0.0, -0.4, false);
    EXPECT_EQ(projected.head<3>(), Eigen::Vector3d::Zero());
    EXPECT_EQ(projected.tail<3>(), free.tail<3>());
    EXPECT_NE(free.head<3>(), Eigen::Vector3d::Zero());
    // the projection applies to the sum when accumulating
    Eigen::VectorXd sum = Eigen::VectorXd::Ones(6);
    sys.apply_mbk(p, sum, 1.5, 0.0, -0.4, true, true);
    EXPECT_EQ(sum.head<3>(), Eigen::Vector3d::Zero());
    EXPECT_LT((sum.tail<3>() - (free.tail<3>() + Eigen::Vector3d::Ones())).cwiseAbs().maxCoeff(), 1e-13);
}

}  // namespace
}  // namespace penalty
