// BeamFEMForceField: SOFA's local stiffness in closed form, a cantilever's tip deflection PL³/3EI
// and rotation PL²/2EI (Euler–Bernoulli beams are exact at the nodes under end loads), axial and
// torsional compliance, a stress-free rigid motion, and the derivatives: K = ∂f/∂x by finite
// differences at rest (any rigid placement), f = −∂E/∂x in the centres, assembled = add_dforce;
// the force and product on threads (the bits of one thread).
#include "penalty/mechanics/beam_fem_force_field.hpp"

#include "penalty_test/rigid_derivatives.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>

namespace penalty {
namespace {

/// n + 1 frames along `axis` from the origin, spacing `step`, every orientation `q`.
Rigid3Object beam_frames(int n, double step, const Vec3& axis, const Quat& q = Quat::Identity()) {
    Rigid3Object s;
    for (int i = 0; i <= n; ++i) s.position.push_back(RigidFrame{axis.normalized() * (step * i), q});
    s.init();
    return s;
}

std::vector<std::array<Index, 2>> chain(int n) {
    std::vector<std::array<Index, 2>> beams;
    for (int i = 0; i < n; ++i) beams.push_back({i, i + 1});
    return beams;
}

BeamParameters steel_rod() {
    BeamParameters p;
    p.young_modulus = {2.0e5};
    p.poisson_ratio = {0.3};
    p.radius = 0.05;
    return p;
}

TEST(BeamFEMForceField, LocalStiffnessInClosedForm) {
    Rigid3Object s = beam_frames(1, 2.0, Vec3::UnitX());
    BeamFEMForceField ff(s, chain(1), steel_rod());
    ff.init();
    const double e = 2.0e5, l = 2.0, r = 0.05, g = e / 2.6;
    const double a = std::numbers::pi * r * r, i = std::numbers::pi * r * r * r * r / 4, j = 2 * i;
    const auto& k = ff.local_stiffness(0);
    EXPECT_NEAR(k(0, 0), e * a / l, 1e-9 * e * a / l);
    EXPECT_NEAR(k(1, 1), 12 * e * i / (l * l * l), 1e-12);
    EXPECT_NEAR(k(5, 1), 6 * e * i / (l * l), 1e-12);
    EXPECT_NEAR(k(5, 5), 4 * e * i / l, 1e-12);
    EXPECT_NEAR(k(11, 5), 2 * e * i / l, 1e-12);
    EXPECT_NEAR(k(3, 3), g * j / l, 1e-12);
    EXPECT_NEAR(k(4, 2), -6 * e * i / (l * l), 1e-12);
    EXPECT_TRUE(k.isApprox(k.transpose(), 0.0));
}

/// Static linear solve with frame 0 clamped: u = (−K_ff)⁻¹ f_ext over the other frames' DOFs.
Eigen::VectorXd cantilever_displacement(BeamFEMForceField& ff, Rigid3Object& s, const Eigen::VectorXd& load) {
    ff.accumulate_force();
    const auto n = static_cast<Eigen::Index>(6 * s.num_dofs());
    const Eigen::MatrixXd k = test::assembled_stiffness(ff, n);
    const Eigen::MatrixXd kff = -k.bottomRightCorner(n - 6, n - 6);
    return kff.ldlt().solve(load.tail(n - 6));
}

TEST(BeamFEMForceField, CantileverTipDeflectionAndRotation) {
    for (int elements : {1, 4}) {
        const double length = 3.0, p = 0.02;
        Rigid3Object s = beam_frames(elements, length / elements, Vec3::UnitX());
        BeamFEMForceField ff(s, chain(elements), steel_rod());
        ff.init();
        const auto n = static_cast<Eigen::Index>(6 * s.num_dofs());
        Eigen::VectorXd load = Eigen::VectorXd::Zero(n);
        load[n - 6 + 1] = p;  // tip force along y
        const Eigen::VectorXd u = cantilever_displacement(ff, s, load);
        const double ei = 2.0e5 * std::numbers::pi * std::pow(0.05, 4) / 4;
        EXPECT_NEAR(u[u.size() - 6 + 1], p * length * length * length / (3 * ei), 1e-9) << elements << " elements";
        EXPECT_NEAR(u[u.size() - 6 + 5], p * length * length / (2 * ei), 1e-9) << elements << " elements";
    }
}

TEST(BeamFEMForceField, AxialAndTorsionalCompliance) {
    const double length = 2.0;
    Rigid3Object s = beam_frames(2, length / 2, Vec3::UnitX());
    BeamFEMForceField ff(s, chain(2), steel_rod());
    ff.init();
    Eigen::VectorXd load = Eigen::VectorXd::Zero(18);
    load[12] = 3.0;  // tip axial force
    load[15] = 0.5;  // tip torque about x
    const Eigen::VectorXd u = cantilever_displacement(ff, s, load);
    const double e = 2.0e5, r = 0.05, a = std::numbers::pi * r * r, j = std::numbers::pi * std::pow(r, 4) / 2;
    EXPECT_NEAR(u[6], 3.0 * length / (e * a), 1e-12);
    EXPECT_NEAR(u[9], 0.5 * length / (e / 2.6 * j), 1e-9);
}

TEST(BeamFEMForceField, TheCorotationalForceBalancesTheLoadAtTheLinearSolution) {
    // a beam along a tilted direction, its frames turned to match: the nonlinear force at the
    // linear solution of a small tip load is minus that load. SOFA's corotational frame is node a's
    // (not the chord): the axial strain is of second order in the rotations, θ²·L, times the stiff
    // EA/L, so the balance holds to a relative error of order EA·θ²·L/P, which scales with the load
    const Vec3 axis = Vec3(1, 1, 0.5).normalized();
    const Quat q = Quat::FromTwoVectors(Vec3::UnitX(), axis);
    Rigid3Object s = beam_frames(3, 1.0, axis, q);
    BeamFEMForceField ff(s, chain(3), steel_rod());
    ff.init();
    Eigen::VectorXd load = Eigen::VectorXd::Zero(24);
    load.segment<3>(18) = q * Vec3(0, 0, 1e-9);
    const Eigen::VectorXd u = cantilever_displacement(ff, s, load);
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(24);
    delta.tail(18) = u;
    const Eigen::VectorXd f = test::rigid_force_at(ff, s, s.position, delta);
    EXPECT_LT((f.tail(18) + load.tail(18)).cwiseAbs().maxCoeff(), 1e-3 * load.cwiseAbs().maxCoeff())
        << "f " << f.tail(18).transpose();
}

TEST(BeamFEMForceField, RigidMotionIsStressFree) {
    Rigid3Object s = beam_frames(2, 1.0, Vec3::UnitY());
    BeamFEMForceField ff(s, chain(2), steel_rod());
    ff.init();
    const Quat turn(Eigen::AngleAxisd(1.1, Vec3(1, 0, 2).normalized()));
    for (RigidFrame& f : s.position) {
        f.center = turn * f.center + Vec3(3, -1, 2);
        f.orientation = turn * f.orientation;
    }
    ff.accumulate_force();
    for (const RigidDeriv& f : s.force) EXPECT_LT(f.linear.norm() + f.angular.norm(), 1e-9);
}

TEST(BeamFEMForceField, DerivativesAtRestInAnyPlacement) {
    const Quat q(Eigen::AngleAxisd(0.8, Vec3(2, -1, 1).normalized()));
    Rigid3Object s = beam_frames(2, 0.7, q * Vec3::UnitX(), q);
    BeamParameters p = steel_rod();
    p.young_modulus = {1.0e3};
    BeamFEMForceField ff(s, chain(2), p);
    ff.init();
    const Eigen::MatrixXd fd = test::rigid_force_jacobian(ff, s);
    const Eigen::MatrixXd k = test::rigid_dforce_matrix(ff, s);
    EXPECT_TRUE(test::near_relative(k, fd, 1e-6)) << "max diff " << (k - fd).cwiseAbs().maxCoeff();
    EXPECT_TRUE(test::near_relative(test::assembled_stiffness(ff, 18), k, 1e-13));
    BeamParameters sym = p;
    sym.symmetric_assembly = true;
    BeamFEMForceField symmetric(s, chain(2), sym);
    symmetric.init();
    symmetric.accumulate_force();
    const Eigen::MatrixXd ks = test::assembled_stiffness(symmetric, 18);
    EXPECT_TRUE(ks.isApprox(ks.transpose(), 1e-14));
    EXPECT_TRUE(test::near_relative(ks, k, 1e-12)) << "at rest, R k Rᵀ is symmetric already";
}

TEST(BeamFEMForceField, ForceIsMinusTheEnergyGradientInTheCentres) {
    Rigid3Object s = beam_frames(1, 1.0, Vec3::UnitX());
    BeamFEMForceField ff(s, chain(1), steel_rod());
    ff.init();
    s.position[1].center += Vec3(0.01, 0.02, -0.015);
    s.position[1].orientation = Quat(Eigen::AngleAxisd(0.03, Vec3(0, 1, 1).normalized()));
    const std::vector<RigidFrame> x0 = s.position;
    const Eigen::VectorXd f = test::rigid_force_at(ff, s, x0, Eigen::VectorXd::Zero(12));
    const auto energy = [&](const Eigen::VectorXd& c) {
        Eigen::VectorXd d = Eigen::VectorXd::Zero(12);
        d.segment<3>(6) = c;
        test::rigid_force_at(ff, s, x0, d);
        return ff.potential_energy();
    };
    const Eigen::VectorXd g = test::finite_gradient(Eigen::VectorXd::Zero(3), energy, 1e-7);
    EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-g), Eigen::VectorXd(f.segment<3>(6)), 1e-6));
}

