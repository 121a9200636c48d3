// One INCISE= line of SOFA's TopologicalChangeProcessor (incision_line.cpp: incise_line,
// save_incisions) on the project-made grid of 3 x 2 unit squares: a cut from border to border,
// a line of two segments continuing where the first ended, the refusals naming the point, the
// topology and the triangle, and the saved cuts of one time merged and moved off the previous
// cut's end (SOFA's 1e-5 "HACK").
#include "incision_grid.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace penalty {
namespace {

using test_incision::grid_point;
using test_incision::IncisionGrid;

/// The message of the std::invalid_argument `f` throws.
template <class F>
std::string incision_line_error(F&& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
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

TEST(IncisionLine, TheRefusalsNameThePointTheTriangleAndTheTopology) {
    IncisionGrid g;
    IncisionLine outside;
    outside.points = {Vec3(0.5, 0.25, 0.0), Vec3(3.5, 0.5, 0.0)};
    EXPECT_EQ(incision_line_error([&] { (void)incise_line(*g.container, g.state.position, outside, 0.1, 0.25); }),
              "point 2 (3.5 0.5 0) is in no triangle of the topology 'grid'");
    IncisionLine bad_index;
    bad_index.points = {Vec3(0.5, 0.25, 0.0), Vec3(1.5, 0.25, 0.0)};
    bad_index.triangles = {0, 12};
    EXPECT_EQ(incision_line_error([&] { (void)incise_line(*g.container, g.state.position, bad_index, 0.1, 0.25); }),
              "point 2 (1.5 0.25 0): triangle 12 does not exist (the topology 'grid' has 12)");
    MeshTopology wire_mesh;
    wire_mesh.set_edges({{0, 1}});
    TopologyContainer wire(wire_mesh, ElementType::edge, "wire");
    EXPECT_EQ(incision_line_error([&] { (void)incise_line(wire, g.state.position, outside, 0.1, 0.25); }),
              "an incision needs a triangle topology; 'wire' keeps edges");
    EXPECT_EQ(incision_line_error([&] {
                  (void)save_incisions(wire, g.state.position, {{1.0, outside}});
              }),
              "an incision needs a triangle topology; 'wire' keeps edges");
    EXPECT_EQ(g.container->num_points(), 12U);
}

TEST(IncisionLine, ASecondSegmentContinuesFromWhereTheFirstEnded) {
    // (0.5, 0.4) → (1.5, 0.4) → (2.5, 0.6), inside the grid: two segments, the second from the
    // first's last point; the surface keeps its area, one piece, every triangle facing +z
    IncisionGrid g;
    IncisionLine line;
    line.points = {Vec3(0.5, 0.4, 0.0), Vec3(1.5, 0.4, 0.0), Vec3(2.5, 0.6, 0.0)};
    const IncisionOutcome outcome = incise_line(*g.container, g.state.position, line, 0.0, 0.0);
    EXPECT_EQ(outcome.segments_cut, 2U);
    EXPECT_EQ(outcome.refused_segment, -1);
    EXPECT_GT(g.container->num_points(), 16U);
    EXPECT_NEAR(g.signed_area_sum(), 6.0, 1e-14);
    EXPECT_EQ(count_connected_components(g.mesh.triangles(), g.container->num_points()), 1U);
    const auto& x = g.state.position;
    for (const Triangle& t : g.mesh.triangles())
        EXPECT_GT((x[std::size_t(t[1])] - x[std::size_t(t[0])]).cross(x[std::size_t(t[2])] - x[std::size_t(t[0])])[2],
                  0.0);
    // the cut's ends are points of the mesh now
    int ends = 0;
    for (const Vec3& p : x) ends += (p - line.points[0]).norm() < 1e-12 || (p - line.points[2]).norm() < 1e-12 ? 1 : 0;
    EXPECT_EQ(ends, 2);
}

TEST(IncisionLine, SavedCutsOfOneTimeAreMergedAndACutStartingWhereTheLastEndedStartsFurther) {
    IncisionGrid g;
    IncisionLine first;
    first.points = {Vec3(0.5, 0.25, 0.0), Vec3(1.5, 0.25, 0.0)};
    IncisionLine same_time;
    same_time.points = {Vec3(1.75, 0.5, 0.0)};
    IncisionLine next;
    next.points = {Vec3(1.75, 0.5, 0.0), Vec3(2.75, 0.5, 0.0)};
    const std::vector<SavedIncision> saved =
        save_incisions(*g.container, g.state.position, {{1.0, first}, {1.0 + 1e-11, same_time}, {2.0, next}});
    ASSERT_EQ(saved.size(), 2U);
    // the lines at 1 and 1 + 1e-11 are one cut of three points
    EXPECT_EQ(saved[0].time, 1.0);
    ASSERT_EQ(saved[0].coordinates.size(), 3U);
    EXPECT_NEAR((saved[0].coordinates[1] - Vec3(1.5, 0.25, 0)).norm(), 0.0, 1e-15);
    // each point: its triangle and its barycentric coordinates there; (1.5, 0.25) in triangle
    // 2 = (1,0), (2,0), (2,1): 0.5, 0.25, 0.25
    EXPECT_EQ(saved[0].triangles[1], 2);
    EXPECT_NEAR(saved[0].barycentric[1][0], 0.5, 1e-15);
    EXPECT_NEAR(saved[0].barycentric[1][1], 0.25, 1e-15);
    EXPECT_NEAR(saved[0].barycentric[1][2], 0.25, 1e-15);
    // the cut at 2 starts where the one at 1 ended: 1e-5 of its first segment further on
    ASSERT_EQ(saved[1].coordinates.size(), 2U);
    EXPECT_NEAR((saved[1].coordinates[0] - Vec3(1.75 + 1e-5, 0.5, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((saved[1].coordinates[1] - Vec3(2.75, 0.5, 0)).norm(), 0.0, 1e-15);
    // nothing was cut
    EXPECT_EQ(g.container->num_points(), 12U);
}

}  // namespace
}  // namespace penalty
