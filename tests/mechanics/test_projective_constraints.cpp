// The projective constraints of projective_constraints.hpp, prescribed_motion_constraints.hpp and
// attach_constraint.hpp: projections are projections (P² = P), projected positions lie on their
// line / plane / point, velocities and responses lose exactly the constrained components, the
// prescribed motions follow their closed forms at SOFA's (start-of-step) time, and the rows an
// assembled system discards are SOFA's.
#include "penalty/mechanics/attach_constraint.hpp"
#include "penalty/mechanics/prescribed_motion_constraints.hpp"
#include "penalty/mechanics/projective_constraints.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace penalty {
namespace {

Vec3Object random_points(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    Vec3Object s;
    for (std::size_t i = 0; i < n; ++i) s.position.emplace_back(u(rng), u(rng), u(rng));
    s.init();
    for (std::size_t i = 0; i < n; ++i) s.velocity[i] = Vec3(u(rng), u(rng), u(rng));
    return s;
}

Eigen::VectorXd random_vector(Eigen::Index n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) v[i] = u(rng);
    return v;
}

TEST(LineProjectiveConstraint, PositionsOnTheLineAndResponsesAlongIt) {
    Vec3Object s = random_points(6, 1);
    const Vec3 origin(1, 2, 3), direction(1, 1, 0);
    LineProjectiveConstraint c(s, {0, 2, 5}, origin, direction);
    c.init();
    const Vec3 n = direction.normalized();
    EXPECT_NEAR((c.unit_direction() - n).norm(), 0.0, 1e-15);
    c.project_position();
    for (Index i : {0, 2, 5}) {
        const Vec3 d = s.position[static_cast<std::size_t>(i)] - origin;
        EXPECT_NEAR((d - n * d.dot(n)).norm(), 0.0, 1e-14) << "point " << i << " is off the line";
    }
    const Vec3 untouched = s.position[1];
    EXPECT_EQ(s.position[1], untouched);
    c.project_velocity();
    for (Index i : {0, 2, 5}) EXPECT_NEAR(s.velocity[static_cast<std::size_t>(i)].cross(n).norm(), 0.0, 1e-15);
    // P² = P on a random response, and P u = (u·n) n at the constrained points only
    Eigen::VectorXd v = random_vector(18, 2);
    const Eigen::VectorXd before = v;
    c.project_response(v);
    Eigen::VectorXd twice = v;
    c.project_response(twice);
    EXPECT_LT((twice - v).cwiseAbs().maxCoeff(), 1e-15) << "P² = P";
    for (Index i = 0; i < 6; ++i) {
        const Vec3 u = before.segment<3>(3 * i), p = v.segment<3>(3 * i);
        if (i == 0 || i == 2 || i == 5) EXPECT_NEAR((p - n * u.dot(n)).norm(), 0.0, 1e-15);
        else EXPECT_EQ(p, u);
    }
}

TEST(LineProjectiveConstraint, ZeroDirectionMeansXAndRepeatedIndexStopsTheJacobian) {
    Vec3Object s = random_points(5, 3);
    LineProjectiveConstraint zero(s, {1}, Vec3::Zero(), Vec3::Zero());
    zero.init();
    EXPECT_EQ(zero.unit_direction(), Vec3(1, 0, 0));
    // SOFA's updateJacobian walks the sorted indices once: after a repeated index no later one matches
    LineProjectiveConstraint repeated(s, {3, 1, 1}, Vec3::Zero(), Vec3(0, 0, 1));
    repeated.init();
    EXPECT_EQ(repeated.projected_points(), (std::vector<Index>{1}));
    LineProjectiveConstraint out_of_range(s, {7}, Vec3::Zero(), Vec3(0, 0, 1));
    EXPECT_THROW(out_of_range.init(), std::invalid_argument);
}

TEST(PlaneProjectiveConstraint, PositionsOnThePlaneAndNoNormalResponse) {
    Vec3Object s = random_points(4, 4);
    const Vec3 origin(0, 1, 0), normal(0, 2, 0);
    PlaneProjectiveConstraint c(s, {0, 1, 2, 3}, origin, normal);
    c.init();
    c.project_position();
    for (const Vec3& x : s.position) EXPECT_NEAR(x.y(), 1.0, 1e-15);
    c.project_velocity();
    for (const Vec3& v : s.velocity) EXPECT_EQ(v.y(), 0.0);
    Eigen::VectorXd v = random_vector(12, 5);
    c.project_response(v);
    Eigen::VectorXd twice = v;
    c.project_response(twice);
    EXPECT_LT((twice - v).cwiseAbs().maxCoeff(), 1e-15) << "P² = P";
    for (Index i = 0; i < 4; ++i) EXPECT_EQ(v[3 * i + 1], 0.0);
    // a zero normal stays zero: SOFA's projection is then the identity (reproduced)
    PlaneProjectiveConstraint none(s, {0}, origin, Vec3::Zero());
    none.init();
    EXPECT_EQ(none.block(), Mat3::Identity());
}

