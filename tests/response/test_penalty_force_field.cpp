// PenaltyForceField: SOFA's own unit-test cases, finite differences of every derivative,
// invariants, SOFA's age rule, input validation, export and grab queries.
#include "penalty/response/penalty_force_field.hpp"

#include "penalty_test/finite_difference.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace penalty {
namespace {

using test::finite_gradient;
using test::finite_jacobian;
using test::near_relative;

Eigen::VectorXd flatten(ConstVec3Span a, ConstVec3Span b = {}) {
    Eigen::VectorXd out(3 * static_cast<Eigen::Index>(a.size() + b.size()));
    Eigen::Index k = 0;
    for (const Vec3& v : a) out.segment<3>(3 * k++) = v;
    for (const Vec3& v : b) out.segment<3>(3 * k++) = v;
    return out;
}

Vec3List unflatten(const Eigen::VectorXd& x, Eigen::Index first, Eigen::Index count) {
    Vec3List out(static_cast<std::size_t>(count));
    for (Eigen::Index i = 0; i < count; ++i) out[static_cast<std::size_t>(i)] = x.segment<3>(3 * (first + i));
    return out;
}

// ---------------------------------------------------------------------------------------------
// SOFA's PenalityContactForceField_test: one state, particle 0 at the origin, contact (0, 1).

struct SofaCase {
    Vec3 x1;
    double dist;
    double ks;
    Vec3 expected_force0;
};

class SofaUnitTestCases : public ::testing::TestWithParam<SofaCase> {};

TEST_P(SofaUnitTestCases, ForceAndDerivativesMatchSofa) {
    const SofaCase& tc = GetParam();
    Vec3List x{Vec3::Zero(), tc.x1};
    Vec3List v(2, Vec3::Zero());
    PenaltyForceField ff;
    ff.add_contact(DofIndex(0), DofIndex(1), ElementIndex(0), ElementIndex(0), (x[1] - x[0]).normalized(), tc.dist,
                   tc.ks);

    // same state on both sides: the same spans
    Vec3List f(2, Vec3::Zero());
    ff.add_force(f, f, x, x, v, v);
    EXPECT_LT((f[0] - tc.expected_force0).cwiseAbs().maxCoeff(), 1e-13) << f[0].transpose();
    EXPECT_LT((f[1] + tc.expected_force0).cwiseAbs().maxCoeff(), 1e-13) << f[1].transpose();

    // SOFA's harness: perturb every DOF by a random vector in [eps, 1000 eps], compare the force
    // change with addDForce and K·dx to 100 eps.
    const double eps = std::numeric_limits<double>::epsilon();
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> perturbation(eps, 1000 * eps);
    Vec3List dx(2);
    for (Vec3& d : dx) d = Vec3(perturbation(rng), perturbation(rng), perturbation(rng));
    Vec3List x_new{x[0] + dx[0], x[1] + dx[1]};
    Vec3List f_new(2, Vec3::Zero());
    PenaltyForceField ff_new = ff;
    ff_new.add_force(f_new, f_new, x_new, x_new, v, v);

    Vec3List df(2, Vec3::Zero());
    ff.add_dforce(df, df, dx, dx, 1.0);
    const Eigen::VectorXd k_dx = ff.stiffness_matrix(2, 0, true) * flatten(dx);
    for (int i = 0; i < 2; ++i) {
        const Vec3 change = f_new[static_cast<std::size_t>(i)] - f[static_cast<std::size_t>(i)];
        EXPECT_LT((change - df[static_cast<std::size_t>(i)]).cwiseAbs().maxCoeff(), 100 * eps);
        EXPECT_LT((change - k_dx.segment<3>(3 * i)).cwiseAbs().maxCoeff(), 100 * eps);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Sofa, SofaUnitTestCases,
    ::testing::Values(SofaCase{Vec3(2, 0, 0), 3, 1, Vec3(-1, 0, 0)}, SofaCase{Vec3(2, 0, 0), 3, 2, Vec3(-2, 0, 0)},
                      SofaCase{Vec3(4.8, -0.4, -2.3), 6, 2,
                               Vec3(-1.19136193691474900901994260494, 0.0992801614095624312961163582258,
                                    0.57086092810498378913308670235)}));

TEST(PenaltyForceField, InactiveContactGivesNoForceNoEnergyNoStiffness) {
    Vec3List x{Vec3::Zero(), Vec3(2, 0, 0)};
    Vec3List v(2, Vec3::Zero()), f(2, Vec3::Zero());
    PenaltyForceField ff;
    ff.add_contact(DofIndex(0), DofIndex(1), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 2.0,
                   5.0);  // pen = 0 exactly: not active (strict)
    ff.add_force(f, f, x, x, v, v);
    EXPECT_EQ(f[0], Vec3::Zero());
    EXPECT_EQ(f[1], Vec3::Zero());
    EXPECT_EQ(ff.potential_energy(), 0.0);
    EXPECT_EQ(ff.active_count(), 0u);
    EXPECT_EQ(ff.stiffness_matrix(2, 0, true).nonZeros(), 0);
    EXPECT_DOUBLE_EQ(ff.contacts()[0].pen, 0.0);
}

TEST(PenaltyForceField, EnergyIsHalfKsPenSquared) {
    Vec3List x1{Vec3(0, 0, 0)}, x2{Vec3(0, 0.3, 0)};
    Vec3List v1(1, Vec3::Zero()), v2(1, Vec3::Zero()), f1(1, Vec3::Zero()), f2(1, Vec3::Zero());
    PenaltyForceField ff;
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), 1.0, 100.0);
    ff.add_force(f1, f2, x1, x2, v1, v2);
    EXPECT_DOUBLE_EQ(ff.contacts()[0].pen, 0.7);
    EXPECT_DOUBLE_EQ(ff.potential_energy(), 0.5 * 100.0 * 0.49);
    EXPECT_TRUE(f2[0].isApprox(Vec3(0, 70, 0)));
    EXPECT_TRUE(f1[0].isApprox(Vec3(0, -70, 0)));
}

