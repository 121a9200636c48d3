// The cut along a path (triangle_incision.cpp, SOFA's TriangleSetGeometryAlgorithms::
// SplitAlongPath, InciseAlongEdgeList) on a project-made grid of 3 x 2 unit squares, two
// triangles each (12 points, 12 triangles), against hand-derived points and triangles (the path:
// test_triangle_path.cpp; its snapping: test_triangle_snapping.cpp; INCISE= lines:
// test_incision_line.cpp).
#include "incision_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace penalty {
namespace {

using test_incision::grid_point;
using test_incision::IncisionGrid;

// SplitAlongPath on that path: 4 new points (the two end triangles' points and the two edge
// crossings), triangles 0, 3, 2 replaced by 4 + 3 + 4 triangles; then InciseAlongEdgeList
// duplicates the two inner points of the chain 12-13-14-15.
TEST(TriangleIncision, SplitCreatesThePathPointsAndTrianglesThenInciseDuplicatesTheInnerPoints) {
    IncisionGrid g;
    TriangleIncision incision(*g.container, g.state.position);
    Vec3 a(2.0 / 3.0, 1.0 / 3.0, 0.0), b(5.0 / 3.0, 1.0 / 3.0, 0.0);
    ElementId ta = 0, tb = 2;
    std::vector<IncisionPathElement> path;
    ASSERT_TRUE(incision.intersected_objects(-1, a, b, ta, tb, path));
    const auto before = g.triangle_sets();
    std::vector<ElementId> new_edges;
    EXPECT_EQ(incision.split_along_path(-1, a, -1, b, path, new_edges, 0.1, 0.25), 4);
    ASSERT_EQ(g.container->num_points(), 16U);
    // positions: the barycentric points of their ancestors
    const auto& x = g.state.position;
    EXPECT_NEAR((x[12] - Vec3(2.0 / 3.0, 1.0 / 3.0, 0)).norm(), 0.0, 1e-15);
    EXPECT_EQ(x[13], Vec3(1.0, 1.0 / 3.0, 0.0));
    EXPECT_NEAR((x[14] - Vec3(4.0 / 3.0, 1.0 / 3.0, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((x[15] - Vec3(5.0 / 3.0, 1.0 / 3.0, 0)).norm(), 0.0, 1e-15);
    EXPECT_EQ(g.state.rest_position[13], x[13]);
    // triangles: 12 - 3 + 11
    ASSERT_EQ(g.mesh.triangles().size(), 20U);
    const auto after = g.triangle_sets();
    const PointId p0 = grid_point(0, 0), p1 = grid_point(1, 0), p2 = grid_point(2, 0), p5 = grid_point(1, 1),
                  p6 = grid_point(2, 1);
    for (const std::set<PointId>& gone : {std::set<PointId>{p0, p1, p5}, {p1, p6, p5}, {p1, p2, p6}})
        EXPECT_FALSE(after.contains(gone));
    // TRIANGLE then EDGE in triangle 0 = (p0, p1, p5), the edge p1-p5 opposite its vertex 0:
    // (12, p0, p1), (12, p5, p0), (12, p1, 13), (12, 13, p5)
    for (const std::set<PointId>& made : {std::set<PointId>{12, p0, p1}, {12, p5, p0}, {12, p1, 13}, {12, 13, p5}})
        EXPECT_TRUE(after.contains(made));
    // EDGE then TRIANGLE in triangle 2 = (p1, p2, p6), the edge p1-p6 opposite its vertex 1:
    // (15, p2, p6), (15, p1, p2), (15, p6, 14), (15, 14, p1)
    for (const std::set<PointId>& made : {std::set<PointId>{15, p2, p6}, {15, p1, p2}, {15, p6, 14}, {15, 14, p1}})
        EXPECT_TRUE(after.contains(made));
    // the corner triangle of triangle 3 = (p1, p6, p5) between its two crossings: (p1, 13, 14)
    EXPECT_TRUE(after.contains(std::set<PointId>{p1, 13, 14}));
    EXPECT_NEAR(g.signed_area_sum(), 6.0, 1e-14);  // the surface is unchanged, every triangle +z
    for (const Triangle& t : g.mesh.triangles())
        EXPECT_GT((x[std::size_t(t[1])] - x[std::size_t(t[0])]).cross(x[std::size_t(t[2])] - x[std::size_t(t[0])])[2],
                  0.0);
    (void)before;
    // the path's edges: 12-13, 13-14, 14-15
    ASSERT_EQ(new_edges.size(), 3U);
    const std::vector<Edge> expected{{12, 13}, {13, 14}, {14, 15}};
    for (std::size_t k = 0; k < 3; ++k) {
        Edge e = g.mesh.edges()[std::size_t(new_edges[k])];
        std::sort(e.begin(), e.end());
        EXPECT_EQ(e, expected[k]) << k;
    }
    std::vector<PointId> new_points, end_points;
    bool border = true;
    border = false;
    ASSERT_TRUE(incision.incise_along_edge_list(new_edges, new_points, end_points, border));
    EXPECT_FALSE(border);
    EXPECT_EQ(new_points, (std::vector<PointId>{16, 17}));
    EXPECT_EQ(end_points, (std::vector<PointId>{12, 15}));
    EXPECT_EQ(x[16], x[13]);
    EXPECT_EQ(x[17], x[14]);
    EXPECT_EQ(g.mesh.triangles().size(), 20U);
    // the cut's inner edges now border one triangle each side: 13-14 and 16-17 both exist
    EXPECT_GE(g.mesh.edge_index(13, 14), 0);
    EXPECT_GE(g.mesh.edge_index(16, 17), 0);
    EXPECT_EQ(g.mesh.triangles_around_edge()[std::size_t(g.mesh.edge_index(13, 14))].size(), 1U);
    EXPECT_EQ(g.mesh.triangles_around_edge()[std::size_t(g.mesh.edge_index(16, 17))].size(), 1U);
    EXPECT_EQ(count_connected_components(g.mesh.triangles(), g.container->num_points()), 1U);
    EXPECT_NEAR(g.signed_area_sum(), 6.0, 1e-14);
}

}  // namespace
}  // namespace penalty
