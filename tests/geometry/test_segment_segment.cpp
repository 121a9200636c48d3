// SegmentSegment: closest points of two segments against a reference, parallel and degenerate segments.
#include "penalty/geometry/point_segment.hpp"
#include "penalty/geometry/segment_segment.hpp"
#include "sampling_references.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace penalty {
namespace {

using namespace test_geometry;

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

}  // namespace
}  // namespace penalty