// ---------------------------------------------------------------------------------------------
// Seeded random configurations; finite differences of energy, force and velocity.

struct RandomScene {
    Vec3List x1, x2, v1, v2;
    PenaltyForceField ff;
};

/// n1/n2 DOFs, `contacts` random springs; dist chosen so that about 60% penetrate, and never
/// within 1e-3 of the activation switch (so central differences with h = 1e-6 stay on one side).
RandomScene make_random_scene(std::mt19937& rng, std::size_t n1, std::size_t n2, std::size_t contacts,
                              PenaltyParameters parameters, bool same_state) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_real_distribution<double> positive(0.5, 5.0);
    RandomScene s{.x1 = {}, .x2 = {}, .v1 = {}, .v2 = {}, .ff = PenaltyForceField(parameters)};
    auto random_vec = [&] { return Vec3(unit(rng), unit(rng), unit(rng)); };
    for (std::size_t i = 0; i < n1; ++i) s.x1.push_back(random_vec()), s.v1.push_back(random_vec());
    if (same_state) {
        s.x2 = s.x1;
        s.v2 = s.v1;
    } else {
        for (std::size_t i = 0; i < n2; ++i) s.x2.push_back(random_vec()), s.v2.push_back(random_vec());
    }
    std::uniform_int_distribution<Index> pick1(0, static_cast<Index>(s.x1.size()) - 1);
    std::uniform_int_distribution<Index> pick2(0, static_cast<Index>(s.x2.size()) - 1);
    std::uniform_real_distribution<double> pen_draw(-0.5, 0.75);
    while (s.ff.size() < contacts) {
        const Index m1 = pick1(rng), m2 = pick2(rng);
        if (same_state && m1 == m2) continue;  // a spring from a DOF to itself has no effect
        const Vec3 n = random_vec().normalized();
        double pen = pen_draw(rng);
        if (std::abs(pen) < 1e-3) continue;
        const double dist = pen + (s.x2[static_cast<std::size_t>(m2)] - s.x1[static_cast<std::size_t>(m1)]).dot(n);
        s.ff.add_contact(DofIndex(m1), DofIndex(m2), ElementIndex(m1), ElementIndex(m2), n, dist, positive(rng), 0.0,
                         0.0, 0);
    }
    return s;
}

