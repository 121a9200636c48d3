// PenaltyForceField in motion: a particle against a fixed contact point, integrated with
// symplectic Euler (v += h·f/m; x += h·v), the contact list renewed every step as a detection
// would. Closed-form checks: Coulomb friction on an incline, restitution of a spring–dashpot.
#include "penalty/response/penalty_force_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penalty {
namespace {

constexpr double kGravity = 9.81;

/// One particle (state 2) in contact with one fixed point (state 1, at the origin).
struct ParticleAgainstFixedPoint {
    PenaltyForceField ff;
    double mass = 1.0;
    Vec3 gravity = Vec3(0, -kGravity, 0);
    Vec3List x1{Vec3::Zero()}, v1{Vec3::Zero()};
    Vec3List x2{Vec3::Zero()}, v2{Vec3::Zero()};

    void step() {
        Vec3List f1{Vec3::Zero()}, f2{mass * gravity};
        ff.add_force(f1, f2, x1, x2, v1, v2);
        v2[0] += ff.parameters().time_step * f2[0] / mass;
        x2[0] += ff.parameters().time_step * v2[0];
        ff.renew_contacts();  // the same contact is detected again, history through old_index
    }
    [[nodiscard]] const PenaltyContact& contact() const { return ff.contacts()[0]; }
};

struct InclineSetup {
    ParticleAgainstFixedPoint sim;
    Vec3 normal;    // plane normal (up the plane's outward side)
    Vec3 downhill;  // unit tangent pointing down the slope
};

/// A plane through the origin tilted by theta about z; the particle rests on it at the normal
/// equilibrium penetration m·g·cosθ / ks, at rest.
InclineSetup make_incline(double theta, double mu_s, double mu_v) {
    const double ks = 1e5;
    PenaltyParameters parameters;
    parameters.friction = FrictionModel::coulomb;
    parameters.tangential_stiffness_ratio = 1.0;
    parameters.tangential_damping = 2.0 * std::sqrt(ks * 1.0);  // critical for kt = ks, m = 1
    parameters.time_step = 1e-4;
    InclineSetup setup{.sim = {.ff = PenaltyForceField(parameters)},
                       .normal = Vec3(-std::sin(theta), std::cos(theta), 0.0),
                       .downhill = -Vec3(std::cos(theta), std::sin(theta), 0.0)};
    const double pen0 = setup.sim.mass * kGravity * std::cos(theta) / ks;
    setup.sim.x2[0] = -pen0 * setup.normal;  // dist = 0: pen = −(x2 − x1)·n
    setup.sim.ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), setup.normal, 0.0, ks, mu_s,
                             mu_v);
    return setup;
}

TEST(PenaltyFriction, SlidesDownAnInclineWithTheDynamicCoefficient) {
    const double theta = std::numbers::pi / 6;  // tan θ = 0.577 > mu_s
    const double mu_s = 0.4, mu_v = 0.3;
    InclineSetup s = make_incline(theta, mu_s, mu_v);
    const double expected_acceleration = kGravity * (std::sin(theta) - mu_v * std::cos(theta));

    double v_half = 0.0;
    const int steps = 10000;  // 1 s
    for (int i = 1; i <= steps; ++i) {
        s.sim.step();
        if (i == steps / 2) v_half = s.sim.v2[0].dot(s.downhill);
    }
    EXPECT_EQ(s.sim.ff.previous_contacts()[0].friction_state, FrictionState::sliding);
    const double v_end = s.sim.v2[0].dot(s.downhill);
    const double acceleration = (v_end - v_half) / 0.5;
    EXPECT_NEAR(acceleration / expected_acceleration, 1.0, 1e-3)
        << "a = " << acceleration << ", expected " << expected_acceleration;
    // the particle stays on the plane: no drift along the normal
    EXPECT_NEAR(s.sim.x2[0].dot(s.normal), -kGravity * std::cos(theta) / 1e5, 1e-9);

    // energy bookkeeping: potential energy lost = kinetic + stored + dissipated (sliding, damping)
    const double drop = -s.sim.x2[0].dot(Vec3::UnitY()) - kGravity * std::cos(theta) / 1e5 * std::cos(theta);
    const double kinetic = 0.5 * s.sim.mass * s.sim.v2[0].squaredNorm();
    const double travelled = s.sim.x2[0].dot(s.downhill);
    const double sliding_work = mu_v * s.sim.mass * kGravity * std::cos(theta) * travelled;
    EXPECT_NEAR(s.sim.ff.dissipated_by_sliding() / sliding_work, 1.0, 1e-2);
    const double balance = s.sim.mass * kGravity * drop - kinetic - s.sim.ff.dissipated_energy();
    EXPECT_NEAR(balance / (s.sim.mass * kGravity * drop), 0.0, 1e-2);
}

