// The selection engines' computations (mechanics/selection_engines.cpp): MeshROI's region, ProximityROI,
// ValuesFromPositions; closed forms on point sets made here.
#include "penalty/mechanics/regions_of_interest.hpp"
#include "penalty/mechanics/selection_engines.hpp"
#include "penalty/mechanics/transform_engines.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

namespace penalty {
namespace {

/// The closed unit cube [0,1]³ as 12 outward triangles.
std::pair<std::vector<Vec3>, std::vector<Triangle>> unit_cube() {
    std::vector<Vec3> p;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) p.emplace_back(i, j, k);
    const std::vector<Triangle> t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                     {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return {p, t};
}

TEST(MeshRegion, InsideAClosedCube) {
    auto [points, triangles] = unit_cube();
    const MeshRegion region(points, triangles, true);
    EXPECT_EQ(region.box(), (std::array<double, 6>{0, 0, 0, 1, 1, 1}));
    EXPECT_TRUE(region.contains(Vec3(0.4, 0.55, 0.6)));
    EXPECT_TRUE(region.contains(Vec3(0.1, 0.8, 0.3)));
    // as SOFA: a ray through a vertex or a face's diagonal is counted once per triangle there, so
    // the cube's centre (whose ray leaves through the corner (1, 1, 1), a vertex of 6 triangles) is
    // not inside
    EXPECT_FALSE(region.contains(Vec3(0.5, 0.5, 0.5)));
    EXPECT_TRUE(region.contains(Vec3(0.9, 0.2, 0.7)));
    EXPECT_FALSE(region.contains(Vec3(1.5, 0.5, 0.5)));  // outside the box
    EXPECT_FALSE(region.contains(Vec3(0.5, -0.01, 0.5)));
    // a seeded sample: the parity test agrees with the box for a convex mesh, and hits both sides
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.5, 1.5);
    int inside = 0, samples = 2000;
    for (int s = 0; s < samples; ++s) {
        const Vec3 p(u(rng), u(rng), u(rng));
        const bool in_cube = p.minCoeff() > 1e-9 && p.maxCoeff() < 1 - 1e-9;
        const bool out_cube = p.minCoeff() < -1e-9 || p.maxCoeff() > 1 + 1e-9;
        if (in_cube) {
            EXPECT_TRUE(region.contains(p)) << p.transpose();
        }
        if (out_cube) {
            EXPECT_FALSE(region.contains(p)) << p.transpose();
        }
        inside += region.contains(p) ? 1 : 0;
    }
    EXPECT_GT(inside, samples / 16);  // (1/2)³ of the sampled volume is the cube
    EXPECT_LT(inside, samples / 4);
    // without the mesh (computeMeshROI 0) every point is inside
    EXPECT_TRUE(MeshRegion(points, triangles, false).contains(Vec3(5, 5, 5)));
    EXPECT_THROW(MeshRegion(points, {{0, 1, 8}}, true), std::invalid_argument);
    // MeshROI's non-strict elements: all points inside, or else the centre
    const std::vector<Vec3> tested = {Vec3(0.4, 0.55, 0.6), Vec3(1.2, 0.47, 0.61), Vec3(-0.1, 0.53, 0.38),
                                      Vec3(3, 3, 3)};
    RoiElements elements;
    elements.edges = {{0, 1}, {1, 2}, {1, 3}};
    const RoiSelection s = select_in_region(
        tested, elements, [&](const Vec3& p) { return region.contains(p); }, ElementTest::all_points_or_center);
    EXPECT_EQ(s.points, (std::vector<PointId>{0}));
    EXPECT_EQ(s.edges, (std::vector<PointId>{0, 1}));  // their centres (0.8, ..), (0.55, ..) are inside
}

TEST(ProximityRoi, TheNearestPointsWithinTheBalls) {
    std::vector<Vec3> points;
    for (int i = 0; i < 10; ++i) points.emplace_back(0.1 * i, 0, 0);
    // one ball at x = 0.42 of radius 0.25: points 2..6 (distances .22 .12 .02 .08 .18); the 3 nearest
    const ProximitySelection s = proximity_roi(points, std::vector<Vec3>{Vec3(0.42, 0, 0)}, {0.25}, 3);
    std::vector<PointId> sorted = s.indices;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, (std::vector<PointId>{3, 4, 5}));
    EXPECT_EQ(s.points.size(), 3u);
    for (std::size_t k = 0; k < s.indices.size(); ++k)
        EXPECT_DOUBLE_EQ(s.distances[k], std::abs(points[std::size_t(s.indices[k])][0] - 0.42));
    EXPECT_EQ(s.indices_out.size(), 7u);
    // no radius, or N = 0: SOFA's initial indices {0}
    EXPECT_EQ(proximity_roi(points, std::vector<Vec3>{Vec3::Zero()}, {}, 3).indices, (std::vector<PointId>{0}));
    EXPECT_EQ(proximity_roi(points, std::vector<Vec3>{Vec3::Zero()}, {1.0}, 0).indices, (std::vector<PointId>{0}));
    // a missing radius repeats the last one
    const ProximitySelection two = proximity_roi(points, std::vector<Vec3>{Vec3(0, 0, 0), Vec3(0.9, 0, 0)}, {0.05}, 10);
    std::vector<PointId> both = two.indices;
    std::sort(both.begin(), both.end());
    EXPECT_EQ(both, (std::vector<PointId>{0, 9}));
}

TEST(ValuesFromPositions, InterpolationAlongTheDirection) {
    const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(10, 0, 0), Vec3(2.5, 7, 0)};
    const std::vector<Edge> edges = {{0, 2}};
    const std::vector<double> values = {0, 10, 40};
    const ValuesFromPositionsResult r =
        values_from_positions(points, edges, {}, {}, Vec3(1, 0, 0), values, 0.0, 10.0, false);
    EXPECT_EQ(r.point_values, (std::vector<double>{0, 10, 40, 5}));
    EXPECT_EQ(r.edge_values, (std::vector<double>{10}));  // the edge's centre x = 5
    const ValuesFromPositionsResult v =
        values_from_positions(points, edges, {}, {}, Vec3(0, 1, 0), values, 0.0, 10.0, true);
    EXPECT_EQ(v.point_vectors.size(), 4u);
    EXPECT_EQ(v.edge_vectors[0], Vec3(0, 1, 0));
    EXPECT_THROW((void)values_from_positions(points, {{0, 9}}, {}, {}, Vec3(1, 0, 0), values, 0, 10, false),
                 std::invalid_argument);
}

}  // namespace
}  // namespace penalty