/// Runs add_force on `ff` at stacked positions q (state 1 then state 2, or the single state) and
/// returns the stacked forces.
Eigen::VectorXd evaluate(PenaltyForceField& ff, const Eigen::VectorXd& q, const RandomScene& s, bool same_state,
                         const Eigen::VectorXd* velocities = nullptr) {
    const auto n1 = static_cast<Eigen::Index>(s.x1.size());
    const auto n2 = static_cast<Eigen::Index>(s.x2.size());
    Vec3List x1 = unflatten(q, 0, n1);
    Vec3List x2 = same_state ? x1 : unflatten(q, n1, n2);
    Vec3List v1 = s.v1, v2 = s.v2;
    if (velocities) {
        v1 = unflatten(*velocities, 0, n1);
        v2 = same_state ? v1 : unflatten(*velocities, n1, n2);
    }
    Vec3List f1(x1.size(), Vec3::Zero()), f2(x2.size(), Vec3::Zero());
    if (same_state) {
        ff.add_force(f1, f1, x1, x1, v1, v1);
        return flatten(f1);
    }
    ff.add_force(f1, f2, x1, x2, v1, v2);
    return flatten(f1, f2);
}

/// Force at q, evaluated on a copy (the contacts' step state is left untouched).
Eigen::VectorXd stacked_force(PenaltyForceField ff, const Eigen::VectorXd& q, const RandomScene& s, bool same_state,
                              const Eigen::VectorXd* velocities = nullptr) {
    return evaluate(ff, q, s, same_state, velocities);
}

/// Stored energy at q, evaluated on a copy.
double stacked_energy(PenaltyForceField ff, const Eigen::VectorXd& q, const RandomScene& s, bool same_state) {
    evaluate(ff, q, s, same_state);
    return ff.potential_energy();
}

struct LayoutCase {
    bool same_state;
    const char* name;
};

class RandomFiniteDifferences : public ::testing::TestWithParam<LayoutCase> {};

TEST_P(RandomFiniteDifferences, ForceIsMinusEnergyGradientAndStiffnessIsForceJacobian) {
    const bool same_state = GetParam().same_state;
    std::mt19937 rng(20261121);
    std::size_t active = 0, total = 0;
    for (int trial = 0; trial < 20; ++trial) {
        RandomScene s = make_random_scene(rng, 6, 5, 12, {}, same_state);
        const Eigen::VectorXd q = same_state ? flatten(s.x1) : flatten(s.x1, s.x2);
        const Eigen::VectorXd f = stacked_force(s.ff, q, s, same_state);
        ASSERT_GT(f.norm(), 0.0);

        // force = −dE/dx
        const Eigen::VectorXd grad =
            finite_gradient(q, [&](const Eigen::VectorXd& y) { return stacked_energy(s.ff, y, s, same_state); });
        EXPECT_TRUE(near_relative(f, -grad, 1e-6)) << "trial " << trial;

        // assembled K = df/dx
        PenaltyForceField evaluated = s.ff;
        evaluate(evaluated, q, s, same_state);
        const Eigen::MatrixXd K = Eigen::MatrixXd(
            evaluated.stiffness_matrix(static_cast<Index>(s.x1.size()), static_cast<Index>(s.x2.size()), same_state));
        const Eigen::MatrixXd fd_K =
            finite_jacobian(q, [&](const Eigen::VectorXd& y) { return stacked_force(s.ff, y, s, same_state); });
        EXPECT_TRUE(near_relative(K, fd_K, 1e-6)) << "trial " << trial;
        EXPECT_TRUE(K.isApprox(K.transpose(), 1e-14));

        // add_dforce(dx) = K·dx, with a k_factor
        std::normal_distribution<double> normal(0.0, 1.0);
        Eigen::VectorXd dq(q.size());
        for (Eigen::Index i = 0; i < dq.size(); ++i) dq[i] = normal(rng);
        const auto n1 = static_cast<Eigen::Index>(s.x1.size());
        const auto n2 = static_cast<Eigen::Index>(s.x2.size());
        Vec3List dx1 = unflatten(dq, 0, n1), dx2 = same_state ? dx1 : unflatten(dq, n1, n2);
        Vec3List df1(dx1.size(), Vec3::Zero()), df2(dx2.size(), Vec3::Zero());
        if (same_state) evaluated.add_dforce(df1, df1, dx1, dx1, -0.37);
        else evaluated.add_dforce(df1, df2, dx1, dx2, -0.37);
        const Eigen::VectorXd df = same_state ? flatten(df1) : flatten(df1, df2);
        EXPECT_TRUE(near_relative(df, Eigen::VectorXd(-0.37 * K * dq), 1e-12));

        // invariants: forces sum to zero; energy ≥ 0
        Vec3 total_force = Vec3::Zero();
        for (Eigen::Index i = 0; i < f.size() / 3; ++i) total_force += f.segment<3>(3 * i);
        EXPECT_LT(total_force.norm(), 1e-12);
        EXPECT_GE(evaluated.potential_energy(), 0.0);
        active += evaluated.active_count();
        total += evaluated.size();
    }
    // a good share of the random contacts penetrate, and not all of them
    const double hit_rate = static_cast<double>(active) / static_cast<double>(total);
    EXPECT_GT(hit_rate, 0.4);
    EXPECT_LT(hit_rate, 0.8);
}

