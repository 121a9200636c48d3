// The path of a cut over a triangle surface (triangle_path.cpp, SOFA's TriangleSetGeometryAlgorithms::
// computeIntersectedObjectsList, compute3PointsBarycoefs; TopologicalChangeProcessor::
// findElementIndex) on the project-made grid of 3 x 2 unit squares: the triangle holding a point
// and its barycentric coordinates, the crossed edges between two triangles, and the connected
// components a cut changes.
#include "incision_grid.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

using test_incision::grid_point;
using test_incision::IncisionGrid;

TEST(TriangleIncision, FindsTheTriangleHoldingAPointAndItsBarycentricCoordinates) {
    IncisionGrid g;
    TriangleIncision incision(*g.container, g.state.position);
    // centroid of triangle 0 (0,0)-(1,0)-(1,1)
    const Vec3 p(2.0 / 3.0, 1.0 / 3.0, 0.0);
    EXPECT_EQ(incision.find_triangle(p), 0);
    const auto c = incision.barycentric(0, p);
    EXPECT_NEAR(c[0], 1.0 / 3.0, 1e-15);
    EXPECT_NEAR(c[1], 1.0 / 3.0, 1e-15);
    EXPECT_NEAR(c[2], 1.0 / 3.0, 1e-15);
    EXPECT_EQ(incision.find_triangle(Vec3(2.5, 1.75, 0.0)), 11);  // above the diagonal of square (2, 1)
    EXPECT_EQ(incision.find_triangle(Vec3(3.5, 0.5, 0.0)), -1);   // outside the grid
}

// From the centroid of triangle 0 to the centroid of triangle 2 along y = 1/3: the edge x = 1
// (points 1-5) and the diagonal of square (1, 0) (points 1-6) are crossed at 1/3 from point 1.
TEST(TriangleIncision, PathThroughThreeTrianglesIsTheCrossedEdgesBetweenTheEndTriangles) {
    IncisionGrid g;
    TriangleIncision incision(*g.container, g.state.position);
    const Vec3 a(2.0 / 3.0, 1.0 / 3.0, 0.0), b(5.0 / 3.0, 1.0 / 3.0, 0.0);
    ElementId ta = 0, tb = 2;
    std::vector<IncisionPathElement> path;
    ASSERT_TRUE(incision.intersected_objects(-1, a, b, ta, tb, path));
    ASSERT_EQ(path.size(), 4U);
    EXPECT_EQ(path[0].type, ElementType::triangle);
    EXPECT_EQ(path[0].index, 0);
    const MeshTopology& m = g.mesh;
    EXPECT_EQ(path[1].type, ElementType::edge);
    EXPECT_EQ(path[1].index, m.edge_index(grid_point(1, 0), grid_point(1, 1)));
    EXPECT_EQ(path[2].type, ElementType::edge);
    EXPECT_EQ(path[2].index, m.edge_index(grid_point(1, 0), grid_point(2, 1)));
    for (int k = 1; k <= 2; ++k) {
        const Edge& e = m.edges()[std::size_t(path[std::size_t(k)].index)];
        const double from_point_1 =
            e[0] == grid_point(1, 0) ? path[std::size_t(k)].coefs[0] : 1 - path[std::size_t(k)].coefs[0];
        EXPECT_NEAR(from_point_1, 1.0 / 3.0, 1e-15) << k;
    }
    EXPECT_EQ(path[3].type, ElementType::triangle);
    EXPECT_EQ(path[3].index, 2);
    // a segment inside one triangle, and one leaving the grid, are no path (SOFA's refusals)
    ElementId t0 = 0, t0b = 0;
    std::vector<IncisionPathElement> none;
    EXPECT_FALSE(incision.intersected_objects(-1, a, Vec3(0.8, 0.3, 0.0), t0, t0b, none));
}

TEST(TrianglePath, BarycentricCoordinatesAreExactAndAFlatTrianglesAreAThirdEach) {
    // compute3PointsBarycoefs on (0,0,0), (4,0,0), (0,2,0): (1, 0.5) is 1/2 of a, 1/4 of b and c
    const auto c = TriangleIncision::barycentric_of(Vec3(1, 0.5, 0), Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 2, 0));
    EXPECT_NEAR(c[0], 0.5, 1e-15);
    EXPECT_NEAR(c[1], 0.25, 1e-15);
    EXPECT_NEAR(c[2], 0.25, 1e-15);
    // a point off the plane: the coordinates of its projection
    const auto off = TriangleIncision::barycentric_of(Vec3(1, 0.5, 7), Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 2, 0));
    EXPECT_NEAR(off[1], 0.25, 1e-15);
    // three points on a line: no area, 1/3 each
    const auto flat = TriangleIncision::barycentric_of(Vec3(1, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0));
    for (const double w : flat) EXPECT_NEAR(w, 1.0 / 3.0, 1e-15);
}

TEST(TrianglePath, APointOnASharedEdgeIsInTheFirstTriangleOrTheHintedOne) {
    IncisionGrid g;
    TriangleIncision incision(*g.container, g.state.position);
    // (0.5, 0.5) lies on the diagonal of square (0, 0), shared by triangles 0 and 1: the first
    // in index order, or the previous triangle when it holds the point (findElementIndex)
    EXPECT_EQ(incision.find_triangle(Vec3(0.5, 0.5, 0)), 0);
    EXPECT_EQ(incision.find_triangle(Vec3(0.5, 0.5, 0), 1), 1);
    EXPECT_EQ(incision.find_triangle(Vec3(0.5, 0.5, 0), 7), 0);  // a hint that does not hold it
    // the grid's corners and a point just off its side
    EXPECT_EQ(incision.find_triangle(Vec3(3, 2, 0)), 10);
    EXPECT_EQ(incision.find_triangle(Vec3(3, 2.001, 0)), -1);
}

TEST(TrianglePath, ConnectedComponentsShareAVertex) {
    // two triangles sharing only a vertex are one component; a separate one is a second; a
    // point no triangle uses is none
    EXPECT_EQ(count_connected_components({{0, 1, 2}, {2, 3, 4}}, 5), 1U);
    EXPECT_EQ(count_connected_components({{0, 1, 2}, {3, 4, 5}}, 6), 2U);
    EXPECT_EQ(count_connected_components({{0, 1, 2}, {3, 4, 5}}, 7), 2U);
    EXPECT_EQ(count_connected_components({}, 0), 0U);
    IncisionGrid g;
    EXPECT_EQ(count_connected_components(g.mesh.triangles(), 12), 1U);
}

}  // namespace
}  // namespace penalty
