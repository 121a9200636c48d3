// SparseGridTopology: SOFA's voxelisation of a closed surface (cell types, cell and point order,
// hexahedra, edges, quads) and BarycentricMapperSparseGridTopology's weights, on surfaces made
// here (a unit cube, an octahedron) with independent closed-form cell classifications.
#include "penalty/mechanics/sparse_grid_topology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace penalty {
namespace {

/// The unit cube [0,1]³ as 12 outward triangles (two per face).
struct Surface {
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
};

Surface unit_cube_surface() {
    Surface s;
    for (int k = 0; k < 8; ++k) s.positions.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        s.triangles.push_back({q[0], q[1], q[2]});
        s.triangles.push_back({q[0], q[2], q[3]});
    }
    return s;
}

/// The octahedron |x| + |y| + |z| = 1 (8 triangles).
Surface octahedron() {
    Surface s;
    s.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const PointId x : {0, 1})
        for (const PointId y : {2, 3})
            for (const PointId z : {4, 5}) s.triangles.push_back({x, y, z});
    return s;
}

TEST(SparseGridTopology, CubeSurfaceKeepsTheShellAsBoundaryThenTheInsideCells) {
    // cells of 0.4 from −1.1: the faces x = 0 and x = 1 lie inside cell layers 2 and 5
    const Surface cube = unit_cube_surface();
    const auto g = SparseGridTopology::from_surface({9, 9, 9}, Vec3::Constant(-1.1), Vec3::Constant(2.1),
                                                    cube.positions, cube.triangles);
    const auto& types = g.grid_cell_types();
    ASSERT_EQ(types.size(), 512u);
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const bool in_block = std::min({x, y, z}) >= 2 && std::max({x, y, z}) <= 5;
                const bool shell = in_block && (std::min({x, y, z}) == 2 || std::max({x, y, z}) == 5);
                const auto expected = !in_block ? SparseCellType::outside
                                      : shell   ? SparseCellType::boundary
                                                : SparseCellType::inside;
                EXPECT_EQ(types[std::size_t(x + 8 * (y + 8 * z))], expected) << x << " " << y << " " << z;
            }
    ASSERT_EQ(g.hexahedra().size(), 64u);
    EXPECT_EQ(std::count(g.cell_types().begin(), g.cell_types().begin() + 56, SparseCellType::boundary), 56);
    EXPECT_EQ(std::count(g.cell_types().begin() + 56, g.cell_types().end(), SparseCellType::inside), 8);
    // points: the 5³ corners of the block, x slowest then y then z (SOFA's map keyed by position)
    ASSERT_EQ(g.points().size(), 125u);
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 5; ++k) {
                const Vec3 expected = g.grid().point(2 + i, 2 + j, 2 + k);
                EXPECT_EQ(g.points()[std::size_t(25 * i + 5 * j + k)], expected);
            }
    // first hexahedron: regular cell (2,2,2), vertex order (i,j,k) (i+1,j,k) (i+1,j+1,k) (i,j+1,k), z+1
    const Hexahedron first{0, 25, 30, 5, 1, 26, 31, 6};
    EXPECT_EQ(g.hexahedra().front(), first);
    // first inside cell: regular cell (3,3,3)
    const auto at = [](int i, int j, int k) { return PointId(25 * i + 5 * j + k); };
    const Hexahedron inside{at(1, 1, 1), at(2, 1, 1), at(2, 2, 1), at(1, 2, 1),
                            at(1, 1, 2), at(2, 1, 2), at(2, 2, 2), at(1, 2, 2)};
    EXPECT_EQ(g.hexahedra()[56], inside);
    // edges and quads of the 4³ block of cells: 3·4·5·5 edges, 3·5·4·4 faces, sorted
    const auto edges = g.edges();
    EXPECT_EQ(edges.size(), 300u);
    EXPECT_TRUE(std::is_sorted(edges.begin(), edges.end()));
    EXPECT_EQ(edges.front(), (Edge{0, 1}));
    EXPECT_EQ(g.quads().size(), 240u);
}

TEST(SparseGridTopology, DefaultBoxIsTheSurfaceBoxGrownByOnePercent) {
    const Surface cube = unit_cube_surface();
    const auto [lo, hi] = SparseGridTopology::default_box(cube.positions);
    EXPECT_EQ(lo, Vec3::Constant(-0.01));
    EXPECT_EQ(hi, Vec3::Constant(1.01));
    // n = 5 on that box: every cell meets or lies inside the cube; the 2³ middle ones inside
    const auto g = SparseGridTopology::from_surface({5, 5, 5}, lo, hi, cube.positions, cube.triangles);
    EXPECT_EQ(g.hexahedra().size(), 64u);
    EXPECT_EQ(std::count(g.cell_types().begin(), g.cell_types().end(), SparseCellType::inside), 8);
    EXPECT_EQ(g.points().size(), 125u);
    // n below 2 is raised to 2 (SparseGridTopology::init): one cell holding the whole cube
    const auto one = SparseGridTopology::from_surface({1, 0, 1}, lo, hi, cube.positions, cube.triangles);
    EXPECT_EQ(one.grid().n(), (std::array<int, 3>{2, 2, 2}));
    EXPECT_EQ(one.hexahedra().size(), 1u);
}

