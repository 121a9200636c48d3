// PointCylinder: signed distance to a solid cylinder against surface sampling; points on the axis, zero radius.
#include "penalty/geometry/point_cylinder.hpp"
#include "sampling_references.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>

namespace penalty {
namespace {

using namespace test_geometry;

TEST(PointCylinder, SignedDistanceMatchesSurfaceSampling) {
    std::mt19937 g(2024);
    int inside = 0, outside = 0;
    std::set<CylinderFeature> seen;
    for (int s = 0; s < 300; ++s) {
        CylinderShape c;
        c.center = rand_vec(g, 0.5);
        c.axis = rand_unit(g);
        c.radius = 0.2 + 0.5 * std::uniform_real_distribution<double>(0, 1)(g);
        c.half_height = 0.2 + 0.6 * std::uniform_real_distribution<double>(0, 1)(g);
        const Vec3 p = c.center + rand_vec(g, s % 2 ? 1.5 : 0.5);
        const PointCylinderResult r = point_cylinder_signed_distance(p, c);
        double brute = std::numeric_limits<double>::infinity();
        for (const Vec3& x : cylinder_surface(c, 60)) brute = std::min(brute, (x - p).norm());
        // the exact distance is below every sample and above the best sample minus the grid
        // resolution
        const double tol =
            std::hypot(2.0 * std::numbers::pi * c.radius / 240.0, 2.0 * c.half_height / 60.0, c.radius / 60.0);
        EXPECT_LE(std::abs(r.signed_distance), brute + 1e-12);
        EXPECT_GE(std::abs(r.signed_distance), brute - tol);
        EXPECT_NEAR((p - (r.closest + r.signed_distance * r.normal)).norm(), 0.0, 1e-12);
        EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12);
        (r.signed_distance < 0 ? inside : outside)++;
        seen.insert(r.feature);
    }
    EXPECT_GE(inside, 20);
    EXPECT_GE(outside, 100);
    EXPECT_EQ(seen.size(), 5u);
}

TEST(PointCylinder, PointOnAxisAndZeroRadius) {
    CylinderShape c;  // r 0.5, h 1, axis y
    auto r = point_cylinder_signed_distance(Vec3(0, 0.2, 0), c);
    EXPECT_DOUBLE_EQ(r.signed_distance, -0.5);
    EXPECT_TRUE(r.normal.allFinite());
    EXPECT_NEAR(r.normal.dot(Vec3::UnitY()), 0.0, 1e-15);
    c.radius = 0.0;
    r = point_cylinder_signed_distance(Vec3(0, 0.2, 0), c);
    EXPECT_DOUBLE_EQ(r.signed_distance, 0.0);
    EXPECT_TRUE(r.normal.allFinite());
    r = point_cylinder_signed_distance(Vec3(2, 0.2, 0), c);
    EXPECT_DOUBLE_EQ(r.signed_distance, 2.0);
}

}  // namespace
}  // namespace penalty
