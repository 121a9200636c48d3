// SubsetTopology's selection (SubsetTopology::doUpdate) on a grid of points made here.
#include "penalty/mechanics/subset_topology.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

/// A 4×3 grid of points in the plane z = 0, point i + 4j at (i, j, 0), two triangles per cell
/// (i, i+1, i+5) and (i, i+5, i+4), cells in order; its horizontal edges.
SubsetInput grid_input() {
    SubsetInput in;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) in.positions.emplace_back(i, j, 0);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) {
            const PointId p = i + 4 * j;
            in.triangles.push_back({p, p + 1, p + 5});
            in.triangles.push_back({p, p + 5, p + 4});
        }
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) in.edges.push_back({i + 4 * j, i + 1 + 4 * j});
    return in;
}

SubsetRegion box(double xmin, double ymin, double xmax, double ymax) {
    return {.boxes = {AlignedBox::from_corners(Vec3(xmin, ymin, -1), Vec3(xmax, ymax, 1))}, .centers = {}, .radii = {}};
}

TEST(SubsetTopology, BoxSelectsPointsAndWholeElementsInInputOrder) {
    // box x ∈ [1, 3] (bounds included): columns 1..3
    const SubsetOutput out = select_subset(grid_input(), box(3, 0, 1, 2));  // corners swapped: put in order
    EXPECT_EQ(out.indices, (std::vector<PointId>{1, 2, 3, 5, 6, 7, 9, 10, 11}));
    ASSERT_EQ(out.points_in.size(), 9u);
    EXPECT_EQ(out.points_in[3], Vec3(1, 1, 0));
    EXPECT_EQ(out.points_out.size(), 3u);
    EXPECT_EQ(out.points_out[2], Vec3(0, 2, 0));
    // triangles of cells 1 and 2 of each row (cell 0 has vertices at x = 0)
    EXPECT_EQ(out.triangle_indices, (std::vector<PointId>{2, 3, 4, 5, 8, 9, 10, 11}));
    EXPECT_EQ(out.triangles_in.front(), (Triangle{1, 2, 6}));  // global indices
    EXPECT_EQ(out.triangles_out, (std::vector<Triangle>{{0, 1, 5}, {0, 5, 4}, {4, 5, 9}, {4, 9, 8}}));
    EXPECT_EQ(out.edge_indices, (std::vector<PointId>{1, 2, 4, 5, 7, 8}));
    EXPECT_EQ(out.edges_out.size(), 3u);
    EXPECT_EQ(out.border_count, 0u);
}

TEST(SubsetTopology, AnElementMustLieInOneRegion) {
    // two boxes: column 0 and column 1; the cells between them have vertices in both but not
    // all in one: outside
    SubsetRegion r = box(-0.5, 0, 0.5, 2);
    r.boxes.push_back(box(0.5, 0, 1.5, 2).boxes[0]);
    const SubsetOutput out = select_subset(grid_input(), r);
    EXPECT_EQ(out.indices, (std::vector<PointId>{0, 1, 4, 5, 8, 9}));
    EXPECT_TRUE(out.triangles_in.empty());
    EXPECT_TRUE(out.edges_in.empty());
}

TEST(SubsetTopology, SpheresReplaceTheBoxes) {
    SubsetRegion r = box(-10, -10, 10, 10);
    r.centers = {Vec3(0, 0, 0)};
    r.radii = {1.0};  // |p| ≤ 1: points 0, 1, 4
    const SubsetOutput out = select_subset(grid_input(), r);
    EXPECT_EQ(out.indices, (std::vector<PointId>{0, 1, 4}));
    EXPECT_EQ(out.edge_indices, (std::vector<PointId>{0}));
    r.radii.push_back(2.0);
    EXPECT_THROW((void)select_subset(grid_input(), r), std::invalid_argument);
}

TEST(SubsetTopology, LocalIndicesPutTheBorderPointsFirst) {
    // box x ∈ [1.5, 3]: columns 2, 3 inside. Triangles with vertices on both sides make the
    // inside vertices 2, 6, 10 the border points: first in both point lists.
    SubsetInput in = grid_input();
    in.local_indices = true;
    const SubsetOutput out = select_subset(in, box(1.5, 0, 3, 2));
    EXPECT_EQ(out.border_count, 3u);
    EXPECT_EQ(out.indices, (std::vector<PointId>{2, 6, 10, 3, 7, 11}));
    ASSERT_EQ(out.points_in.size(), 6u);
    ASSERT_EQ(out.points_out.size(), 9u);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(out.points_in[k], out.points_out[k]);
    EXPECT_EQ(out.points_in[3], Vec3(3, 0, 0));
    EXPECT_EQ(out.points_out[3], Vec3(0, 0, 0));
    // inside: point 2 → 0, 3 → 3, 6 → 1, 7 → 4; the cell (2, 3, 7), (2, 7, 6)
    EXPECT_EQ(out.triangles_in.front(), (Triangle{0, 3, 4}));
    EXPECT_EQ(out.triangles_in[1], (Triangle{0, 4, 1}));
    // outside: 0 → 3, 1 → 4, 5 → 6, 4 → 5; the first cell (0, 1, 5), (0, 5, 4); the border
    // cell (1, 2, 6) → (4, 0, 1)
    EXPECT_EQ(out.triangles_out[0], (Triangle{3, 4, 6}));
    EXPECT_EQ(out.triangles_out[1], (Triangle{3, 6, 5}));
    EXPECT_EQ(out.triangles_out[2], (Triangle{4, 0, 1}));
    // every output element indexes its own point list
    for (const Triangle& t : out.triangles_out)
        for (const PointId v : t) EXPECT_LT(static_cast<std::size_t>(v), out.points_out.size());
    for (const Triangle& t : out.triangles_in)
        for (const PointId v : t) EXPECT_LT(static_cast<std::size_t>(v), out.points_in.size());
}

TEST(SubsetTopology, TetrahedraInputListsTheInsideTetrahedra) {
    SubsetInput in;
    in.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 1, 1)};
    in.tetrahedra = {{0, 1, 2, 3}, {1, 2, 3, 4}};
    in.tetrahedra_input = std::vector<PointId>{1};
    in.local_indices = true;
    const SubsetOutput out = select_subset(in, box(10, 10, 11, 11));  // the region selects nothing
    EXPECT_EQ(out.tetrahedron_indices, (std::vector<PointId>{1}));
    EXPECT_EQ(out.tetrahedra_in, (std::vector<Tetrahedron>{{0, 1, 2, 3}}));
    EXPECT_EQ(out.tetrahedra_out, (std::vector<Tetrahedron>{{0, 1, 2, 3}}));
    EXPECT_EQ(out.points_in, (std::vector<Vec3>{in.positions[1], in.positions[2], in.positions[3], in.positions[4]}));
    EXPECT_EQ(out.points_out, (std::vector<Vec3>{in.positions[0], in.positions[1], in.positions[2], in.positions[3]}));
    EXPECT_EQ(out.indices, (std::vector<PointId>{1, 2, 3, 4}));
}

TEST(SubsetTopology, RefusesAnElementOutOfRange) {
    SubsetInput in = grid_input();
    in.triangles.push_back({0, 1, 12});
    EXPECT_THROW((void)select_subset(in, box(0, 0, 1, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
