// A subtree's forces and products (subtree_products.cpp): compute_force as the external forces,
// the masses' gravity and the fields' forces, and apply_mbk's (m·M + k·K)·dx, against their
// closed forms for two points of 2 kg joined by a spring (ks 50, rest length 1), projected by a
// fixed point or not, accumulated or not; dot's sum.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <Eigen/Dense>

#include <random>

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

// 400 bodies of 8 points under one solver (9 600 unknowns, above
// kMinUnknownsForConcurrentStatePasses): dot, direction_and_mbk and update_and_residual run state
// by state on two threads and give the bits of one thread; dot is SOFA's chain, each state's sum
// added in order.
TEST(SubtreeProducts, StatePassesOnThreadsAreTheBitsOfOneThreadAndSofasChain) {
    const tbb::global_control two_workers(tbb::global_control::max_allowed_parallelism, 2);
    Simulation sim;
    sim.root().set_ode_solver<EulerImplicitSolver>();
    std::vector<Vec3Object*> states;
    for (int b = 0; b < 400; ++b) {
        Node& n = sim.root().add_child("body" + std::to_string(b));
        Vec3Object& x = n.add_state<Vec3Types>();
        for (int i = 0; i < 8; ++i) x.position.push_back(Vec3(b, 0.3 * i, 0.01 * i * i));
        n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(0.5 + 0.001 * b);
        auto& springs = n.add_force_field<SpringForceField>(x, x);
        for (int i = 0; i + 1 < 8; ++i) springs.add_spring({i, i + 1, 40.0 + b, 0.1, 0.25});
        states.push_back(&x);
    }
    sim.init();
    SubtreeSystem sys(sim.root());
    ASSERT_EQ(sys.size(), 9600);
    std::mt19937 rng(61);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto random_vector = [&] {
        Eigen::VectorXd v(sys.size());
        for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = unit(rng);
        return v;
    };
    const Eigen::VectorXd r0 = random_vector(), p0 = random_vector(), x0 = random_vector();
    struct Results {
        double dot = 0, pq = 0, rr = 0;
        Eigen::VectorXd p, q, x, r;
    };
    const auto run = [&](int threads) {
        Results out;
        tbb::task_arena(threads).execute([&] {
            out.dot = sys.dot(r0, p0);
            out.p = p0;
            out.pq = sys.direction_and_mbk(r0, 0.37, false, out.p, out.q, 1.02, -0.01, -2e-4);
            out.x = x0;
            out.r = r0;
            out.rr = sys.update_and_residual(0.61, out.p, out.q, out.x, out.r);
        });
        return out;
    };
    const Results one = run(1);
    EXPECT_EQ(sys.concurrent_state_passes(), 0u);
    const Results two = run(2);
    EXPECT_EQ(sys.concurrent_state_passes(), 4u);  // dot, the direction, p·q, update
    EXPECT_TRUE(test::same_bits(one.dot, two.dot));
    EXPECT_TRUE(test::same_bits(one.pq, two.pq));
    EXPECT_TRUE(test::same_bits(one.rr, two.rr));
    long differing = 0;
    for (Eigen::Index i = 0; i < sys.size(); ++i)
        differing += !test::same_bits(one.p[i], two.p[i]) + !test::same_bits(one.q[i], two.q[i]) +
                     !test::same_bits(one.x[i], two.x[i]) + !test::same_bits(one.r[i], two.r[i]);
    EXPECT_EQ(differing, 0);
    // SOFA's chain: each body's Σ ((a_x·b_x + a_y·b_y) + a_z·b_z), the bodies' sums added in order
    double chain = 0.0;
    for (Eigen::Index body = 0; body < 400; ++body) {
        double sum = 0.0;
        for (Eigen::Index j = 24 * body; j < 24 * body + 24; j += 3)
            sum += (r0[j] * p0[j] + r0[j + 1] * p0[j + 1]) + r0[j + 2] * p0[j + 2];
        chain += sum;
    }
    EXPECT_TRUE(test::same_bits(chain, two.dot));
    EXPECT_NE(r0.dot(p0), two.dot);  // another order gives other bits here: the check can fail
}

// One body of 4 000 points (12 000 unknowns in one state): the CG's passes without a sum (the
// direction, df cleared, the blocked mode's copy of q) split the state into pieces on two threads,
// with the bits of one thread; the sums stay the state's single chain.
TEST(SubtreeProducts, ALargeStatesPassesWithoutASumSplitIntoPieces) {
    const tbb::global_control two_workers(tbb::global_control::max_allowed_parallelism, 2);
    Simulation sim;
    sim.root().set_ode_solver<EulerImplicitSolver>();
    Vec3Object& x = sim.root().add_state<Vec3Types>();
    for (int i = 0; i < 4000; ++i) x.position.push_back(Vec3(0.01 * i, 0.3 * (i % 7), 0.001 * i * (i % 3)));
    sim.root().set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(0.7);
    auto& springs = sim.root().add_force_field<SpringForceField>(x, x);
    for (int i = 0; i + 1 < 4000; ++i) springs.add_spring({i, i + 1, 50.0 + i % 11, 0.1, 0.02});
    sim.init();
    for (const bool blocked : {false, true}) {
        SubtreeSystem sys(sim.root());
        sys.set_blocked_reductions(blocked);
        ASSERT_EQ(sys.size(), 12000);
        ASSERT_GE(sys.size(), SubtreeSystem::kMinUnknownsForConcurrentStatePasses);
        std::mt19937 rng(67);
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        Eigen::VectorXd r0(sys.size()), p0(sys.size());
        for (Eigen::Index i = 0; i < r0.size(); ++i) r0[i] = unit(rng), p0[i] = unit(rng);
        const auto run = [&](int threads, Eigen::VectorXd& p, Eigen::VectorXd& q) {
            p = p0;
            double pq = 0.0;
            tbb::task_arena(threads).execute(
                [&] { pq = sys.direction_and_mbk(r0, 0.37, false, p, q, 1.02, -0.01, -2e-4); });
            return pq;
        };
        Eigen::VectorXd p1, q1, p2, q2;
        const double one = run(1, p1, q1);
        EXPECT_EQ(sys.concurrent_state_passes(), 0u);
        const double two = run(2, p2, q2);
        // the direction's pieces, and in blocked mode q's copy
        EXPECT_EQ(sys.concurrent_state_passes(), blocked ? 2u : 1u);
        EXPECT_TRUE(test::same_bits(one, two)) << blocked;
        long differing = 0;
        for (Eigen::Index i = 0; i < sys.size(); ++i)
            differing += !test::same_bits(p1[i], p2[i]) + !test::same_bits(q1[i], q2[i]);
        EXPECT_EQ(differing, 0) << blocked;
    }
}

}  // namespace
}  // namespace penalty
