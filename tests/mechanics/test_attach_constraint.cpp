// AttachProjectiveConstraint (mechanics/attach_constraint.cpp): a Vec3 follower goes half way and
// velocities average; a Rigid3 follower copies the frame unless rotations are free.
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

TEST(AttachProjectiveConstraint, Vec3FollowerGoesHalfWayAndVelocitiesAverage) {
    Vec3Object a = random_moving_points(2, 13), b = random_moving_points(3, 14);
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
