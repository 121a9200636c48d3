// Closest-point kernels against dense-sampling references (seeded), plus degenerate inputs.
#include "penalty/geometry/convex_distance.hpp"
#include "penalty/geometry/point_cylinder.hpp"
#include "penalty/geometry/point_segment.hpp"
#include "penalty/geometry/point_tetrahedron.hpp"
#include "penalty/geometry/point_triangle.hpp"
#include "penalty/geometry/segment_segment.hpp"
#include "penalty/geometry/segment_triangle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>

namespace penalty {
namespace {

Vec3 rand_vec(std::mt19937& g, double s) {
    std::uniform_real_distribution<double> u(-s, s);
    return Vec3(u(g), u(g), u(g));
}
Vec3 rand_unit(std::mt19937& g) {
    Vec3 v;
    do {
        v = rand_vec(g, 1.0);
    } while (v.squaredNorm() < 1e-3 || v.squaredNorm() > 1.0);
    return v.normalized();
}

// distance from p to the triangle by dense barycentric sampling (reference)
double brute_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            const double u = double(i) / n, v = double(j) / n;
            best = std::min(best, (p - (a + u * (b - a) + v * (c - a))).norm());
        }
    return best;
}

// surface samples of a solid cylinder (side grid and both caps)
std::vector<Vec3> cylinder_surface(const CylinderShape& c, int n) {
    std::vector<Vec3> out;
    const Vec3 e1 = any_orthogonal(c.axis);
    const Vec3 e2 = c.axis.cross(e1);
    for (int i = 0; i < 4 * n; ++i) {
        const double th = 2.0 * std::numbers::pi * i / (4 * n);
        const Vec3 radial = std::cos(th) * e1 + std::sin(th) * e2;
        for (int j = 0; j <= n; ++j) {
            const double y = -c.half_height + 2.0 * c.half_height * j / n;
            out.push_back(c.center + y * c.axis + c.radius * radial);
        }
        for (int k = 0; k <= n; ++k) {
            const double rr = c.radius * k / n;
            out.push_back(c.center + c.half_height * c.axis + rr * radial);
            out.push_back(c.center - c.half_height * c.axis + rr * radial);
        }
    }
    return out;
}

TEST(PointSegment, MatchesDenseSamplingAndCoversFeatures) {
    std::mt19937 g(12345);
    std::set<SegmentFeature> seen;
    for (int s = 0; s < 500; ++s) {
        const Vec3 a = rand_vec(g, 1), b = rand_vec(g, 1), p = rand_vec(g, 2);
        const PointSegmentResult r = point_segment_closest_point(p, a, b);
        double brute = std::numeric_limits<double>::infinity();
        for (int i = 0; i <= 4000; ++i) brute = std::min(brute, (p - (a + (i / 4000.0) * (b - a))).norm());
        const double d = std::sqrt(r.distance_squared);
        EXPECT_LE(d, brute + 1e-12);
        EXPECT_GE(d, brute - 1e-3);
        EXPECT_NEAR((r.closest - (a + r.t * (b - a))).norm(), 0.0, 1e-12);
        seen.insert(r.feature);
    }
    EXPECT_EQ(seen.size(), 3u);
}

TEST(PointSegment, ZeroLengthSegmentIsItsEndPoint) {
    const Vec3 a(1, 2, 3);
    const PointSegmentResult r = point_segment_closest_point(Vec3(0, 0, 0), a, a);
    EXPECT_EQ(r.t, 0.0);
    EXPECT_EQ(r.closest, a);
    EXPECT_DOUBLE_EQ(r.distance_squared, 14.0);
}

