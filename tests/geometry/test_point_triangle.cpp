// PointTriangle: closest point on a triangle against dense barycentric sampling (all seven features), invariance, zero
// area.
#include "penalty/geometry/point_triangle.hpp"
#include "sampling_references.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace penalty {
namespace {

using namespace test_geometry;

TEST(PointTriangle, MatchesDenseSamplingAndCoversAllSevenFeatures) {
    std::mt19937 g(4242);
    std::set<TriangleFeature> seen;
    for (int s = 0; s < 400; ++s) {
        const Vec3 a = rand_vec(g, 1), b = rand_vec(g, 1), c = rand_vec(g, 1), p = rand_vec(g, 1.5);
        const PointTriangleResult r = point_triangle_closest_point(p, a, b, c);
        const double brute = brute_point_triangle(p, a, b, c, 150);
        const double d = std::sqrt(r.distance_squared);
        EXPECT_LE(d, brute + 1e-12);
        EXPECT_GE(d, brute - 2e-2 * 0.5);
        const Vec3& w = r.barycentric;
        EXPECT_NEAR(w.sum(), 1.0, 1e-12);
        EXPECT_GE(w.minCoeff(), -1e-12);
        EXPECT_NEAR((w[0] * a + w[1] * b + w[2] * c - r.closest).norm(), 0.0, 1e-12);
        seen.insert(r.feature);
    }
    EXPECT_EQ(seen.size(), 7u);
}

TEST(PointTriangle, InvariantUnderVertexPermutationAndRigidMotion) {
    std::mt19937 g(99);
    for (int s = 0; s < 200; ++s) {
        const Vec3 v[3] = {rand_vec(g, 1), rand_vec(g, 1), rand_vec(g, 1)};
        const Vec3 p = rand_vec(g, 1.5);
        const double d0 = point_triangle_closest_point(p, v[0], v[1], v[2]).distance_squared;
        const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
        for (const auto& pm : perm)
            EXPECT_NEAR(point_triangle_closest_point(p, v[pm[0]], v[pm[1]], v[pm[2]]).distance_squared, d0, 1e-12);
        const Mat3 R = Eigen::AngleAxisd(2.0 * s, rand_unit(g)).toRotationMatrix();
        const Vec3 t = rand_vec(g, 5);
        const auto moved = point_triangle_closest_point(R * p + t, R * v[0] + t, R * v[1] + t, R * v[2] + t);
        EXPECT_NEAR(moved.distance_squared, d0, 1e-11);
    }
}

TEST(PointTriangle, ZeroAreaTriangleFallsBackToEdges) {
    // collinear vertices and a fully collapsed triangle: no NaN, edge distance
    const auto r = point_triangle_closest_point(Vec3(0.5, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0));
    EXPECT_TRUE(r.degenerate);
    EXPECT_DOUBLE_EQ(r.distance_squared, 1.0);
    EXPECT_TRUE(r.closest.allFinite());
    const Vec3 z(3, 3, 3);
    const auto r2 = point_triangle_closest_point(Vec3(3, 3, 4), z, z, z);
    EXPECT_TRUE(r2.degenerate);
    EXPECT_DOUBLE_EQ(r2.distance_squared, 1.0);
    EXPECT_TRUE(r2.barycentric.allFinite());
}

}  // namespace
}  // namespace penalty
