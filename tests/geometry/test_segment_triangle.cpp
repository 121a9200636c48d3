// SegmentTriangle: a crossing segment and a miss.
#include "penalty/geometry/segment_triangle.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

TEST(SegmentTriangle, CrossingAndMiss) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    auto x = segment_triangle_crossing(a, b, c, Vec3(0.2, 0.3, 1), Vec3(0.2, 0.3, -1));
    ASSERT_TRUE(x.has_value());
    EXPECT_NEAR((x->point - Vec3(0.2, 0.3, 0)).norm(), 0.0, 1e-15);
    EXPECT_DOUBLE_EQ(x->w, 0.5);
    EXPECT_FALSE(segment_triangle_crossing(a, b, c, Vec3(0.2, 0.3, 1), Vec3(0.2, 0.3, 0.1)).has_value());
    EXPECT_FALSE(segment_triangle_crossing(a, b, c, Vec3(0, 0, 1), Vec3(1, 0, 1)).has_value());  // parallel
}

}  // namespace
}  // namespace penalty
