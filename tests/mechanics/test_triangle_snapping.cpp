// The snapping of a cut's path (triangle_snapping.cpp, SOFA's TriangleSetGeometryAlgorithms::
// SnapAlongPath): on the project-made grid of 3 x 2 unit squares, a path along y = 1.05 crosses
// the edge x = 1 and the diagonal of square (1, 1) at 0.05 from the inner vertex (1, 1). With
// the path epsilon 0.1 both crossings merge into that vertex, which moves to their mean
// (1.025, 1.05); with 0 they are two new points. A border vertex is never snapped.
#include "incision_grid.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

using test_incision::grid_point;
using test_incision::IncisionGrid;

/// Splits the grid `g` along (x0, y) → (x1, y) with the path epsilon `epsilon`; returns the
/// number of points made.
int split_grid_along(IncisionGrid& g, double x0, double x1, double y, double epsilon) {
    TriangleIncision incision(*g.container, g.state.position);
    Vec3 a(x0, y, 0.0), b(x1, y, 0.0);
    ElementId ta = incision.find_triangle(a), tb = incision.find_triangle(b);
    std::vector<IncisionPathElement> path;
    EXPECT_TRUE(incision.intersected_objects(-1, a, b, ta, tb, path));
    std::vector<ElementId> new_edges;
    return incision.split_along_path(-1, a, -1, b, path, new_edges, epsilon, 0.0);
}

TEST(TriangleSnapping, CrossingsNearAnInnerVertexMergeIntoItAtTheirMean) {
    const PointId inner = grid_point(1, 1);
    IncisionGrid unsnapped;
    // the two ends and the two crossings
    EXPECT_EQ(split_grid_along(unsnapped, 0.3, 1.7, 1.05, 0.0), 4);
    EXPECT_EQ(unsnapped.state.position[std::size_t(inner)], Vec3(1, 1, 0));
    IncisionGrid snapped;
    // the two ends only: the path goes through the vertex
    EXPECT_EQ(split_grid_along(snapped, 0.3, 1.7, 1.05, 0.1), 2);
    const Vec3& moved = snapped.state.position[std::size_t(inner)];
    EXPECT_NEAR(moved.x(), (1.0 + 1.05) / 2, 1e-15);
    EXPECT_NEAR(moved.y(), 1.05, 1e-15);
    EXPECT_EQ(moved.z(), 0.0);
    // both surfaces keep their area (the vertex moves inside its star)
    EXPECT_NEAR(unsnapped.signed_area_sum(), 6.0, 1e-14);
    EXPECT_NEAR(snapped.signed_area_sum(), 6.0, 1e-14);
    EXPECT_LT(snapped.mesh.triangles().size(), unsnapped.mesh.triangles().size());
}

TEST(TriangleSnapping, ABorderVertexIsNotSnapped) {
    // along y = 0.05 the crossings are as near the border vertex (1, 0): no snapping
    IncisionGrid g;
    EXPECT_EQ(split_grid_along(g, 0.3, 1.7, 0.05, 0.1), 4);
    EXPECT_EQ(g.state.position[std::size_t(grid_point(1, 0))], Vec3(1, 0, 0));
}

}  // namespace
}  // namespace penalty