TEST(DirectionProjectiveConstraint, EachPointStaysOnTheLineThroughItsInitialPosition) {
    Vec3Object s = random_points(3, 6);
    const std::vector<Vec3> initial = s.position;
    DirectionProjectiveConstraint c(s, {0, 2}, Vec3(0, 0, 3));
    c.init();
    for (Vec3& x : s.position) x += Vec3(0.3, -0.2, 0.7);
    c.project_position();
    EXPECT_NEAR((s.position[0] - (initial[0] + Vec3(0, 0, 0.7))).norm(), 0.0, 1e-14);
    EXPECT_NEAR((s.position[2] - (initial[2] + Vec3(0, 0, 0.7))).norm(), 0.0, 1e-14);
    EXPECT_NEAR((s.position[1] - (initial[1] + Vec3(0.3, -0.2, 0.7))).norm(), 0.0, 1e-15);
    Eigen::VectorXd v = random_vector(9, 7);
    const Eigen::VectorXd before = v;
    c.project_response(v);
    EXPECT_EQ(v.segment<3>(0), Vec3(0, 0, before[2]));
    EXPECT_EQ(v.segment<3>(3), before.segment<3>(3));
}

TEST(PointProjectiveConstraint, PointsHeldAtThePointWithRowsDiscarded) {
    Vec3Object s = random_points(4, 8);
    const Vec3 target(1, -1, 2);
    PointProjectiveConstraint c(s, {1, 3}, target, false);
    c.init();
    c.project_position();
    c.project_velocity();
    EXPECT_EQ(s.position[1], target);
    EXPECT_EQ(s.position[3], target);
    EXPECT_EQ(s.velocity[3], Vec3::Zero());
    EXPECT_NE(s.velocity[0], Vec3::Zero());
    std::vector<Index> rows;
    EXPECT_TRUE(c.list_discarded_rows(rows));
    EXPECT_EQ(rows, (std::vector<Index>{3, 4, 5, 9, 10, 11}));
    PointProjectiveConstraint all(s, {}, target, true);
    all.init();
    all.project_position();
    for (const Vec3& x : s.position) EXPECT_EQ(x, target);
}

TEST(PartialFixedProjectiveConstraint, FixedComponentsOnlyAndVelocityOnlyWhenAsked) {
    Vec3Object s = random_points(3, 9);
    PartialFixedProjectiveConstraint c(s, {1}, false, {true, false, true}, false);
    c.init();
    Eigen::VectorXd v = random_vector(9, 10);
    const Eigen::VectorXd before = v;
    c.project_response(v);
    EXPECT_EQ(v[3], 0.0);
    EXPECT_EQ(v[4], before[4]);
    EXPECT_EQ(v[5], 0.0);
    EXPECT_EQ(v.segment<3>(0), before.segment<3>(0));
    const Vec3 velocity = s.velocity[1];
    c.project_velocity();
    EXPECT_EQ(s.velocity[1], velocity) << "projectVelocity is false by default";
    PartialFixedProjectiveConstraint with_velocity(s, {1}, false, {true, false, true}, true);
    with_velocity.init();
    with_velocity.project_velocity();
    EXPECT_EQ(s.velocity[1], Vec3(0, velocity.y(), 0));
    std::vector<Index> rows;
    EXPECT_TRUE(c.list_discarded_rows(rows));
    EXPECT_EQ(rows, (std::vector<Index>{3, 5}));
    PartialFixedProjectiveConstraint wrong(s, {1}, false, {true, true}, false);
    EXPECT_THROW(wrong.init(), std::invalid_argument);
}

TEST(PartialFixedProjectiveConstraint, Rigid3SixDirections) {
    Rigid3Object s;
    s.position.resize(2);
    s.init();
    PartialFixedProjectiveConstraint c(s, {}, true, {false, false, false, true, true, false}, false);
    c.init();
    Eigen::VectorXd v = Eigen::VectorXd::Ones(12);
    c.project_response(v);
    Eigen::VectorXd expected = Eigen::VectorXd::Ones(12);
    expected[3] = expected[4] = expected[9] = expected[10] = 0.0;
    EXPECT_EQ(v, expected);
}

