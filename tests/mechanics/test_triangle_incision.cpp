// Incision along a path (SOFA's TriangleSetGeometryAlgorithms::computeIntersectedObjectsList,
// SplitAlongPath, InciseAlongEdgeList) on a project-made grid of 3 x 2 unit squares, two
// triangles each (12 points, 12 triangles), against hand-derived paths, points and triangles.
#include "penalty/mechanics/state_topology.hpp"
#include "penalty/mechanics/triangle_incision.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace penalty {
namespace {

/// Point (i, j) of the grid: index 4 j + i, at (i, j, 0).
constexpr PointId grid_point(int i, int j) { return PointId(4 * j + i); }

/// The grid, its container and a state following it.
struct IncisionGrid {
    MeshTopology mesh;
    Vec3Object state{"grid"};
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<StateTopologyFollower<Vec3Types>> follower;
    IncisionGrid() {
        std::vector<Triangle> triangles;
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                const PointId a = grid_point(i, j), b = grid_point(i + 1, j), c = grid_point(i + 1, j + 1),
                              d = grid_point(i, j + 1);
                triangles.push_back({a, b, c});  // below the diagonal a-c
                triangles.push_back({a, c, d});  // above it
            }
        mesh.set_num_points(12);
        mesh.set_triangles(triangles);
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i) state.position.emplace_back(double(i), double(j), 0.0);
        state.rest_position = state.position;
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "grid");
        follower = std::make_unique<StateTopologyFollower<Vec3Types>>(state);
        container->add_state_follower(*follower);
    }
    /// The triangles as vertex sets.
    [[nodiscard]] std::set<std::set<PointId>> triangle_sets() const {
        std::set<std::set<PointId>> out;
        for (const Triangle& t : mesh.triangles()) out.insert({t[0], t[1], t[2]});
        return out;
    }
    [[nodiscard]] double signed_area_sum() const {
        double sum = 0;
        for (const Triangle& t : mesh.triangles()) {
            const Vec3 &a = state.position[std::size_t(t[0])], &b = state.position[std::size_t(t[1])],
                       &c = state.position[std::size_t(t[2])];
            sum += 0.5 * (b - a).cross(c - a)[2];
        }
        return sum;
    }
};

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

// A cut across the grid along x = 1.15, from (1.15, 0.05) to (1.15, 1.95). Its ends lie within
// 0.25 of the diagonal of square (1, 0) and of the edge x = 1 of square (1, 1), inner edges, and
// within 0.25 of the vertices (1, 0) and (1, 2) (barycentric 0.85 and 0.8): SnapBorderPath moves
// the ends onto these border vertices, and drops the crossing of the diagonal next to (1, 0).
// (Within 0.25 of a border edge too, but SOFA's projection onto a border edge never meets it:
// computePointProjectionOnEdge draws its line away from the edge.) The path: vertex 1, the edge
// (1,1)-(2,1) at x = 1.15, the diagonal (1,1)-(2,2) at (1.15, 1.15), vertex 9; 2 new points, 3
// triangles split into 2 + 3 + 2; both chain ends on the border: all 4 chain points duplicated,
// and the left column falls off.
TEST(TriangleIncision, CutFromBorderToBorderSeparatesTheGrid) {
    IncisionGrid g;
    IncisionLine line;
    line.points = {Vec3(1.15, 0.05, 0.0), Vec3(1.15, 1.95, 0.0)};
    EXPECT_EQ(count_connected_components(g.mesh.triangles(), 12), 1U);
    const IncisionOutcome outcome = incise_line(*g.container, g.state.position, line, 0.1, 0.25);
    EXPECT_EQ(outcome.segments_cut, 1U);
    EXPECT_EQ(outcome.refused_segment, -1);
    ASSERT_EQ(g.container->num_points(), 18U);
    const auto& x = g.state.position;
    EXPECT_NEAR((x[12] - Vec3(1.15, 1.0, 0.0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((x[13] - Vec3(1.15, 1.15, 0.0)).norm(), 0.0, 1e-15);
    // the copies of the chain 1, 12, 13, 9
    EXPECT_EQ(x[14], x[std::size_t(grid_point(1, 0))]);
    EXPECT_EQ(x[15], x[12]);
    EXPECT_EQ(x[16], x[13]);
    EXPECT_EQ(x[17], x[std::size_t(grid_point(1, 2))]);
    EXPECT_EQ(g.mesh.triangles().size(), 16U);  // 12 - 3 + 7
    EXPECT_EQ(count_connected_components(g.mesh.triangles(), g.container->num_points()), 2U);
    EXPECT_NEAR(g.signed_area_sum(), 6.0, 1e-14);
}

TEST(TriangleIncision, BadLinesAreRefusedBeforeAnythingChanges) {
    IncisionGrid g;
    IncisionLine outside;
    outside.points = {Vec3(0.5, 0.2, 0.0), Vec3(3.5, 0.5, 0.0)};
    EXPECT_THROW((void)incise_line(*g.container, g.state.position, outside, 0.1, 0.25), std::invalid_argument);
    IncisionLine bad_index;
    bad_index.points = {Vec3(0.5, 0.2, 0.0), Vec3(1.5, 0.2, 0.0)};
    bad_index.triangles = {0, 12};
    EXPECT_THROW((void)incise_line(*g.container, g.state.position, bad_index, 0.1, 0.25), std::invalid_argument);
    EXPECT_EQ(g.container->num_points(), 12U);
    EXPECT_EQ(g.mesh.triangles().size(), 12U);
    // a segment that stays in one triangle: refused (SOFA's "Invalid path"), nothing cut
    IncisionLine inside;
    inside.points = {Vec3(0.6, 0.2, 0.0), Vec3(0.8, 0.3, 0.0)};
    const IncisionOutcome o = incise_line(*g.container, g.state.position, inside, 0.1, 0.25);
    EXPECT_EQ(o.refused_segment, 1);
    EXPECT_EQ(o.segments_cut, 0U);
    EXPECT_EQ(g.container->num_points(), 12U);
}

}  // namespace
}  // namespace penalty