TEST(PenaltyFriction, SticksOnAnInclineBelowTheStaticCoefficient) {
    const double theta = 15.0 * std::numbers::pi / 180.0;  // tan θ = 0.268 < mu_s
    const double mu_s = 0.4, mu_v = 0.3;
    InclineSetup s = make_incline(theta, mu_s, mu_v);
    for (int i = 0; i < 5000; ++i) {
        s.sim.step();
        ASSERT_EQ(s.sim.ff.previous_contacts()[0].friction_state, FrictionState::sticking) << "step " << i;
    }
    // at rest, held by the tangential spring: f_t = m·g·sinθ up the slope, ξ = f_t / kt
    EXPECT_LT(s.sim.v2[0].norm(), 1e-9);
    const PenaltyContact& c = s.sim.ff.previous_contacts()[0];
    EXPECT_NEAR(c.tangential_force.dot(-s.downhill) / (kGravity * std::sin(theta)), 1.0, 1e-6);
    EXPECT_NEAR(s.sim.x2[0].dot(s.downhill) / (kGravity * std::sin(theta) / 1e5), 1.0, 1e-3);
    EXPECT_EQ(s.sim.ff.dissipated_by_sliding(), 0.0);
}

TEST(PenaltyFriction, DefaultsIgnoreFrictionCoefficientsAsSofa) {
    InclineSetup s = make_incline(std::numbers::pi / 6, 0.9, 0.9);
    PenaltyParameters sofa = s.sim.ff.parameters();
    sofa.friction = FrictionModel::ignored;
    s.sim.ff.set_parameters(sofa);
    for (int i = 0; i < 1000; ++i) s.sim.step();
    // frictionless: a = g·sinθ exactly as on a smooth plane
    const double v = s.sim.v2[0].dot(s.downhill);
    EXPECT_NEAR(v / (kGravity * 0.5 * 0.1), 1.0, 1e-3);
    EXPECT_EQ(s.sim.contact().tangential_force, Vec3::Zero());
}

TEST(PenaltyFriction, AnchorSurvivesThroughOldIndexAndIsDroppedWhenContactEnds) {
    const double theta = 15.0 * std::numbers::pi / 180.0;
    InclineSetup s = make_incline(theta, 0.4, 0.3);
    for (int i = 0; i < 3000; ++i) s.sim.step();
    const Vec3 held = s.sim.ff.previous_contacts()[0].tangential_force;
    ASSERT_GT(held.norm(), 1.0);

    auto evaluate = [&](PenaltyForceField& ff) {
        Vec3List f1{Vec3::Zero()}, f2{Vec3::Zero()};
        ff.add_force(f1, f2, s.sim.x1, s.sim.x2, s.sim.v1, s.sim.v2);
        return ff.contacts()[0].tangential_force;
    };
    const PenaltyContact c = s.sim.contact();
    // re-detected with old_index = 1: the same spring holds the particle
    PenaltyForceField carried = s.sim.ff;
    carried.clear();
    carried.add_contact(DofIndex(c.m1), DofIndex(c.m2), ElementIndex(c.index1), ElementIndex(c.index2), c.normal,
                        c.dist, c.ks, c.mu_s, c.mu_v, 1);
    EXPECT_LT((evaluate(carried) - held).norm(), 1e-6 * held.norm());
    // re-detected as new (old_index = 0): a fresh anchor, no tangential force at rest
    PenaltyForceField fresh = s.sim.ff;
    fresh.clear();
    fresh.add_contact(DofIndex(c.m1), DofIndex(c.m2), ElementIndex(c.index1), ElementIndex(c.index2), c.normal, c.dist,
                      c.ks, c.mu_s, c.mu_v, 0);
    EXPECT_LT(evaluate(fresh).norm(), 1e-6);
    // re-detected with a rotated normal: the spring is re-projected with its length kept
    PenaltyForceField rotated = s.sim.ff;
    rotated.clear();
    const Vec3 tilted = (c.normal + 0.2 * s.downhill).normalized();
    rotated.add_contact(DofIndex(c.m1), DofIndex(c.m2), ElementIndex(c.index1), ElementIndex(c.index2), tilted, c.dist,
                        c.ks, c.mu_s, c.mu_v, 1);
    const Vec3 f_rotated = evaluate(rotated);
    EXPECT_NEAR(f_rotated.dot(tilted), 0.0, 1e-9);
    EXPECT_NEAR(rotated.contacts()[0].shear.norm(), c.shear_start.norm(), 1e-12);

    // the contact separates for one step: the anchor is dropped
    s.sim.x2[0] += 0.01 * s.normal;
    s.sim.step();
    EXPECT_EQ(s.sim.ff.previous_contacts()[0].friction_state, FrictionState::none);
    s.sim.x2[0] -= 0.01 * s.normal;
    s.sim.v2[0].setZero();
    PenaltyForceField after = s.sim.ff;
    EXPECT_LT(evaluate(after).norm(), 1e-9);
}