TEST_P(RandomFiniteDifferences, DampingMatrixIsForceVelocityJacobian) {
    const bool same_state = GetParam().same_state;
    std::mt19937 rng(77);
    PenaltyParameters parameters;
    parameters.damping = 3.5;
    std::size_t active = 0, total = 0;
    for (int trial = 0; trial < 10; ++trial) {
        RandomScene s = make_random_scene(rng, 5, 4, 10, parameters, same_state);
        const Eigen::VectorXd q = same_state ? flatten(s.x1) : flatten(s.x1, s.x2);
        const Eigen::VectorXd w = same_state ? flatten(s.v1) : flatten(s.v1, s.v2);
        PenaltyForceField evaluated = s.ff;
        evaluate(evaluated, q, s, same_state);
        const auto n1 = static_cast<Index>(s.x1.size()), n2 = static_cast<Index>(s.x2.size());
        const Eigen::MatrixXd B = Eigen::MatrixXd(evaluated.damping_matrix(n1, n2, same_state));
        const Eigen::MatrixXd fd_B =
            finite_jacobian(w, [&](const Eigen::VectorXd& y) { return stacked_force(s.ff, q, s, same_state, &y); });
        ASSERT_GT(B.norm(), 0.0);
        EXPECT_TRUE(near_relative(B, fd_B, 1e-6)) << "trial " << trial;
        EXPECT_TRUE(B.isApprox(B.transpose(), 1e-14));

        // add_dforce with b_factor only = b·B·dx
        Eigen::VectorXd dq = Eigen::VectorXd::LinSpaced(q.size(), -1.0, 2.0);
        Vec3List dx1 = unflatten(dq, 0, n1), dx2 = same_state ? dx1 : unflatten(dq, n1, n2);
        Vec3List df1(dx1.size(), Vec3::Zero()), df2(dx2.size(), Vec3::Zero());
        if (same_state) evaluated.add_dforce(df1, df1, dx1, dx1, 0.0, 0.25);
        else evaluated.add_dforce(df1, df2, dx1, dx2, 0.0, 0.25);
        const Eigen::VectorXd df = same_state ? flatten(df1) : flatten(df1, df2);
        EXPECT_TRUE(near_relative(df, Eigen::VectorXd(0.25 * B * dq), 1e-12));
        active += evaluated.active_count();
        total += evaluated.size();
    }
    EXPECT_GT(static_cast<double>(active) / static_cast<double>(total), 0.4);
}

