// Regions of interest of SOFA's BoxROI (regions.hpp): the closed axis-aligned box and the points
// inside any of several boxes.
#include "penalty/mechanics/regions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace penalty {
namespace {

TEST(AlignedBox, PointsOnTheFacesAreInsideAndCornersAreOrdered) {
    const AlignedBox box = AlignedBox::from_corners(Vec3(1, 1, 1), Vec3(0, 0, 0));
    EXPECT_EQ(box.min, Vec3(0, 0, 0));
    EXPECT_EQ(box.max, Vec3(1, 1, 1));
    const std::vector<Vec3> points{Vec3(0, 0, 0), Vec3(1, 1, 1.0000001), Vec3(0.5, 1, 0.5), Vec3(3, 3, 3),
                                   Vec3(-1, 0, 0)};
    const std::vector<AlignedBox> boxes{box, AlignedBox::from_corners(Vec3(2.5, 2.5, 2.5), Vec3(3, 3, 3))};
    EXPECT_EQ(points_in_boxes(points, boxes), (std::vector<PointId>{0, 2, 3}));
}

TEST(AlignedBox, EachAxisIsOrderedOnItsOwn) {
    // SOFA's six numbers with x in order, y swapped and z swapped: each pair is sorted apart
    const AlignedBox box = AlignedBox::from_corners(Vec3(-1, 5, 0.5), Vec3(2, -3, -0.5));
    EXPECT_EQ(box.min, Vec3(-1, -3, -0.5));
    EXPECT_EQ(box.max, Vec3(2, 5, 0.5));
    // each of the six faces, on it and a step of one ulp beyond
    for (int k = 0; k < 3; ++k) {
        Vec3 on_min = Vec3(0.5, 1, 0);
        Vec3 on_max = on_min;
        on_min[k] = box.min[k];
        on_max[k] = box.max[k];
        EXPECT_TRUE(box.contains(on_min)) << k;
        EXPECT_TRUE(box.contains(on_max)) << k;
        Vec3 below = on_min;
        Vec3 above = on_max;
        below[k] = std::nextafter(box.min[k], -10.0);
        above[k] = std::nextafter(box.max[k], 10.0);
        EXPECT_FALSE(box.contains(below)) << k;
        EXPECT_FALSE(box.contains(above)) << k;
    }
}

TEST(AlignedBox, AFlatBoxHoldsTheOnePlaneItSpans) {
    // zmin = zmax: the points of the square on z = 0.25 exactly
    const AlignedBox plane = AlignedBox::from_corners(Vec3(0, 0, 0.25), Vec3(1, 1, 0.25));
    EXPECT_TRUE(plane.contains(Vec3(0.5, 0.5, 0.25)));
    EXPECT_FALSE(plane.contains(Vec3(0.5, 0.5, std::nextafter(0.25, 1.0))));
    EXPECT_FALSE(plane.contains(Vec3(0.5, 0.5, std::nextafter(0.25, 0.0))));
}

TEST(PointsInBoxes, TheUnionOfTheBoxesInIncreasingIndexOrderEachPointOnce) {
    // a row of 10 points x = 0, 0.1, …, 0.9; boxes [0.55, 0.85] listed before [0, 0.25] and a
    // box [0.15, 0.65] overlapping both: every point of the union, once, in index order
    std::vector<Vec3> row;
    for (int i = 0; i < 10; ++i) row.emplace_back(0.1 * i, 0, 0);
    const std::vector<AlignedBox> boxes{AlignedBox::from_corners(Vec3(0.55, -1, -1), Vec3(0.85, 1, 1)),
                                        AlignedBox::from_corners(Vec3(0, -1, -1), Vec3(0.25, 1, 1)),
                                        AlignedBox::from_corners(Vec3(0.15, -1, -1), Vec3(0.65, 1, 1))};
    EXPECT_EQ(points_in_boxes(row, boxes), (std::vector<PointId>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
    // the first two boxes alone leave the gap 0.3 … 0.5
    EXPECT_EQ(points_in_boxes(row, std::span(boxes).first(2)), (std::vector<PointId>{0, 1, 2, 6, 7, 8}));
    // no box, no point; no point, nothing
    EXPECT_TRUE(points_in_boxes(row, {}).empty());
    EXPECT_TRUE(points_in_boxes({}, boxes).empty());
}

TEST(AlignedBox, ANotANumberCoordinatePassesItsAxisAsInSofa) {
    // BoxROI::isPointInAlignedBox rejects on p < min or p > max: both are false for NaN, so a NaN
    // coordinate passes the test of its axis; the point is inside when the other axes are
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const AlignedBox box = AlignedBox::from_corners(Vec3(0, 0, 0), Vec3(1, 1, 1));
    EXPECT_TRUE(box.contains(Vec3(nan, 0.5, 0.5)));
    EXPECT_FALSE(box.contains(Vec3(nan, 2, 0.5)));
}

}  // namespace
}  // namespace penalty
