// The projective constraints of projective_constraints.hpp: projections are projections (P² = P),
// projected positions lie on their line / plane / point, velocities and responses lose exactly the
// constrained components, and the rows an assembled system discards are SOFA's. The prescribed
// motions and AttachProjectiveConstraint: test_prescribed_motion_constraints.cpp,
// test_attach_constraint.cpp.
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

TEST(LineProjectiveConstraint, PositionsOnTheLineAndResponsesAlongIt) {
    Vec3Object s = random_moving_points(6, 1);
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
    Vec3Object s = random_moving_points(5, 3);
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
    Vec3Object s = random_moving_points(4, 4);
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
    Vec3Object s = random_moving_points(3, 6);
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
    Vec3Object s = random_moving_points(4, 8);
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
    Vec3Object s = random_moving_points(3, 9);
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

}  // namespace
}  // namespace penalty
