// PlaneROI and SphereROI shapes and the element selection every ROI shares, on grids made here.
#include "penalty/mechanics/regions_of_interest.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

/// A 3×3×3 grid of points (0, 0.5, 1 in each axis), index i + 3j + 9k.
std::vector<Vec3> grid() {
    std::vector<Vec3> p;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) p.emplace_back(0.5 * i, 0.5 * j, 0.5 * k);
    return p;
}

TEST(PlaneRegion, ABoxOnThreeCornersWithADepthCentredOnThem) {
    // corners (0,0,0) → (1,0,0) → (1,1,0), depth 0.2: the box [0,1]×[0,1]×[−0.1,0.1]
    const PlaneRegion plane(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), 0.2);
    EXPECT_TRUE(plane.contains(Vec3(0.5, 0.5, 0.0)));
    EXPECT_TRUE(plane.contains(Vec3(1, 1, 0.1)));  // faces included
    EXPECT_TRUE(plane.contains(Vec3(0, 0, -0.1)));
    EXPECT_FALSE(plane.contains(Vec3(0.5, 0.5, 0.11)));
    EXPECT_FALSE(plane.contains(Vec3(1.01, 0.5, 0)));
    EXPECT_FALSE(plane.contains(Vec3(0.5, -0.01, 0)));
    const std::vector<Vec3> points = grid();
    const RoiSelection s = select_in_region(
        points, {}, [&](const Vec3& p) { return plane.contains(p); }, ElementTest::all_points);
    EXPECT_EQ(s.points, (std::vector<PointId>{0, 1, 2, 3, 4, 5, 6, 7, 8}));  // the layer z = 0
}

TEST(PlaneRegion, AnObliqueBoxAndTheDegenerateDefault) {
    // SOFA's PlaneROI.scn fixing plane: corners (0.3,0,0) → (0,0,0) → (0,0.3,0), depth 0. With
    // no depth the side normals (p1−p0)×(p4−p0) vanish (p4 = p0), so the sides test nothing:
    // every point of the plane z = 0 is inside, also far outside the square [0,0.3]² (as SOFA)
    const PlaneRegion fixing(Vec3(0.3, 0, 0), Vec3(0, 0, 0), Vec3(0, 0.3, 0), 0.0);
    EXPECT_TRUE(fixing.contains(Vec3(0.1, 0.2, 0)));
    EXPECT_TRUE(fixing.contains(Vec3(-5, 7, 0)));
    EXPECT_FALSE(fixing.contains(Vec3(0.1, 0.2, 1e-9)));
    // an oblique box: corners (0,0,0) → (1,1,0) → (1,1,1), depth 0.2 (normal (1,−1,0)/√2)
    const PlaneRegion oblique(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1), 0.2);
    EXPECT_TRUE(oblique.contains(Vec3(0.5, 0.5, 0.5)));
    EXPECT_TRUE(oblique.contains(Vec3(0.55, 0.45, 0.5)));  // 0.1/√2 ≈ 0.07 off the plane
    EXPECT_FALSE(oblique.contains(Vec3(0.6, 0.4, 0.5)));   // 0.2/√2 ≈ 0.14 off
    EXPECT_FALSE(oblique.contains(Vec3(0.5, 0.5, 1.2)));
    // ten zeros (SOFA's default): every test is |0| ≤ 0, every point is inside
    const PlaneRegion zero(Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 0.0);
    EXPECT_TRUE(zero.contains(Vec3(3, -4, 5)));
}

TEST(SphereRegion, ClosedBall) {
    const SphereRegion ball{Vec3(0, 0, 1), 0.5};
    EXPECT_TRUE(ball.contains(Vec3(0, 0.5, 1)));
    EXPECT_FALSE(ball.contains(Vec3(0, 0.5, 1.01)));
    const std::vector<Vec3> points = grid();
    const RoiSelection s = select_in_region(
        points, {}, [&](const Vec3& p) { return ball.contains(p); }, ElementTest::all_points);
    // z = 0.5 at (0,0): 9 + 0 = 9 (distance 0.5); z = 1: (0,0), (0.5,0), (0,0.5) → 18, 19, 21
    EXPECT_EQ(s.points, (std::vector<PointId>{9, 18, 19, 21}));
}

TEST(RegionSelection, StrictElementsNeedEveryPointInsideElseTheCentre) {
    const std::vector<Vec3> points = grid();
    RoiElements e;
    // bottom layer z = 0 split in triangles, plus one triangle reaching z = 0.5
    e.triangles = {{0, 1, 4}, {0, 4, 3}, {4, 5, 8}, {0, 1, 9}};
    e.edges = {{0, 1}, {1, 10}, {7, 8}};
    e.tetrahedra = {{0, 1, 3, 9}, {0, 1, 3, 4}};
    // the region x ≤ 0.6, z ≤ 0.1
    const auto inside = [](const Vec3& p) { return p.x() <= 0.6 && p.z() <= 0.1; };
    const RoiSelection strict = select_in_region(points, e, inside, ElementTest::all_points);
    EXPECT_EQ(strict.triangles, (std::vector<PointId>{0, 1}));
    EXPECT_EQ(strict.edges, (std::vector<PointId>{0}));
    EXPECT_EQ(strict.tetrahedra, (std::vector<PointId>{1}));
    // centres: triangle 2 (x̄ = 0.83) out, triangle 3 (z̄ = 0.17) out; edge 1 (z̄ = 0.25) out;
    // edge 2 (x̄ = 0.75) out
    const RoiSelection centre = select_in_region(points, e, inside, ElementTest::center);
    EXPECT_EQ(centre.triangles, (std::vector<PointId>{0, 1}));
    EXPECT_EQ(centre.edges, (std::vector<PointId>{0}));
    // a wider region in x: the centre test takes triangle 2 (x̄ ≈ 0.83) but not strictly
    const auto wider = [](const Vec3& p) { return p.x() <= 0.9 && p.z() <= 0.1; };
    EXPECT_EQ(select_in_region(points, e, wider, ElementTest::center).triangles, (std::vector<PointId>{0, 1, 2}));
    EXPECT_EQ(select_in_region(points, e, wider, ElementTest::all_points).triangles, (std::vector<PointId>{0, 1}));
    // an element using a point past the list is never inside
    RoiElements bad;
    bad.triangles = {{0, 1, 99}};
    EXPECT_TRUE(select_in_region(points, bad, inside, ElementTest::center).triangles.empty());
}

TEST(RegionSelection, SphereRoiAngleFilters) {
    // an edge along x and one along y; direction x, 30°: keeps |e·x| < cos 30°, i.e. the y edge
    const Vec3 x(1, 0, 0);
    EXPECT_FALSE(edge_passes_angle(Vec3(0, 0, 0), Vec3(2, 0, 0), x, 30.0));
    EXPECT_TRUE(edge_passes_angle(Vec3(0, 0, 0), Vec3(0, 2, 0), x, 30.0));
    // a triangle (0,0,0) (1,0,0) (0,1,0): n = (c−a)×(b−a) = −z; keeps n·N < cos 30°
    EXPECT_TRUE(triangle_passes_angle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), 30.0));
    EXPECT_FALSE(triangle_passes_angle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1), 30.0));
}

}  // namespace
}  // namespace penalty
