// SparseGridRamificationTopology: cells split by the connected parts of their finer cells
// (SparseGridRamificationTopology::buildFromFiner), faces cut where no surface edge crosses them
// (findConnexionsAtFinestLevel / sharingTriangle), the ramified point numbering and the
// coarsest-parent lookup, on grids and surfaces made here with closed-form answers (the
// per-surface coefficients: test_sparse_grid_multiple.cpp).
#include "penalty/mechanics/sparse_grid_ramification.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace penalty {
namespace {

using Cell = SparseCellType;
constexpr Cell kO = Cell::outside, kB = Cell::boundary;

/// A finest level of unit cells from (0, 0, 0), typed by hand, with its connexion graph.
std::shared_ptr<const SparseGridTopology> ramified_unit_cells(std::array<int, 3> n, std::vector<Cell> types,
                                                              const SparseGridFacets* surface = nullptr,
                                                              bool ramify = false) {
    const Vec3 max(n[0] - 1, n[1] - 1, n[2] - 1);
    return std::make_shared<const SparseGridTopology>(SparseGridTopology::ramified_finest(
        SparseGridTopology::from_grid_types(n, Vec3::Zero(), max, std::move(types)), surface, ramify));
}

std::array<Vec3, 8> corners_of(const SparseGridTopology& g, std::size_t hexahedron) {
    std::array<Vec3, 8> c;
    for (std::size_t k = 0; k < 8; ++k) c[k] = g.points()[std::size_t(g.hexahedra()[hexahedron][k])];
    return c;
}

TEST(SparseGridRamification, DiagonalFineCellsSplitTheirCoarseCellIntoTwoHexahedra) {
    // 2 x 2 x 1 finest cells, only (0,0,0) and (1,1,0): they share an edge, not a face
    const auto finest = ramified_unit_cells({3, 3, 2}, {kB, kO, kO, kB});
    const SparseGridTopology coarse = SparseGridTopology::from_finer_ramified(finest, true);
    // one coarse cell [0,2]³ (max = min + (n − 1)·2·dx), two connexions: two hexahedra, 16 points
    ASSERT_EQ(coarse.hexahedra().size(), 2u);
    ASSERT_EQ(coarse.points().size(), 16u);
    const std::array<Vec3, 8> cube{
        {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}}};
    for (std::size_t h = 0; h < 2; ++h) {
        EXPECT_EQ(corners_of(coarse, h), cube) << h;
        for (std::size_t k = 0; k < 8; ++k)
            EXPECT_EQ(coarse.hexahedra()[h][k], PointId(8 * h + k));  // own points, in order
        EXPECT_EQ(coarse.cell_types()[h], Cell::boundary);
    }
    // children: each connexion keeps its own finer cell (place 0, place 3)
    EXPECT_EQ(coarse.children()[0], (std::array<Index, 8>{0, -1, -1, -1, -1, -1, -1, -1}));
    EXPECT_EQ(coarse.children()[1], (std::array<Index, 8>{-1, -1, -1, 1, -1, -1, -1, -1}));
    // coefficients: one BOUNDARY child (0.5) over 8; not split, the cell would have 2
    EXPECT_EQ(coarse.stiffness_coefficients(true), (std::vector<double>{0.0625, 0.0625}));
    EXPECT_EQ(coarse.mass_coefficients(true), (std::vector<double>{0.0625, 0.0625}));
    const SparseGridTopology plain = SparseGridTopology::from_finer(finest, true);
    EXPECT_EQ(plain.hexahedra().size(), 1u);
    EXPECT_EQ(plain.points().size(), 8u);
    EXPECT_EQ(plain.stiffness_coefficients(true), std::vector<double>{0.125});
}

TEST(SparseGridRamification, PointsFindTheHexahedronOfTheirFinestCellsConnexion) {
    const auto finest = ramified_unit_cells({3, 3, 2}, {kB, kO, kO, kB});
    const SparseGridTopology coarse = SparseGridTopology::from_finer_ramified(finest, true);
    // SparseGridRamificationTopology::findCube: the finest cell's coarsest parent, fractions in [0,2]³
    EXPECT_EQ(coarse.locate({0.5, 0.5, 0.5}), std::pair(Index(0), Vec3(0.25, 0.25, 0.25)));
    EXPECT_EQ(coarse.locate({1.5, 1.5, 0.5}), std::pair(Index(1), Vec3(0.75, 0.75, 0.25)));
    // in no finest cell: the nearest BOUNDARY finest cell (a tie: the first), fractions clamped cell
    EXPECT_EQ(coarse.locate({1.5, 0.5, 0.5}), std::pair(Index(0), Vec3(0.75, 0.25, 0.25)));
    EXPECT_EQ(coarse.locate({1.6, 1.4, 0.5}).first, 1);
    // two ramified levels: 4 x 4 x 2 finest cells, the two diagonal ones in the first 2 x 2 block
    std::vector<Cell> types(16, kO);
    types[0] = types[5] = kB;  // (0,0,0) and (1,1,0)
    const auto finest4 = ramified_unit_cells({5, 5, 2}, types);
    auto middle = std::make_shared<const SparseGridTopology>(SparseGridTopology::from_finer_ramified(finest4, true));
    ASSERT_EQ(middle->hexahedra().size(), 2u);
    const SparseGridTopology top = SparseGridTopology::from_finer_ramified(middle, true);
    // the middle level's two connexions lie in one top cell and are not neighbours: still two
    ASSERT_EQ(top.hexahedra().size(), 2u);
    EXPECT_EQ(top.locate({1.5, 1.5, 0.5}).first, 1);
    EXPECT_EQ(top.locate({0.5, 0.5, 0.5}).first, 0);
}