TEST_P(RandomFiniteDifferences, StickingFrictionIsConservativeWithinAStep) {
    const bool same_state = GetParam().same_state;
    std::mt19937 rng(4242);
    PenaltyParameters parameters;
    parameters.friction = FrictionModel::coulomb;
    parameters.tangential_stiffness_ratio = 0.6;
    std::size_t sticking = 0, total = 0;
    for (int trial = 0; trial < 10; ++trial) {
        RandomScene base = make_random_scene(rng, 5, 4, 8, parameters, same_state);
        // re-add the same contacts with a huge mu so every active contact sticks
        PenaltyForceField ff(parameters);
        for (const PenaltyContact& c : base.ff.contacts())
            ff.add_contact(DofIndex(c.m1), DofIndex(c.m2), ElementIndex(c.index1), ElementIndex(c.index2), c.normal,
                           c.dist, c.ks, 1e6, 1e6, 0);
        // step start at x0, then move: the tangential spring ξ = P·(u − u0) is stretched
        Vec3List f1(base.x1.size(), Vec3::Zero()), f2(base.x2.size(), Vec3::Zero());
        if (same_state) ff.add_force(f1, f1, base.x1, base.x1, base.v1, base.v1);
        else ff.add_force(f1, f2, base.x1, base.x2, base.v1, base.v2);
        std::normal_distribution<double> small(0.0, 0.05);
        for (Vec3& p : base.x1) p += Vec3(small(rng), small(rng), small(rng));
        if (same_state) {
            base.x2 = base.x1;
        } else {
            for (Vec3& p : base.x2) p += Vec3(small(rng), small(rng), small(rng));
        }
        base.ff = ff;

        const Eigen::VectorXd q = same_state ? flatten(base.x1) : flatten(base.x1, base.x2);
        const Eigen::VectorXd f = stacked_force(ff, q, base, same_state);
        const Eigen::VectorXd grad =
            finite_gradient(q, [&](const Eigen::VectorXd& y) { return stacked_energy(ff, y, base, same_state); });
        EXPECT_TRUE(near_relative(f, -grad, 1e-6)) << "trial " << trial;

        PenaltyForceField evaluated = ff;
        evaluate(evaluated, q, base, same_state);
        const Eigen::MatrixXd K = Eigen::MatrixXd(evaluated.stiffness_matrix(
            static_cast<Index>(base.x1.size()), static_cast<Index>(base.x2.size()), same_state));
        const Eigen::MatrixXd fd_K =
            finite_jacobian(q, [&](const Eigen::VectorXd& y) { return stacked_force(ff, y, base, same_state); });
        EXPECT_TRUE(near_relative(K, fd_K, 1e-6)) << "trial " << trial;
        EXPECT_TRUE(K.isApprox(K.transpose(), 1e-14));
        for (const PenaltyContact& c : evaluated.contacts()) {
            sticking += c.friction_state == FrictionState::sticking;
            total += 1;
            if (c.friction_state == FrictionState::sticking) {
                EXPECT_GT(c.shear.norm(), 0.0);
            }
        }
    }
    EXPECT_GT(static_cast<double>(sticking) / static_cast<double>(total), 0.3);
}