TEST(BeamFEMForceField, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // 10 000 beams (more than OrderedScatter::kMinElements) along a bent chain, listed in order and
    // shuffled, the frames moved and turned a little: force, energy and product at 2, 3 and 8
    // threads, each end's force and torque of a deferred end added in beam order after.
    constexpr int kBeams = 10'000;
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    using BeamList = std::vector<std::array<Index, 2>>;
    const BeamList in_order = chain(kBeams);
    BeamList shuffled = in_order;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    for (const BeamList* list : {&in_order, static_cast<const BeamList*>(&shuffled)}) {
        Rigid3Object s = beam_frames(kBeams, 0.01, Vec3(1, 0.2, 0));
        for (RigidFrame& frame : s.position) {
            frame.center += 1e-4 * Vec3(u(rng), u(rng), u(rng));
            frame.orientation = Quat(Eigen::AngleAxisd(0.02 * u(rng), Vec3(u(rng), u(rng), 1.0).normalized()));
        }
        std::vector<RigidDeriv> dx(s.position.size());
        for (RigidDeriv& d : dx) d = {Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng))};
        BeamFEMForceField beams(s, *list, steel_rod());
        beams.init();
        struct Products {
            std::vector<RigidDeriv> force, product;
            double energy = 0.0;
            std::size_t chunks = 0, deferred = 0;
        };
        const auto run = [&](int threads) {
            Products out;
            out.force.assign(s.position.size(), RigidDeriv{});
            out.product.assign(s.position.size(), RigidDeriv{Vec3(0.25, -0.5, 1.0), Vec3(-1.0, 0.5, 0.125)});
            tbb::task_arena(threads).execute([&] {
                beams.add_force(out.force, s.position, s.velocity);
                beams.add_dforce(out.product, dx, -0.37, 0.0);
            });
            out.energy = beams.potential_energy();
            out.chunks = beams.product_scatter().chunk_count();
            out.deferred = beams.product_scatter().deferred_terms();
            return out;
        };
        const auto same_bits = [](const std::vector<RigidDeriv>& a, const std::vector<RigidDeriv>& b) {
            return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(RigidDeriv)) == 0;
        };
        const Products one = run(1);
        EXPECT_EQ(one.chunks, 0U);
        EXPECT_GT(one.energy, 0.0);
        for (const int threads : {2, 3, 8}) {
            const Products many = run(threads);
            const std::string where = std::to_string(threads) + " threads" + (list == &in_order ? "" : ", shuffled");
            EXPECT_GT(many.chunks, 1U) << where;
            EXPECT_GT(many.deferred, 0U) << where;
            EXPECT_TRUE(same_bits(many.force, one.force)) << where;
            EXPECT_TRUE(same_bits(many.product, one.product)) << where;
            EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
        }
    }
}

TEST(BeamFEMForceField, RefusesBadBeams) {
    Rigid3Object s = beam_frames(1, 1.0, Vec3::UnitX());
    BeamFEMForceField out_of_range(s, {{0, 2}}, steel_rod());
    EXPECT_THROW(out_of_range.init(), std::invalid_argument);
    BeamFEMForceField zero_length(s, {{1, 1}}, steel_rod());
    EXPECT_THROW(zero_length.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
