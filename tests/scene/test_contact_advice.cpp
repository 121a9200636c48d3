// `penalty info --contact-advice` (contact_advice.cpp): a 2 kg ball of radius 0.1 falling 1.8 m
// onto a static triangle (NewProximity alarm 0.5, contact 0.05, k = 10 on both models, dt 0.01,
// g = 10): v = √(2·g·H) = 6 m/s, D = 0.05 + 0.1, A = 0.5 + 0.1, ks = 10·10/0.15 (SOFA's
// k1·k2/dist). Each number against its closed form, the printed lines, an explicit contact's
// stability limit, and the scenes with nothing to advise.
#include "penalty/scene/contact_advice.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using namespace penalty;

/// The ball (height 1.8, velocity `v0` downwards) with `solver` in its node, over the floor y = 0.
std::string advice_scene(const std::string& solver, double v0 = 0.0, bool ball_simulated = true) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <DefaultAnimationLoop/>
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <NewProximityIntersection alarmDistance="0.5" contactDistance="0.05"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Floor">
    <MechanicalObject name="floor" position="-5 0 -5  5 0 -5  0 0 5"/>
    <MeshTopology triangles="0 1 2"/>
    <TriangleCollisionModel name="floor_triangles" moving="0" simulated="0" contactStiffness="10"/>
  </Node>
  <Node name="Ball">
    )" + solver +
           R"(
    <MechanicalObject name="ball" position="0 1.8 0" velocity="0 )" +
           std::to_string(-v0) + R"( 0"/>
    <UniformMass totalMass="2"/>
    <SphereCollisionModel name="ball_sphere" radius="0.1" contactStiffness="10" simulated=")" +
           (ball_simulated ? "1" : "0") + R"("/>
  </Node>
</Node>)";
}

const std::string kImplicit =
    R"(<EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-20"/>)";

TEST(ContactAdvice, TheNumbersOfAFallingBallAreTheirClosedForms) {
    auto s = test::build(advice_scene(kImplicit));
    EXPECT_NEAR(scene::estimated_impact_speed(*s), 6.0, 1e-14);
    const std::vector<scene::PairAdvice> pairs = scene::contact_advice_pairs(*s);
    ASSERT_EQ(pairs.size(), 1u);
    const scene::PairAdvice& a = pairs[0];
    EXPECT_EQ(a.model1, "floor_triangles");
    EXPECT_EQ(a.model2, "ball_sphere");
    EXPECT_NEAR(a.impact_speed, 6.0, 1e-14);
    EXPECT_EQ(a.mass, 2.0);  // the floor does not move: the ball's mass per contact point
    EXPECT_NEAR(a.reach, 0.15, 1e-16);
    EXPECT_NEAR(a.alarm, 0.6, 1e-16);
    EXPECT_NEAR(a.ks, 100.0 / 0.15, 1e-12);
    EXPECT_EQ(a.dt, 0.01);
    EXPECT_NEAR(a.max_dt_detection, 0.1, 1e-16);
    EXPECT_NEAR(a.min_ks_energy, 2.0 * 36.0 / 0.0225, 1e-9);
    EXPECT_EQ(a.min_ks_implicit, 0.0);  // v·dt = 0.06 < D
    EXPECT_FALSE(a.explicit_contact);
    EXPECT_NEAR(a.cg_iterations, std::sqrt(1.0 + 1e-4 * (100.0 / 0.15) / 2.0) * std::log(2.0 / 1e-9), 1e-12);
    EXPECT_EQ(a.cg_limit, 25);
    EXPECT_FALSE(a.safe());  // ks 667 < 3 200
    // at 1 m/s the spring is stiff enough: m·v²/D² = 88.9
    const scene::PairAdvice slow = scene::contact_advice_pairs(*s, 1.0)[0];
    EXPECT_NEAR(slow.min_ks_energy, 2.0 / 0.0225, 1e-12);
    EXPECT_TRUE(slow.safe());
    // thrown down at 4 m/s: v = 4 + 6; the implicit condition m·(v·dt − D)/(dt²·D) still 0
    auto thrown = test::build(advice_scene(kImplicit, 4.0));
    EXPECT_NEAR(scene::estimated_impact_speed(*thrown), 10.0, 1e-14);
    // at 20 m/s: v·dt = 0.2 > D: 2·(0.2 − 0.15)/(1e-4·0.15)
    EXPECT_NEAR(scene::contact_advice_pairs(*s, 20.0)[0].min_ks_implicit, 2.0 * 0.05 / (1e-4 * 0.15), 1e-6);
}

TEST(ContactAdvice, ThePrintedAdviceNamesThePairAndWhatIsNotMet) {
    auto s = test::build(advice_scene(kImplicit));
    const std::string text = scene::contact_advice(*s);
    EXPECT_EQ(text,
              "contact advice (docs/no-tunnelling.md, \"Advice\"): dt = 0.01 s, impact speed v = 6 m/s (initial "
              "speed + sqrt(2 g H), H the scene's height; --impact-speed V to set it)\n"
              "scene: largest dt 0.1 s (pair floor_triangles - ball_sphere), smallest contact stiffness ks 3.2e+03 "
              "N/m (pair floor_triangles - ball_sphere); 1 of 1 model pairs may tunnel at the scene's dt and ks\n"
              "pair floor_triangles - ball_sphere: mass per contact point m = 2 kg, reach D = 0.15 m, first seen at "
              "A = 0.6 m, spring ks = 667 N/m\n"
              "  detection: dt <= A/v = 0.1 s\n"
              "  energy: ks >= m v^2/D^2 = 3.2e+03 N/m  (NOT MET)\n"
              "  solve: implicit Euler (A-stable for any ks); CG needs about sqrt(1 + dt^2 ks/m) ln(2/tol) = 21.8 "
              "iterations of its limit 25\n"
              "  => largest dt 0.1 s, smallest ks 3.2e+03 N/m\n");
}

TEST(ContactAdvice, AnExplicitContactHasItsStabilityLimit) {
    // an explicit solver: the contact is explicit, stable for dt <= 2·√(m/ks) = 2·√(2·0.15/100)
    auto s = test::build(advice_scene("<EulerExplicitSolver/>"));
    const scene::PairAdvice a = scene::contact_advice_pairs(*s, 1.0)[0];
    EXPECT_TRUE(a.explicit_contact);
    EXPECT_NEAR(a.max_dt_explicit, 2.0 * std::sqrt(0.003), 1e-15);
    EXPECT_EQ(a.cg_limit, 0);
    EXPECT_TRUE(a.safe());  // 0.01 ≤ 0.1095
    EXPECT_NE(scene::contact_advice(*s, 1.0).find("stable for dt <= 2 sqrt(m/ks) = 0.11 s\n"), std::string::npos);
}

TEST(ContactAdvice, NothingMovingNothingToAdvise) {
    // the ball in no solver's subtree: neither side moves, no pair to advise on
    auto unsolved = test::build(advice_scene(""));
    EXPECT_TRUE(scene::contact_advice_pairs(*unsolved).empty());
    // the ball not simulated: the broad phase keeps no pair of two static models
    auto s = test::build(advice_scene(kImplicit, 0.0, false));
    EXPECT_TRUE(scene::contact_advice_pairs(*s).empty());
    const std::string text = scene::contact_advice(*s, 3.0);
    EXPECT_EQ(text.substr(text.find('\n') + 1),
              "no model pair can tunnel (no moving model paired with a triangle, edge or sphere model)\n");
    EXPECT_NE(text.find("impact speed v = 3 m/s (--impact-speed)"), std::string::npos);
}

}  // namespace
