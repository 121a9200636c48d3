#include "penalty/mechanics/fixed_plane_constraint.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

TEST(FixedPlaneProjectiveConstraint, SelectsThePointsStrictlyBetweenThePlanes) {
    const std::vector<Vec3> points{Vec3(0, 0, -0.1), Vec3(5, 3, 0.05), Vec3(1, 1, 0.1), Vec3(0, 0, -0.09),
                                   Vec3(0, 0, 2)};
    EXPECT_EQ(points_between_planes(points, Vec3(0, 0, 1), -0.1, 0.1), (std::vector<Index>{1, 3}));
    // p·d with d not normalised: z·2 in (-0.1, 0.1) keeps |z| < 0.05 only.
    EXPECT_EQ(points_between_planes(points, Vec3(0, 0, 2), -0.1, 0.1), (std::vector<Index>{}));
    EXPECT_EQ(points_between_planes(points, Vec3(0, 0, 2), -0.2, 0.2), (std::vector<Index>{1, 3}));
}

TEST(FixedPlaneProjectiveConstraint, RemovesTheNormalComponentOfResponsesOnly) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    s.velocity = {Vec3(1, 2, 3), Vec3(4, 5, 6), Vec3(7, 8, 9)};
    s.init();
    const Vec3 d = Vec3(1, 0, 1).normalized();
    FixedPlaneProjectiveConstraint c(s, d);
    c.set_indices({0, 2});
    c.init();
    Eigen::VectorXd dx(9);
    dx << 1, 2, 3, 4, 5, 6, 7, 8, 9;
    const Eigen::VectorXd before = dx;
    c.project_response(dx);
    for (int i : {0, 2}) {
        const Vec3 u = before.segment<3>(3 * i);
        const Vec3 p = dx.segment<3>(3 * i);
        EXPECT_NEAR(p.dot(d), 0.0, 1e-14) << i;
        EXPECT_NEAR((p - (u - d * u.dot(d))).norm(), 0.0, 1e-14) << i;
        EXPECT_EQ(p.y(), u.y());  // the in-plane component is kept
    }
    EXPECT_EQ(dx.segment<3>(3), before.segment<3>(3));  // not listed: untouched
    // Positions and velocities are left as they are (SOFA's projectPosition/projectVelocity).
    c.project_velocity();
    EXPECT_EQ(s.velocity[0], Vec3(1, 2, 3));
    EXPECT_EQ(s.position[2], Vec3(2, 0, 0));
    c.set_indices({3});
    EXPECT_THROW(c.init(), std::invalid_argument);
}

TEST(FixedPlaneProjectiveConstraint, RigidDofsProjectTheirLinearPart) {
    Rigid3Object s;
    s.position.assign(2, RigidFrame{});
    s.init();
    FixedPlaneProjectiveConstraint c(s, Vec3(0, 1, 0));
    c.set_indices({1});
    c.init();
    Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(12, 1, 12);
    c.project_response(v);
    Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(12, 1, 12);
    expected(7) = 0.0;  // DOF 1's linear y; its angular part (9..11) is kept
    EXPECT_EQ(v, expected);
}

}  // namespace
}  // namespace penalty