TEST(SparseGridTopology, OctahedronCellsMatchTheClosedFormClassification) {
    // A closed cell meets the surface |x|+|y|+|z| = 1 iff min over the cell ≤ 1 ≤ max over the
    // cell (the minimum per axis is 0 when the interval holds 0, else its smaller |end|); it is
    // inside iff its largest corner value is below 1. Grid offsets avoid exact touching.
    const Surface oct = octahedron();
    const Vec3 lo(-1.37, -1.29, -1.31), hi(1.33, 1.41, 1.27);
    const std::array<int, 3> n{12, 11, 13};
    const auto g = SparseGridTopology::from_surface(n, lo, hi, oct.positions, oct.triangles);
    const auto& types = g.grid_cell_types();
    int boundary = 0, inside = 0;
    for (int z = 0; z < n[2] - 1; ++z)
        for (int y = 0; y < n[1] - 1; ++y)
            for (int x = 0; x < n[0] - 1; ++x) {
                const Vec3 a = g.grid().point(x, y, z), b = g.grid().point(x + 1, y + 1, z + 1);
                double smallest = 0, largest = 0;
                for (int k = 0; k < 3; ++k) {
                    smallest += (a[k] <= 0 && b[k] >= 0) ? 0.0 : std::min(std::abs(a[k]), std::abs(b[k]));
                    largest += std::max(std::abs(a[k]), std::abs(b[k]));
                }
                const auto expected = (smallest <= 1 && largest >= 1) ? SparseCellType::boundary
                                      : largest < 1                   ? SparseCellType::inside
                                                                      : SparseCellType::outside;
                boundary += expected == SparseCellType::boundary;
                inside += expected == SparseCellType::inside;
                EXPECT_EQ(types[std::size_t(x + (n[0] - 1) * (y + (n[1] - 1) * z))], expected)
                    << x << " " << y << " " << z;
            }
    EXPECT_GT(inside, 0);
    EXPECT_EQ(g.hexahedra().size(), std::size_t(boundary + inside));
    // every hexahedron is an axis-aligned grid cell: corner k = corner 0 + its offsets
    for (const Hexahedron& h : g.hexahedra()) {
        const Vec3 p0 = g.points()[std::size_t(h[0])], p6 = g.points()[std::size_t(h[6])];
        EXPECT_EQ(g.points()[std::size_t(h[1])], Vec3(p6.x(), p0.y(), p0.z()));
        EXPECT_EQ(g.points()[std::size_t(h[3])], Vec3(p0.x(), p6.y(), p0.z()));
        EXPECT_EQ(g.points()[std::size_t(h[7])], Vec3(p0.x(), p6.y(), p6.z()));
    }
    // points strictly increasing in (x, y, z) lexicographic order, all used
    for (std::size_t i = 1; i < g.points().size(); ++i) {
        const Vec3 &p = g.points()[i - 1], &q = g.points()[i];
        EXPECT_TRUE(std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3)) << i;
    }
    // only inside cells
    const auto core =
        SparseGridTopology::from_surface(n, lo, hi, oct.positions, oct.triangles, /*only_inside_cells=*/true);
    EXPECT_EQ(core.hexahedra().size(), std::size_t(inside));
}

TEST(SparseGridTopology, MappingIsTrilinearInTheKeptCellElseInTheNearestBoundaryCell) {
    const Surface cube = unit_cube_surface();
    const auto g = SparseGridTopology::from_surface({9, 9, 9}, Vec3::Constant(-1.1), Vec3::Constant(2.1),
                                                    cube.positions, cube.triangles);
    Vec3Object in("grid"), out("points");
    in.position = g.points();
    in.init();
    const std::vector<Vec3> points{{0.3, 0.55, 0.71}, {0.5, 0.5, 0.5}, {-0.5, 0.37, 0.45}, {3.0, 3.0, 3.0}};
    out.position = points;
    out.init();
    BarycentricMapping mapping(in, out);
    map_on_sparse_grid(mapping, g, points);
    mapping.init();
    // inside the kept cells: the point is reproduced
    for (std::size_t i = 0; i < 2; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.position[i][k], points[i][k], 1e-12) << i;
    // (−0.5, 0.37, 0.45) lies in an outside cell: nearest boundary cell centre is that of cell
    // (2, 3, 3) (centre (−0.1, 0.3, 0.3)); extrapolated trilinear coordinates reproduce it too
    const auto [cell, f] = g.locate(points[2]);
    const Vec3 p0 = g.points()[std::size_t(g.hexahedra()[std::size_t(cell)][0])];
    EXPECT_NEAR(p0.x(), -0.3, 1e-12);
    EXPECT_NEAR(p0.y(), 0.1, 1e-12);
    EXPECT_NEAR(p0.z(), 0.1, 1e-12);
    EXPECT_NEAR(f.x(), (-0.5 + 0.3) / 0.4, 1e-12);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.position[2][k], points[2][k], 1e-12);
    // far outside the grid: the corner cell (5,5,5)
    const auto [far_cell, far_f] = g.locate(points[3]);
    EXPECT_EQ(g.points()[std::size_t(g.hexahedra()[std::size_t(far_cell)][6])], g.grid().point(6, 6, 6));
    (void)far_f;
}

}  // namespace
}  // namespace penalty
