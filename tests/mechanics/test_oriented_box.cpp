// SOFA's BoxROI oriented box (OrientedBox): the parallelogram p0, p1, p2 extruded by depth/2 on
// each side, against its closed form in the box's own frame.
#include "penalty/mechanics/oriented_box.hpp"
#include "penalty_test/random_draws.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace penalty {
namespace {

TEST(OrientedBox, AnAxisAlignedParallelogramIsTheBoxItSpans) {
    // p0 (0,0,0) → p1 (2,0,0) → p2 (2,1,0), depth 0.4: n = (0,0,1), the box [0,2]×[0,1]×[−0.2,0.2]
    const OrientedBox box(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), 0.4);
    EXPECT_TRUE(box.contains(Vec3(1, 0.5, 0)));
    // the faces are inside (every test is ≤)
    EXPECT_TRUE(box.contains(Vec3(0, 0, -0.2)));
    EXPECT_TRUE(box.contains(Vec3(2, 1, 0.2)));
    EXPECT_TRUE(box.contains(Vec3(2, 0, 0)));
    // just beyond each of the six faces
    EXPECT_FALSE(box.contains(Vec3(-1e-9, 0.5, 0)));
    EXPECT_FALSE(box.contains(Vec3(2 + 1e-9, 0.5, 0)));
    EXPECT_FALSE(box.contains(Vec3(1, -1e-9, 0)));
    EXPECT_FALSE(box.contains(Vec3(1, 1 + 1e-9, 0)));
    EXPECT_FALSE(box.contains(Vec3(1, 0.5, -0.2 - 1e-9)));
    EXPECT_FALSE(box.contains(Vec3(1, 0.5, 0.2 + 1e-9)));
    // the half-planes of a pair of sides alone would take y ∈ [−1, 1] and y ∈ [0, 2]: both are needed
    EXPECT_FALSE(box.contains(Vec3(1, -0.5, 0)));
    EXPECT_FALSE(box.contains(Vec3(1, 1.5, 0)));
    EXPECT_FALSE(box.contains(Vec3(-0.5, 0.5, 0)));
    EXPECT_FALSE(box.contains(Vec3(2.5, 0.5, 0)));
    // BoxROI::isPointInOrientedBox accepts on |·| ≤ w: false for NaN (unlike the aligned box's test)
    EXPECT_FALSE(box.contains(Vec3(std::numeric_limits<double>::quiet_NaN(), 0.5, 0)));
}

TEST(OrientedBox, ANegativeDepthGivesTheSameBoxAsItsMagnitude) {
    // |(p − p0)·n| ≤ |depth/2|, and the side normals lose their sign in |·|
    const OrientedBox positive(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), 0.4);
    const OrientedBox negative(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), -0.4);
    for (const Vec3& p : {Vec3(1, 0.5, 0.19), Vec3(1, 0.5, -0.19), Vec3(1, 0.5, 0.21), Vec3(1, 0.5, -0.21),
                          Vec3(0.1, 0.9, 0.0), Vec3(1, 1.1, 0)})
        EXPECT_EQ(positive.contains(p), negative.contains(p)) << p.transpose();
    EXPECT_TRUE(negative.contains(Vec3(1, 0.5, -0.19)));
    EXPECT_FALSE(negative.contains(Vec3(1, 0.5, 0.21)));
}

TEST(OrientedBox, TheCornersOrderSetsTheNormalNotTheBox) {
    // p0 → p1 → p2 clockwise seen from +z: n = (0,0,−1); the box is the same set
    const OrientedBox box(Vec3(2, 1, 0), Vec3(2, 0, 0), Vec3(0, 0, 0), 0.4);
    EXPECT_TRUE(box.contains(Vec3(1, 0.5, 0.2)));
    EXPECT_TRUE(box.contains(Vec3(0, 0, -0.2)));
    EXPECT_FALSE(box.contains(Vec3(1, 0.5, 0.21)));
    EXPECT_FALSE(box.contains(Vec3(2.01, 0.5, 0)));
}

TEST(OrientedBox, ARotatedBoxAgreesWithItsLocalFrameOnSeededPoints) {
    // a box of sides a (along u), b (along v) and depth d (along w = u × v), rotated and moved;
    // points in the cube around it, each against |local coordinates| in the box's frame, away
    // from the faces by 1e-9 (rounding); a hit rate near the box's share of the cube's volume
    std::mt19937 rng(20261130);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Eigen::AngleAxisd turn(0.7, Vec3(1, 2, 3).normalized());
    const Mat3 r = turn.toRotationMatrix();
    const Vec3 u = r.col(0);
    const Vec3 v = r.col(1);
    const Vec3 w = r.col(2);
    const double a = 1.2;
    const double b = 0.8;
    const double d = 0.5;
    const Vec3 origin(0.3, -0.2, 0.1);
    // p0, p1 = p0 + a·u, p2 = p1 + b·v: n = u × v = w
    const OrientedBox box(origin, origin + a * u, origin + a * u + b * v, d);
    int inside = 0;
    int compared = 0;
    const int samples = 20000;
    for (int i = 0; i < samples; ++i) {
        const Vec3 p = origin + 1.5 * penalty::test::draw_vec3(unit, rng);
        const Vec3 q = p - origin;
        const double s = q.dot(u);
        const double t = q.dot(v);
        const double h = q.dot(w);
        const double margin =
            std::min({std::fabs(s), std::fabs(s - a), std::fabs(t), std::fabs(t - b), std::fabs(std::fabs(h) - d / 2)});
        if (margin < 1e-9) continue;
        const bool expected = s >= 0 && s <= a && t >= 0 && t <= b && std::fabs(h) <= d / 2;
        EXPECT_EQ(box.contains(p), expected) << p.transpose();
        inside += expected ? 1 : 0;
        ++compared;
    }
    EXPECT_EQ(compared, samples);
    // the box's volume a·b·d = 0.48 in the cube of side 3 (27): 1.8 %
    const double rate = double(inside) / double(samples);
    EXPECT_GT(rate, 0.014);
    EXPECT_LT(rate, 0.022);
}

TEST(OrientedBox, AParallelogramThatIsNoRectangleKeepsItsSlantedSides) {
    // p0 (0,0,0) → p1 (1,0,0) → p2 (1.5,1,0): p3 = p0 + (p2 − p1) = (0.5,1,0), sides slanted by
    // 0.5 in x over 1 in y. SOFA tests the two side pairs with the widths w = |(p2 − p0)·m0| = 1
    // and l = |(p2 − p0)·m2| = |(1.5,1,0)·(−2,1,0)/√5| = 2/√5, measured from p0 and from p2.
    const OrientedBox box(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.5, 1, 0), 0.2);
    EXPECT_TRUE(box.contains(Vec3(0.75, 0.5, 0)));  // the centre
    EXPECT_TRUE(box.contains(Vec3(0.26, 0.5, 0)));  // the slanted side x = 0.5y is at 0.25
    EXPECT_FALSE(box.contains(Vec3(0.24, 0.5, 0)));
    EXPECT_TRUE(box.contains(Vec3(1.24, 0.5, 0)));  // the slanted side x = 1 + 0.5y is at 1.25
    EXPECT_FALSE(box.contains(Vec3(1.26, 0.5, 0)));
    // inside the rectangle [0,1.5]×[0,1], not the parallelogram
    EXPECT_FALSE(box.contains(Vec3(0.1, 0.9, 0)));
    EXPECT_FALSE(box.contains(Vec3(1.4, 0.1, 0)));
}

}  // namespace
}  // namespace penalty
