// The projective constraints built from scenes (scene/builder/projective_constraints.cpp): a particle
// slides down its line as implicit Euler predicts, plane and point constraints hold their points,
// LinearMovement lags one step behind the step's time as SOFA's.
#include "field_and_constraint_scenes.hpp"

namespace {

using namespace penalty;
using namespace penalty::test_field_scenes;
using penalty::test::build;
using ::testing::HasSubstr;

TEST(FieldAndConstraintComponents, ParticleSlidesDownItsLineAsImplicitEulerPredicts) {
    // line through the origin along (1, −1, 0)/√2: the gravity component along it is g/√2, and
    // implicit Euler without stiffness gives v_n = n h a, x_n = x_0 + h² a n(n+1)/2 along n
    auto s = build(
        particles("0 0 0  5 5 5", R"(<LineProjectiveConstraint indices="0" origin="0 0 0" direction="1 -1 0"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("keeps 1 point on the line through (0, 0, 0)"));
    const int steps = 30;
    for (int i = 0; i < steps; ++i) s->step();
    const Vec3 n = Vec3(1, -1, 0).normalized();
    const double a = 10 / std::sqrt(2.0), h = 0.01;
    const Vec3Object& x = vec3_dofs(*s);
    EXPECT_NEAR((x.position[0] - n * (h * h * a * steps * (steps + 1) / 2)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((x.velocity[0] - n * (h * a * steps)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(x.position[1].y(), 5 - h * h * 10 * steps * (steps + 1) / 2, 1e-11) << "the other point falls freely";
}

TEST(FieldAndConstraintComponents, PlaneAndPointConstraintsHoldTheirPoints) {
    auto s = build(particles("0 1 0  2 3 4  1 1 1",
                             R"(<PlaneProjectiveConstraint indices="0 1" origin="0 1 0" normal="0 1 0"/>
                                <PointProjectiveConstraint indices="2" point="1 1 1"/>)"));
    for (int i = 0; i < 10; ++i) s->step();
    const Vec3Object& x = vec3_dofs(*s);
    EXPECT_NEAR(x.position[0].y(), 1.0, 1e-15);
    EXPECT_NEAR(x.position[1].y(), 1.0, 1e-15) << "projected onto the plane at init";
    EXPECT_EQ(x.position[2], Vec3(1, 1, 1));
}

TEST(FieldAndConstraintComponents, LinearMovementLagsOneStepBehindTheStepsTime) {
    // SOFA projects after the solve at the context time, still the step's start: after step k
    // the point is at the movement of time (k − 1)·h
    auto s = build(particles(
        "1 0 0", R"(<LinearMovementProjectiveConstraint indices="0" keyTimes="0 1" movements="0 0 0  2 0 0"/>)"));
    const int steps = 10;
    for (int i = 0; i < steps; ++i) s->step();
    const Vec3Object& x = vec3_dofs(*s);
    EXPECT_NEAR(x.position[0].x(), 1 + 2 * 0.01 * (steps - 1), 1e-14);
    EXPECT_NEAR(x.position[0].y(), 0.0, 1e-15);
    EXPECT_NEAR(x.velocity[0].x(), 2.0, 1e-14);
}

}  // namespace
