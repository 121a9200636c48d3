// The prescribed motions (mechanics/prescribed_motion_constraints.cpp): LinearMovement follows its
// piecewise linear keys at the clock time (a Rigid3 rotation by slerp); Parabolic passes through its
// three points in their plane.
#include "constraint_samples.hpp"
#include "penalty/mechanics/attach_constraint.hpp"
#include "penalty/mechanics/prescribed_motion_constraints.hpp"
#include "penalty/mechanics/projective_constraints.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace penalty {
namespace {

using namespace test_samples;

TEST(LinearMovementProjectiveConstraint, FollowsThePiecewiseLinearMotionAtTheClockTime) {
    Vec3Object s = random_moving_points(2, 11);
    const Vec3 x0 = s.position[0];
    double now = 0.0;
    LinearMovementProjectiveConstraint<Vec3Types> c(
        s, {0}, {0.0, 1.0, 3.0}, {Vec3::Zero(), Vec3(1, 0, 0), Vec3(1, 4, 0)}, true, [&now] { return now; });
    c.init();
    c.project_position();  // t = 0: x0 recorded, m = 0
    EXPECT_EQ(s.position[0], x0);
    now = 0.25;
    c.project_position();
    c.project_velocity();
    EXPECT_NEAR((s.position[0] - (x0 + Vec3(0.25, 0, 0))).norm(), 0.0, 1e-15);
    EXPECT_EQ(s.velocity[0], Vec3(1, 0, 0));
    now = 2.0;
    c.project_position();
    c.project_velocity();
    EXPECT_NEAR((s.position[0] - (x0 + Vec3(1, 2, 0))).norm(), 0.0, 1e-15);
    EXPECT_NEAR((s.velocity[0] - Vec3(0, 2, 0)).norm(), 0.0, 1e-15);
    Eigen::VectorXd r = Eigen::VectorXd::Ones(6);
    c.project_response(r);
    EXPECT_EQ(r.segment<3>(0), Vec3::Zero());
    EXPECT_EQ(r.segment<3>(3), Vec3::Ones());
    // at the last key time no segment is found: the motion stops, responses are free again
    now = 3.0;
    const Vec3 held = s.position[0];
    c.project_position();
    EXPECT_EQ(s.position[0], held);
    r.setOnes();
    c.project_response(r);
    EXPECT_EQ(r, Eigen::VectorXd::Ones(6));
    std::vector<Index> rows;
    EXPECT_TRUE(c.list_discarded_rows(rows));
    EXPECT_EQ(rows, (std::vector<Index>{0, 1, 2}));
}

TEST(LinearMovementProjectiveConstraint, Rigid3AbsoluteRotationIsTheSlerpOfTheKeys) {
    Rigid3Object s;
    s.position.resize(1);
    s.init();
    double now = 0.5;
    RigidDeriv start, end;
    end.linear = Vec3(2, 0, 0);
    end.angular = Vec3(0, 0, std::numbers::pi / 2);  // Euler angles: 90° about z
    LinearMovementProjectiveConstraint<Rigid3Types> c(s, {0}, {0.0, 1.0}, {start, end}, false, [&now] { return now; });
    c.init();
    c.project_position();
    EXPECT_NEAR((s.position[0].center - Vec3(1, 0, 0)).norm(), 0.0, 1e-15);
    const Quat expected(Eigen::AngleAxisd(std::numbers::pi / 4, Vec3::UnitZ()));
    EXPECT_NEAR(s.position[0].orientation.angularDistance(expected), 0.0, 1e-12);
}

TEST(ParabolicProjectiveConstraint, PassesThroughItsThreePointsInItsPlane) {
    Vec3Object s = random_moving_points(1, 12);
    double now = 0.5;
    const Vec3 p1(1, 0, 0), p2(5, 3, 1), p3(7, 6, -5);
    ParabolicProjectiveConstraint<Vec3Types> c(
        s, {0}, p1, p2, p3, 0.5, 1.5, [&now] { return now; }, [] { return 0.01; });
    c.init();
    EXPECT_NEAR((c.point_at(0.5) - p1).norm(), 0.0, 1e-12);
    EXPECT_NEAR((c.point_at(1.5) - p3).norm(), 0.0, 1e-12);
    const Vec3 normal = (p3 - p1).cross(p2 - p1).normalized();
    // P2 lies on the curve: at the time whose abscissa along P1P3 is P2's
    const double r = (p2 - p1).dot((p3 - p1).normalized()) / (p3 - p1).norm();
    EXPECT_NEAR((c.point_at(0.5 + r) - p2).norm(), 0.0, 1e-12);
    for (double t = 0.5; t <= 1.5; t += 0.1) EXPECT_NEAR((c.point_at(t) - p1).dot(normal), 0.0, 1e-12);
    now = 0.7;
    c.project_position();
    c.project_velocity();
    EXPECT_EQ(s.position[0], c.point_at(0.7));
    EXPECT_NEAR((s.velocity[0] - (c.point_at(0.71) - c.point_at(0.7)) / 0.01).norm(), 0.0, 1e-9);
    now = 2.0;  // outside the interval: nothing
    const Vec3 held = s.position[0];
    c.project_position();
    EXPECT_EQ(s.position[0], held);
    ParabolicProjectiveConstraint<Vec3Types> degenerate(
        s, {0}, p1, p1, p3, 0, 1, [] { return 0.0; }, [] { return 0.01; });
    EXPECT_THROW(degenerate.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
