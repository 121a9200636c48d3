// The tunnelling guard's stiffening law (simulation/tunnelling_stiffening.cpp, StiffeningLaw):
// F = dE/dpen and ks·factor = dF/dpen by finite differences, continuity at its two joints, its bounds.
#include "penalty/simulation/tunnelling_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

constexpr StiffeningLaw kLaw{.ks = 2000.0, .reach = 0.02, .fraction = 0.5, .max_factor = 1e4};

TEST(StiffeningLaw, IsSofasSpringUpToTheFraction) {
    for (double pen : {-0.01, 0.0, 0.004, 0.01}) {
        EXPECT_FALSE(kLaw.acts(pen));
        EXPECT_DOUBLE_EQ(kLaw.force(pen), kLaw.ks * pen);
        EXPECT_DOUBLE_EQ(kLaw.energy(pen), 0.5 * kLaw.ks * pen * pen);
        EXPECT_EQ(kLaw.factor(pen), 1.0);
    }
    EXPECT_TRUE(kLaw.acts(0.0101));
    EXPECT_FALSE((StiffeningLaw{.ks = 2000.0, .reach = 0.0}.acts(1.0)));  // no reach: never
}

TEST(StiffeningLaw, ForceIsTheEnergyDerivativeAndStiffnessTheForceDerivative) {
    // finite differences over the three pieces (h = 1e-9 m, far from the joints)
    const double pc = kLaw.cap_penetration();
    EXPECT_NEAR(pc, 0.02 - 0.01 / 100.0, 1e-15);  // g_c = g_s/√κ
    int checked = 0;
    for (double pen : {0.005, 0.0123, 0.015, 0.019, 0.0198, 0.02, 0.025}) {
        if (std::abs(pen - 0.01) < 1e-6 || std::abs(pen - pc) < 1e-6) continue;
        const double h = 1e-9;
        const double dE = (kLaw.energy(pen + h) - kLaw.energy(pen - h)) / (2 * h);
        const double dF = (kLaw.force(pen + h) - kLaw.force(pen - h)) / (2 * h);
        EXPECT_NEAR(dE, kLaw.force(pen), 1e-6 * std::abs(kLaw.force(pen))) << "pen " << pen;
        EXPECT_NEAR(dF, kLaw.ks * kLaw.factor(pen), 1e-5 * kLaw.ks * kLaw.factor(pen)) << "pen " << pen;
        ++checked;
    }
    EXPECT_EQ(checked, 7);
}

TEST(StiffeningLaw, ContinuousAtItsJointsAndBounded) {
    const double ps = 0.01, pc = kLaw.cap_penetration();
    for (double joint : {ps, pc}) {
        const double e = 1e-12;
        EXPECT_NEAR(kLaw.force(joint - e), kLaw.force(joint + e), 1e-6 * kLaw.force(joint)) << joint;
        // E changes by F·2e across the joint, no jump
        EXPECT_NEAR(kLaw.energy(joint - e), kLaw.energy(joint + e), 3e-12 * kLaw.force(joint)) << joint;
    }
    EXPECT_NEAR(kLaw.factor(pc - 1e-12), kLaw.max_factor, 1e-3 * kLaw.max_factor);  // (g_s/g)² reaches κ there
    EXPECT_EQ(kLaw.factor(pc), kLaw.max_factor);
    EXPECT_EQ(kLaw.factor(1.0), kLaw.max_factor);
    // closed forms: at the far side (pen = D) the force is F(p_c) + κ·ks·g_c, with
    // F(p_c) = ks·(p_s + g_s·√κ − g_s); the energy there is finite
    const double gs = 0.01, gc = gs / 100.0;
    const double fc = kLaw.ks * (ps + gs * 100.0 - gs);
    EXPECT_NEAR(kLaw.force(pc), fc, 1e-9 * fc);
    EXPECT_NEAR(kLaw.force(0.02), fc + kLaw.max_factor * kLaw.ks * gc, 1e-9 * fc);
    const double e_far = 0.5 * kLaw.ks * ps * ps + kLaw.ks * (ps - gs) * (pc - ps) +
                         kLaw.ks * gs * gs * std::log(100.0) + fc * gc + 0.5 * kLaw.max_factor * kLaw.ks * gc * gc;
    EXPECT_NEAR(kLaw.energy(0.02), e_far, 1e-12 * e_far);
    // it stores more than SOFA's spring over its reach: ½·ks·D² = 0.4 J
    EXPECT_GT(kLaw.energy(0.02), 2.0 * 0.5 * kLaw.ks * 0.02 * 0.02);
}

}  // namespace
}  // namespace penalty