INSTANTIATE_TEST_SUITE_P(Layouts, RandomFiniteDifferences,
                         ::testing::Values(LayoutCase{false, "TwoStates"}, LayoutCase{true, "SameState"}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(PenaltyForceField, SeparatedContactsGiveExactlyZero) {
    // random contacts all with pen < 0: energy, forces, K and add_dforce are exactly zero
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    PenaltyParameters parameters;
    parameters.damping = 2.0;
    parameters.friction = FrictionModel::coulomb;
    PenaltyForceField ff(parameters);
    Vec3List x1(8), x2(8), v(8);
    for (std::size_t i = 0; i < 8; ++i) {
        x1[i] = Vec3(unit(rng), unit(rng), unit(rng));
        x2[i] = Vec3(unit(rng), unit(rng), unit(rng));
        v[i] = Vec3(unit(rng), unit(rng), unit(rng));
    }
    for (Index i = 0; i < 8; ++i) {
        const Vec3 n = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
        const double gap = (x2[static_cast<std::size_t>(i)] - x1[static_cast<std::size_t>(7 - i)]).dot(n);
        ff.add_contact(DofIndex(7 - i), DofIndex(i), ElementIndex(0), ElementIndex(0), n,
                       gap - 0.01 - 0.1 * (unit(rng) + 1.0), 50.0, 0.5, 0.5);
    }
    Vec3List f1(8, Vec3::Zero()), f2(8, Vec3::Zero());
    ff.add_force(f1, f2, x1, x2, v, v);
    EXPECT_EQ(ff.active_count(), 0u);
    EXPECT_EQ(ff.potential_energy(), 0.0);
    for (std::size_t i = 0; i < 8; ++i) {
        EXPECT_EQ(f1[i], Vec3::Zero());
        EXPECT_EQ(f2[i], Vec3::Zero());
        EXPECT_LT(ff.contacts()[i].pen, 0.0);
    }
    EXPECT_EQ(ff.stiffness_matrix(8, 8, false).nonZeros(), 0);
    EXPECT_EQ(ff.damping_matrix(8, 8, false).nonZeros(), 0);
    Vec3List df1(8, Vec3::Zero()), df2(8, Vec3::Zero());
    ff.add_dforce(df1, df2, v, v, 1.0, 1.0);
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(df1[i], Vec3::Zero());
    EXPECT_EQ(ff.dissipated_energy(), 0.0);
}

TEST(PenaltyForceField, TwoStateAndSameStateAssemblyAgree) {
    // the same physical contacts, written once with two states and once with one merged state
    Vec3List x1{Vec3(0, 0, 0), Vec3(1, 0, 0)}, x2{Vec3(0.1, 0.5, 0), Vec3(1, 0.2, 0.1)};
    Vec3List merged{x1[0], x1[1], x2[0], x2[1]};
    Vec3List z2(2, Vec3::Zero()), z4(4, Vec3::Zero());
    PenaltyForceField two, one;
    const Vec3 n = Vec3(0.1, 1, 0.2).normalized();
    two.add_contact(DofIndex(0), DofIndex(1), ElementIndex(0), ElementIndex(0), n, 1.0, 10.0);
    two.add_contact(DofIndex(1), DofIndex(0), ElementIndex(0), ElementIndex(0), n, 0.9, 20.0);
    one.add_contact(DofIndex(0), DofIndex(3), ElementIndex(0), ElementIndex(0), n, 1.0, 10.0);
    one.add_contact(DofIndex(1), DofIndex(2), ElementIndex(0), ElementIndex(0), n, 0.9, 20.0);
    Vec3List f1(2, Vec3::Zero()), f2(2, Vec3::Zero()), f(4, Vec3::Zero());
    two.add_force(f1, f2, x1, x2, z2, z2);
    one.add_force(f, f, merged, merged, z4, z4);
    EXPECT_TRUE(flatten(f1, f2).isApprox(flatten(f)));
    EXPECT_TRUE(
        Eigen::MatrixXd(two.stiffness_matrix(2, 2, false)).isApprox(Eigen::MatrixXd(one.stiffness_matrix(4, 0, true))));
    EXPECT_GT(two.stiffness_matrix(2, 2, false).norm(), 0.0);
}

TEST(PenaltyForceField, StiffnessTripletsHonourOffsetsAndFactor) {
    Vec3List x1{Vec3(0, 0, 0)}, x2{Vec3(0, 0.5, 0)};
    Vec3List z(1, Vec3::Zero()), f1(1, Vec3::Zero()), f2(1, Vec3::Zero());
    PenaltyForceField ff;
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), 1.0, 8.0);
    ff.add_force(f1, f2, x1, x2, z, z);
    TripletList triplets;
    ff.add_stiffness_triplets(triplets, 6, 12, 0.5);
    SparseMatrix K(15, 15);
    K.setFromTriplets(triplets.begin(), triplets.end());
    // only the yy entries: (m1,m1) = −k, (m1,m2) = +k with k = 0.5·8
    EXPECT_DOUBLE_EQ(K.coeff(7, 7), -4.0);
    EXPECT_DOUBLE_EQ(K.coeff(7, 13), 4.0);
    EXPECT_DOUBLE_EQ(K.coeff(13, 7), 4.0);
    EXPECT_DOUBLE_EQ(K.coeff(13, 13), -4.0);
    EXPECT_EQ(K.nonZeros(), 4);
    EXPECT_EQ(ff.damping_matrix(1, 1, false).nonZeros(), 0);  // SOFA: no damping matrix
}

// ---------------------------------------------------------------------------------------------
// SOFA's age rule and the previous list.