TEST(SparseGridRamification, FaceNeighboursStayOneHexahedronWithSharedPoints) {
    // (0,0,0) and (1,0,0) share a face: one connexion
    const auto finest = ramified_unit_cells({3, 3, 2}, {kB, kB, kO, kO});
    ASSERT_EQ(finest->ramification()->connexions[0].neighbors[kRight], std::vector<Index>{1});
    ASSERT_EQ(finest->ramification()->connexions[1].neighbors[kLeft], std::vector<Index>{0});
    const SparseGridTopology coarse = SparseGridTopology::from_finer_ramified(finest, true);
    ASSERT_EQ(coarse.hexahedra().size(), 1u);
    EXPECT_EQ(coarse.points().size(), 8u);
    EXPECT_EQ(coarse.children()[0], (std::array<Index, 8>{0, 1, -1, -1, -1, -1, -1, -1}));
    EXPECT_EQ(coarse.stiffness_coefficients(true), std::vector<double>{0.125});
}

TEST(SparseGridRamification, FinestConnectivityCutsTheFacesNoSurfaceEdgeCrosses) {
    // two BOUNDARY unit cells along x; their common face is x = 1, 0 ≤ y, z ≤ 1
    const auto points_with = [](std::vector<Vec3> triangle) {
        SparseGridFacets surface{std::move(triangle), {{0, 1, 2}}};
        return ramified_unit_cells({3, 2, 2}, {kB, kB}, &surface, true)->points().size();
    };
    // the edge (v0, v1) crosses the face at (1, 0.5, 0.5): connected, 12 points
    EXPECT_EQ(points_with({{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}, {1.5, 0.6, 0.6}}), 12u);
    // no edge reaches x = 1: two hexahedra of their own, 16 points
    EXPECT_EQ(points_with({{0.2, 0.5, 0.5}, {0.8, 0.5, 0.5}, {0.8, 0.6, 0.6}}), 16u);
    // only the closing edge (v2, v0) crosses inside the square ((v0, v1) crosses x = 1 at y = 1.75):
    // SOFA tests the edges (v[j−1], v[j]) for j ≥ 1 only
    EXPECT_EQ(points_with({{0.5, 0.5, 0.5}, {1.5, 3.0, 0.5}, {1.5, 0.5, 0.5}}), 16u);
    EXPECT_EQ(points_with({{1.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, {1.5, 3.0, 0.5}}), 12u);  // the same triangle, turned
    // an edge crossing the face's plane outside the square does not connect them
    EXPECT_EQ(points_with({{0.5, 1.5, 0.5}, {1.5, 1.5, 0.5}, {1.5, 1.6, 0.6}}), 16u);
    // an INSIDE cell is connected to its neighbours whatever the surface
    SparseGridFacets none{{{0.2, 0.5, 0.5}, {0.8, 0.5, 0.5}, {0.8, 0.6, 0.6}}, {{0, 1, 2}}};
    EXPECT_EQ(ramified_unit_cells({3, 2, 2}, {kB, Cell::inside}, &none, true)->points().size(), 12u);
    // the ramified numbering: the first cell's corners 0..7 in its corner order, then the second's
    // own corners (its face takes the first's labels)
    const auto g = ramified_unit_cells({3, 2, 2}, {kB, kB}, &none, false);
    EXPECT_EQ(g->points().size(), 12u);  // without ramify_points: SOFA's position-sorted points
    SparseGridFacets crossing{{{0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}, {1.5, 0.6, 0.6}}, {{0, 1, 2}}};
    const auto r = ramified_unit_cells({3, 2, 2}, {kB, kB}, &crossing, true);
    EXPECT_EQ(r->hexahedra()[0], (Hexahedron{0, 1, 2, 3, 4, 5, 6, 7}));
    EXPECT_EQ(r->hexahedra()[1], (Hexahedron{1, 8, 9, 2, 5, 10, 11, 6}));
    EXPECT_EQ(r->points()[8], Vec3(2, 0, 0));
}

}  // namespace
}  // namespace penalty