// ---------------------------------------------------------------------------------------------
// Linear spring–dashpot: e = exp(−ζπ / √(1 − ζ²)), ζ = c / (2·√(ks·m)).

class PenaltyDamping : public ::testing::TestWithParam<double> {};

TEST_P(PenaltyDamping, BounceHasTheClosedFormRestitution) {
    const double zeta = GetParam();
    const double ks = 1e4, mass = 1.0;
    PenaltyParameters parameters;
    parameters.damping = 2.0 * zeta * std::sqrt(ks * mass);
    parameters.time_step = 1e-6;
    ParticleAgainstFixedPoint sim{.ff = PenaltyForceField(parameters), .mass = mass, .gravity = Vec3::Zero()};
    sim.x2[0] = Vec3(0, 1.001, 0);
    sim.v2[0] = Vec3(0, -1, 0);
    sim.ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), 1.0, ks);

    bool touched = false;
    int steps = 0;
    while (steps < 200000) {
        sim.step();
        ++steps;
        const double pen = sim.ff.previous_contacts()[0].pen;
        if (pen > 0) touched = true;
        if (touched && pen <= 0 && sim.v2[0].y() > 0) break;
    }
    ASSERT_TRUE(touched);
    ASSERT_LT(steps, 200000);
    const double restitution = sim.v2[0].y() / 1.0;
    const double expected = std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
    EXPECT_NEAR(restitution, expected, 1e-3);
    // the kinetic energy lost is the energy dissipated by the dashpot
    const double lost = 0.5 * mass * (1.0 - restitution * restitution);
    EXPECT_NEAR(sim.ff.dissipated_by_damping() / lost, 1.0, 1e-2);
    EXPECT_EQ(sim.ff.dissipated_by_sliding(), 0.0);
}

INSTANTIATE_TEST_SUITE_P(DampingRatios, PenaltyDamping, ::testing::Values(0.05, 0.2, 0.5));

TEST(PenaltyDamping, WithoutDampingTheBounceIsElastic) {
    PenaltyParameters parameters;
    parameters.time_step = 1e-6;
    ParticleAgainstFixedPoint sim{.ff = PenaltyForceField(parameters), .mass = 1.0, .gravity = Vec3::Zero()};
    sim.x2[0] = Vec3(0, 1.001, 0);
    sim.v2[0] = Vec3(0, -1, 0);
    sim.ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), 1.0, 1e4);
    for (int i = 0; i < 60000; ++i) sim.step();
    EXPECT_GT(sim.v2[0].y(), 0.0);
    EXPECT_NEAR(sim.v2[0].y(), 1.0, 1e-3);
    EXPECT_EQ(sim.ff.dissipated_energy(), 0.0);
}

}  // namespace
}  // namespace penalty