TEST(PenaltyForceField, AgeCarriesOverThroughOldIndexAsSofa) {
    PenaltyForceField ff;
    const Vec3 n = Vec3::UnitZ();
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), n, 1, 1);  // A
    ff.add_contact(DofIndex(1), DofIndex(1), ElementIndex(1), ElementIndex(1), n, 1, 1);  // B
    EXPECT_EQ(ff.contacts()[0].age, 0);
    // step 1: B continues (old #2) and comes first, A is re-detected as new
    ff.clear(2);
    ff.add_contact(DofIndex(1), DofIndex(1), ElementIndex(1), ElementIndex(1), n, 1, 1, 0, 0, 2);
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), n, 1, 1, 0, 0, 0);
    ASSERT_EQ(ff.previous_contacts().size(), 2u);
    EXPECT_EQ(ff.contacts()[0].age, 1);
    EXPECT_EQ(ff.contacts()[1].age, 0);
    // step 2: both continue, order swapped back
    ff.clear(2);
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), n, 1, 1, 0, 0, 2);
    ff.add_contact(DofIndex(1), DofIndex(1), ElementIndex(1), ElementIndex(1), n, 1, 1, 0, 0, 1);
    EXPECT_EQ(ff.contacts()[0].age, 1);
    EXPECT_EQ(ff.contacts()[1].age, 2);
    // renew_contacts = clear + add_contact(old_index = i + 1)
    ff.renew_contacts();
    EXPECT_EQ(ff.contacts()[0].age, 2);
    EXPECT_EQ(ff.contacts()[1].age, 3);
    // an old_index outside 1..previous size starts at 0
    ff.clear();
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), n, 1, 1, 0, 0, 3);
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), n, 1, 1, 0, 0, -1);
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), n, 1, 1, 0, 0, 0);
    EXPECT_EQ(ff.contacts()[0].age, 0);
    EXPECT_EQ(ff.contacts()[1].age, 0);
    EXPECT_EQ(ff.contacts()[2].age, 0);
    EXPECT_EQ(ff.previous_contacts()[1].age, 3);
}

// ---------------------------------------------------------------------------------------------
// Invalid input.

TEST(PenaltyForceField, InvalidParametersNameTheParameterAndTheContact) {
    PenaltyForceField ff;
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 1.0, 1.0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto message_of = [](auto&& call) -> std::string {
        try {
            call();
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "no exception";
    };
    using ::testing::AllOf;
    using ::testing::HasSubstr;
    EXPECT_THAT(message_of([&] {
                    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 1.0,
                                   -2.0);
                }),
                AllOf(HasSubstr("contact 1"), HasSubstr("stiffness ks = -2")));
    EXPECT_THAT(message_of([&] {
                    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 1.0, 1.0,
                                   -0.1);
                }),
                HasSubstr("mu_s = -0.1"));
    EXPECT_THAT(message_of([&] {
                    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 1.0, 1.0,
                                   0.0, nan);
                }),
                HasSubstr("mu_v = nan"));
    EXPECT_THAT(message_of([&] {
                    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3(nan, 0, 0), 1.0,
                                   1.0);
                }),
                HasSubstr("normal (nan"));
    EXPECT_THAT(message_of([&] {
                    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3(1, 1, 0), 1.0, 1.0);
                }),
                HasSubstr("unit vector"));
    EXPECT_THAT(message_of([&] {
                    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), nan, 1.0);
                }),
                HasSubstr("dist = nan"));
    EXPECT_THAT(message_of([&] {
                    ff.add_contact(DofIndex(-1), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 1.0,
                                   1.0);
                }),
                HasSubstr("m1 = -1"));
    EXPECT_EQ(ff.size(), 1u);  // nothing was appended by the failed calls

    ff.add_contact(DofIndex(0), DofIndex(3), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 1.0, 1.0);
    Vec3List x(2, Vec3::Zero()), f(2, Vec3::Zero());
    EXPECT_THAT(message_of([&] { ff.add_force(f, f, x, x, x, x); }),
                AllOf(HasSubstr("add_force"), HasSubstr("contact 1"), HasSubstr("m2 = 3"),
                      HasSubstr("outside state 2 (size 2)")));
    EXPECT_EQ(f[0], Vec3::Zero());  // no partial accumulation before the error

    PenaltyParameters bad;
    bad.damping = -1.0;
    EXPECT_THAT(message_of([&] { PenaltyForceField{bad}; }), HasSubstr("damping = -1"));
    bad = {};
    bad.tangential_damping = nan;
    EXPECT_THAT(message_of([&] { PenaltyForceField{bad}; }), HasSubstr("tangential_damping = nan"));
    bad = {};
    bad.time_step = 0.0;
    EXPECT_THAT(message_of([&] { PenaltyForceField{bad}; }), HasSubstr("time_step = 0"));
    bad = {};
    bad.tangential_stiffness_ratio = -3.0;
    EXPECT_THAT(message_of([&] { PenaltyForceField{bad}; }), HasSubstr("tangential_stiffness_ratio = -3"));
    bad = {};
    bad.damping = 1.0;
    PenaltyForceField damped(bad);
    damped.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitX(), 1.0, 1.0);
    Vec3List empty;
    EXPECT_THAT(message_of([&] { damped.add_force(f, f, x, x, empty, empty); }), HasSubstr("need velocities"));
}