TEST(SegmentSegment, MatchesReferenceIncludingParallel) {
    std::mt19937 g(777);
    int parallel = 0;
    for (int s = 0; s < 400; ++s) {
        Vec3 a = rand_vec(g, 1), b = rand_vec(g, 1), c = rand_vec(g, 1), d = rand_vec(g, 1);
        if (s % 4 == 0) {  // exactly parallel (or anti-parallel) copies
            const Vec3 off = rand_vec(g, 0.5);
            const double k = (s % 8 == 0) ? 0.7 : -1.3;
            c = a + off;
            d = c + k * (b - a);
        }
        const SegmentSegmentResult r = segment_segment_closest_points(a, b, c, d);
        parallel += r.parallel;
        double ref = std::numeric_limits<double>::infinity();
        for (int i = 0; i <= 2000; ++i) {
            const Vec3 p = a + (i / 2000.0) * (b - a);
            ref = std::min(ref, std::sqrt(point_segment_closest_point(p, c, d).distance_squared));
        }
        const double dist = std::sqrt(r.distance_squared);
        ASSERT_TRUE(std::isfinite(dist));
        EXPECT_LE(dist, ref + 1e-12);
        EXPECT_GE(dist, ref - 2e-3);
        EXPECT_GE(r.s, 0.0);
        EXPECT_LE(r.s, 1.0);
        EXPECT_GE(r.t, 0.0);
        EXPECT_LE(r.t, 1.0);
    }
    EXPECT_GE(parallel, 90);
}

TEST(SegmentSegment, DegenerateSegments) {
    const Vec3 p(0, 0, 0), q(1, 1, 0);
    auto r = segment_segment_closest_points(p, p, q, q);
    EXPECT_DOUBLE_EQ(r.distance_squared, 2.0);
    r = segment_segment_closest_points(p, p, Vec3(-1, 1, 0), Vec3(1, 1, 0));
    EXPECT_DOUBLE_EQ(r.distance_squared, 1.0);
    EXPECT_DOUBLE_EQ(r.t, 0.5);
    r = segment_segment_closest_points(Vec3(-1, 1, 0), Vec3(1, 1, 0), p, p);
    EXPECT_DOUBLE_EQ(r.s, 0.5);
}

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

TEST(PointTetrahedron, SignedDistanceMatchesFaceSampling) {
    std::mt19937 g(31);
    int inside = 0, outside = 0;
    for (int s = 0; s < 300; ++s) {
        const Vec3 v[4] = {rand_vec(g, 1), rand_vec(g, 1), rand_vec(g, 1), rand_vec(g, 1)};
        const Vec3 p = rand_vec(g, 0.8);
        const auto r = point_tetrahedron_signed_distance(p, v[0], v[1], v[2], v[3]);
        const int f[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
        double brute = std::numeric_limits<double>::infinity();
        for (const auto& fk : f) brute = std::min(brute, brute_point_triangle(p, v[fk[0]], v[fk[1]], v[fk[2]], 120));
        EXPECT_LE(std::abs(r.signed_distance), brute + 1e-12);
        EXPECT_GE(std::abs(r.signed_distance), brute - 2e-2);
        EXPECT_NEAR((p - (r.closest + r.signed_distance * r.normal)).norm(), 0.0, 1e-10);
        (r.inside ? inside : outside)++;
    }
    EXPECT_GE(inside, 10);
    EXPECT_GE(outside, 100);
}

TEST(SegmentTriangle, CrossingAndMiss) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    auto x = segment_triangle_crossing(a, b, c, Vec3(0.2, 0.3, 1), Vec3(0.2, 0.3, -1));
    ASSERT_TRUE(x.has_value());
    EXPECT_NEAR((x->point - Vec3(0.2, 0.3, 0)).norm(), 0.0, 1e-15);
    EXPECT_DOUBLE_EQ(x->w, 0.5);
    EXPECT_FALSE(segment_triangle_crossing(a, b, c, Vec3(0.2, 0.3, 1), Vec3(0.2, 0.3, 0.1)).has_value());
    EXPECT_FALSE(segment_triangle_crossing(a, b, c, Vec3(0, 0, 1), Vec3(1, 0, 1)).has_value());  // parallel
}

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