TEST(LinearMovementProjectiveConstraint, FollowsThePiecewiseLinearMotionAtTheClockTime) {
    Vec3Object s = random_points(2, 11);
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
    Vec3Object s = random_points(1, 12);
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

TEST(FixedRotationProjectiveConstraint, RemovesTheTwistAboutTheFixedAxisOnly) {
    Rigid3Object s;
    s.position.resize(1);
    s.init();
    FixedRotationProjectiveConstraint c(s, false, false, true);
    c.init();  // initial orientation: identity
    // a rotation about z alone is undone; about x alone is kept
    s.position[0].orientation = Quat(Eigen::AngleAxisd(0.7, Vec3::UnitZ()));
    c.project_position();
    EXPECT_NEAR(s.position[0].orientation.angularDistance(Quat::Identity()), 0.0, 1e-14);
    const Quat about_x(Eigen::AngleAxisd(0.4, Vec3::UnitX()));
    s.position[0].orientation = about_x;
    c.project_position();
    EXPECT_NEAR(s.position[0].orientation.angularDistance(about_x), 0.0, 1e-14);
    // the projection is a projection: applying it twice changes nothing more
    s.position[0].orientation = Quat(Eigen::AngleAxisd(0.5, Vec3(1, 2, 3).normalized()));
    c.project_position();
    const Quat once = s.position[0].orientation;
    c.project_position();
    EXPECT_NEAR(s.position[0].orientation.angularDistance(once), 0.0, 1e-14);
    // what is left is the swing q·twist⁻¹, a rotation about an axis normal to z: no z component
    EXPECT_NEAR(once.z(), 0.0, 1e-15);
    EXPECT_GT(std::abs(once.x()) + std::abs(once.y()), 0.1);
}

TEST(AttachProjectiveConstraint, Vec3FollowerGoesHalfWayAndVelocitiesAverage) {
    Vec3Object a = random_points(2, 13), b = random_points(3, 14);
    AttachParameters p;
    p.indices1 = {1};
    p.indices2 = {2};
    AttachProjectiveConstraint<Vec3Types> c(a, b, p);
    c.init();
    const Vec3 x1 = a.position[1], x2 = b.position[2];
    c.project_position();
    EXPECT_EQ(a.position[1], x1) << "object1 is not moved (SOFA corrects a copy)";
    EXPECT_NEAR((b.position[2] - (x2 - (x2 - x1) * 0.5)).norm(), 0.0, 1e-15);
    const Vec3 v1 = a.velocity[1], v2 = b.velocity[2];
    c.project_velocity();
    EXPECT_NEAR((a.velocity[1] - (v1 + v2) / 2).norm(), 0.0, 1e-15);
    EXPECT_NEAR((b.velocity[2] - (v1 + v2) / 2).norm(), 0.0, 1e-15);
    Eigen::VectorXd r = Eigen::VectorXd::Ones(9);
    c.project_response(r);
    EXPECT_EQ(r.segment<3>(6), Vec3::Zero());
    std::vector<Index> rows;
    EXPECT_TRUE(c.list_discarded_rows(rows));
    EXPECT_EQ(rows, (std::vector<Index>{6, 7, 8}));
    AttachParameters two_way = p;
    two_way.two_way = true;
    AttachProjectiveConstraint<Vec3Types> apart(a, b, two_way);
    EXPECT_THROW(apart.init(), std::invalid_argument);
}

TEST(AttachProjectiveConstraint, Rigid3CopiesTheFrameUnlessRotationsAreFree) {
    Rigid3Object a, b;
    a.position = {RigidFrame{Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()))}};
    b.position = {RigidFrame{}};
    a.init();
    b.init();
    AttachParameters p;
    p.indices1 = {0};
    p.indices2 = {0};
    p.free_rotations = true;
    AttachProjectiveConstraint<Rigid3Types> c(a, b, p);
    c.init();
    c.project_position();
    EXPECT_EQ(b.position[0].center, Vec3(1, 2, 3));
    EXPECT_EQ(b.position[0].orientation.coeffs(), Quat::Identity().coeffs());
    std::vector<Index> rows;
    EXPECT_TRUE(c.list_discarded_rows(rows));
    EXPECT_EQ(rows, (std::vector<Index>{0, 1, 2}));
}

}  // namespace
}  // namespace penalty
