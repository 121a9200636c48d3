// PointSegment: closest point on a segment against dense sampling, and a zero-length segment.
#include "penalty/geometry/point_segment.hpp"
#include "sampling_references.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>

namespace penalty {
namespace {

using namespace test_geometry;

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

}  // namespace
}  // namespace penalty
