// ConvexDistance / ConvexPenetration: cylinder-triangle and cylinder-cylinder distances against sampling, an overlap's
// depth and normal.
#include "penalty/geometry/convex_distance.hpp"
#include "penalty/geometry/point_triangle.hpp"
#include "sampling_references.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace penalty {
namespace {

using namespace test_geometry;

TEST(ConvexDistance, CylinderTriangleAndCylinderCylinderAgainstSampling) {
    std::mt19937 g(555);
    int separated = 0, overlapping = 0;
    for (int s = 0; s < 150; ++s) {
        CylinderShape c;
        c.center = rand_vec(g, 0.3);
        c.axis = rand_unit(g);
        c.radius = 0.2 + 0.3 * std::uniform_real_distribution<double>(0, 1)(g);
        c.half_height = 0.2 + 0.4 * std::uniform_real_distribution<double>(0, 1)(g);
        const ConvexShape A = ConvexShape::make_cylinder(c);
        if (s % 2 == 0) {
            const Vec3 t[3] = {rand_vec(g, 1.2), rand_vec(g, 1.2), rand_vec(g, 1.2)};
            const auto r = convex_distance(A, ConvexShape::triangle(t[0], t[1], t[2]));
            // reference: exact point-cylinder distance over a dense triangle sampling
            double brute = std::numeric_limits<double>::infinity();
            const int n = 120;
            for (int i = 0; i <= n; ++i)
                for (int j = 0; i + j <= n; ++j) {
                    const Vec3 x = t[0] + (double(i) / n) * (t[1] - t[0]) + (double(j) / n) * (t[2] - t[0]);
                    brute = std::min(brute, std::max(0.0, point_cylinder_signed_distance(x, c).signed_distance));
                }
            if (brute > 1e-2) {
                ++separated;
                EXPECT_FALSE(r.overlapping);
                EXPECT_LE(r.distance, brute + 1e-7);
                EXPECT_GE(r.distance, brute - 3e-2);
                EXPECT_NEAR(point_cylinder_signed_distance(r.point_a, c).signed_distance, 0.0, 1e-6);
                EXPECT_NEAR(point_triangle_closest_point(r.point_b, t[0], t[1], t[2]).distance_squared, 0.0, 1e-12);
            } else if (brute == 0.0) {
                ++overlapping;
                EXPECT_TRUE(r.overlapping || r.distance < 1e-6);
            }
        } else {
            CylinderShape d;
            d.center = rand_vec(g, 1.2);
            d.axis = rand_unit(g);
            d.radius = 0.1 + 0.3 * std::uniform_real_distribution<double>(0, 1)(g);
            d.half_height = 0.1 + 0.4 * std::uniform_real_distribution<double>(0, 1)(g);
            const auto r = convex_distance(A, ConvexShape::make_cylinder(d));
            double brute = std::numeric_limits<double>::infinity();
            bool inside_any = false;
            for (const Vec3& x : cylinder_surface(d, 40)) {
                const double sd = point_cylinder_signed_distance(x, c).signed_distance;
                inside_any = inside_any || sd <= 0.0;
                brute = std::min(brute, std::max(0.0, sd));
            }
            if (!inside_any && brute > 1e-2) {
                ++separated;
                EXPECT_FALSE(r.overlapping);
                EXPECT_LE(r.distance, brute + 1e-7);
                EXPECT_GE(r.distance, brute - 3e-2);
                EXPECT_NEAR(point_cylinder_signed_distance(r.point_a, c).signed_distance, 0.0, 1e-6);
                EXPECT_NEAR(point_cylinder_signed_distance(r.point_b, d).signed_distance, 0.0, 1e-6);
            } else if (inside_any) {
                ++overlapping;
                EXPECT_TRUE(r.overlapping || r.distance < 1e-6);
            }
        }
    }
    EXPECT_GE(separated, 40);
    EXPECT_GE(overlapping, 10);
}

TEST(ConvexPenetration, AxisAlignedOverlapOfTwoCylinders) {
    CylinderShape a, b;  // axis y, r 0.5, h 1
    b.center = Vec3(0.8, 0, 0);
    const Vec3 cands[] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    const auto p = convex_penetration(ConvexShape::make_cylinder(a), ConvexShape::make_cylinder(b), cands);
    EXPECT_NEAR(p.depth, 0.2, 1e-12);
    EXPECT_NEAR((p.normal - Vec3::UnitX()).norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace penalty