// ---------------------------------------------------------------------------------------------
// Export and grab.

TEST(PenaltyForceField, ExportGivesSegmentsWithPenAgeAndForce) {
    Vec3List x1{Vec3(0, 0, 0), Vec3(5, 0, 0)}, x2{Vec3(0, 0.25, 0)};
    Vec3List v1(2, Vec3::Zero()), v2(1, Vec3::Zero()), f1(2, Vec3::Zero()), f2(1, Vec3::Zero());
    PenaltyForceField ff;
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(7), ElementIndex(9), Vec3::UnitY(), 1.0, 4.0);
    ff.add_contact(DofIndex(1), DofIndex(0), ElementIndex(8), ElementIndex(9), Vec3::UnitX(), 1.0,
                   4.0);  // (x2 − x1)·n = −5: pen = 6
    ff.renew_contacts();
    ff.add_force(f1, f2, x1, x2, v1, v2);
    const auto segments = ff.export_contacts(x1, x2);
    ASSERT_EQ(segments.size(), 2u);
    EXPECT_EQ(segments[0].point1, x1[0]);
    EXPECT_EQ(segments[0].point2, x2[0]);
    EXPECT_DOUBLE_EQ(segments[0].pen, 0.75);
    EXPECT_TRUE(segments[0].force.isApprox(Vec3(0, 3, 0)));
    EXPECT_EQ(segments[0].age, 1);
    EXPECT_EQ(segments[0].index1, 7);
    EXPECT_EQ(segments[1].index1, 8);
    EXPECT_DOUBLE_EQ(segments[1].pen, 6.0);
    EXPECT_TRUE(segments[1].force.isApprox(Vec3(24, 0, 0)));
}

TEST(PenaltyForceField, GrabPointsReturnOtherSideInContactOrder) {
    Vec3List x1{Vec3(0, 0, 0), Vec3(1, 0, 0)}, x2{Vec3(0, 1, 0), Vec3(0, 2, 0), Vec3(0, 3, 0)};
    PenaltyForceField ff;
    ff.add_contact(DofIndex(0), DofIndex(2), ElementIndex(10), ElementIndex(20), Vec3::UnitY(), 1.0, 1.0);
    ff.add_contact(DofIndex(1), DofIndex(0), ElementIndex(11), ElementIndex(21), Vec3::UnitY(), 1.0, 1.0);
    ff.add_contact(DofIndex(0), DofIndex(1), ElementIndex(12), ElementIndex(22), Vec3::UnitY(), 1.0, 1.0);
    const std::vector<DofIndex> tool{DofIndex(0)};
    const auto grabbed = ff.grab_points(ContactSide::first, tool, x2);
    ASSERT_EQ(grabbed.size(), 2u);
    EXPECT_EQ(grabbed[0].position, x2[2]);
    EXPECT_EQ(grabbed[0].element, ElementIndex(20));
    EXPECT_EQ(grabbed[1].position, x2[1]);
    EXPECT_EQ(grabbed[1].element, ElementIndex(22));
    EXPECT_EQ(grabbed[1].tool_dof, DofIndex(0));
    const std::vector<DofIndex> tool2{DofIndex(0), DofIndex(2)};
    const auto from_second = ff.grab_points(ContactSide::second, tool2, x1);
    ASSERT_EQ(from_second.size(), 2u);
    EXPECT_EQ(from_second[0].element, ElementIndex(10));
    EXPECT_EQ(from_second[0].tool_dof, DofIndex(2));
    EXPECT_EQ(from_second[1].element, ElementIndex(11));
    EXPECT_EQ(from_second[1].position, x1[1]);
}

}  // namespace
}  // namespace penalty
