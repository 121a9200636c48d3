// SOFA's sparse-grid hierarchy (sparse_grid_hierarchy.cpp, SparseGridTopology::buildFromFiner): a
// coarser level from a finer one of 6 × 2 × 2 unit cells, its last column outside and two cells on
// the boundary: each coarse cell INSIDE when its eight children are, OUTSIDE when none is kept,
// else BOUNDARY; its points the kept cells' corners sorted by position; its children; its
// coefficient the mean of its children's (absent ones 0).
#include "penalty/mechanics/sparse_grid_topology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

namespace penalty {
namespace {

/// The fine grid [0,6]×[0,2]×[0,2] of unit cells (index i + 6(j + 2k)): the column i = 5
/// outside, the cells (3,1,1) and (4,0,0) on the boundary, the others inside.
std::shared_ptr<const SparseGridTopology> hierarchy_fine_grid() {
    std::vector<SparseCellType> types(24, SparseCellType::inside);
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j) types[std::size_t(5 + 6 * (j + 2 * k))] = SparseCellType::outside;
    types[3 + 6 * (1 + 2 * 1)] = SparseCellType::boundary;
    types[4] = SparseCellType::boundary;
    return std::make_shared<const SparseGridTopology>(
        SparseGridTopology::from_grid_types({7, 3, 3}, Vec3::Zero(), Vec3(6, 2, 2), std::move(types)));
}

TEST(SparseGridHierarchy, CoarseCellsAreTypedByTheirChildren) {
    const auto fine = hierarchy_fine_grid();
    ASSERT_EQ(fine->hexahedra().size(), 20u);
    const SparseGridTopology coarse = SparseGridTopology::from_finer(fine, true);
    // 4 × 2 × 2 points, cells of 2: the first has eight inside children; the second eight kept
    // ones, one on the boundary; the third four kept ones (the column i = 5 is not kept)
    ASSERT_EQ(coarse.hexahedra().size(), 3u);
    EXPECT_EQ(coarse.cell_types(), (std::vector<SparseCellType>{SparseCellType::inside, SparseCellType::boundary,
                                                                SparseCellType::boundary}));
    EXPECT_EQ(coarse.finer_levels(), 1);
    ASSERT_EQ(coarse.children().size(), 3u);
    for (const Index child : coarse.children()[0]) EXPECT_GE(child, 0);
    for (const Index child : coarse.children()[1]) EXPECT_GE(child, 0);
    int kept = 0;
    for (std::size_t c = 0; c < 8; ++c) {
        const Index child = coarse.children()[2][c];
        // child c = (4 + (c & 1), (c & 2) >> 1, (c & 4) >> 2): the odd ones are in the column i = 5
        EXPECT_EQ(child < 0, (c & 1) == 1) << c;
        kept += child >= 0 ? 1 : 0;
    }
    EXPECT_EQ(kept, 4);
}

TEST(SparseGridHierarchy, PointsAreTheKeptCornersSortedByPosition) {
    const SparseGridTopology coarse = SparseGridTopology::from_finer(hierarchy_fine_grid(), true);
    // every corner of the three cells: (2i, 2j, 2k), numbered with k fastest, then j, then i
    ASSERT_EQ(coarse.points().size(), 16u);
    EXPECT_EQ(coarse.points()[0], Vec3(0, 0, 0));
    EXPECT_EQ(coarse.points()[1], Vec3(0, 0, 2));
    EXPECT_EQ(coarse.points()[2], Vec3(0, 2, 0));
    EXPECT_EQ(coarse.points()[4], Vec3(2, 0, 0));
    EXPECT_EQ(coarse.points()[15], Vec3(6, 2, 2));
    // the cells' corners in SOFA's hexahedron order
    EXPECT_EQ(coarse.hexahedra()[0], (Hexahedron{0, 4, 6, 2, 1, 5, 7, 3}));
    EXPECT_EQ(coarse.hexahedra()[1], (Hexahedron{4, 8, 10, 6, 5, 9, 11, 7}));
    EXPECT_EQ(coarse.hexahedra()[2], (Hexahedron{8, 12, 14, 10, 9, 13, 15, 11}));
}

TEST(SparseGridHierarchy, ACoarseCoefficientIsTheMeanOfItsChildren) {
    const auto fine = hierarchy_fine_grid();
    // fillWeighted: a boundary child weighs 1/2, an absent one 0: (7 + 0.5)/8, (3 + 0.5)/8; else
    // 8/8 and 4/8
    const SparseGridTopology weighted = SparseGridTopology::from_finer(fine, true);
    EXPECT_EQ(weighted.coefficients(true), (std::vector<double>{1.0, 7.5 / 8.0, 3.5 / 8.0}));
    const SparseGridTopology unweighted = SparseGridTopology::from_finer(fine, false);
    EXPECT_EQ(unweighted.coefficients(false), (std::vector<double>{1.0, 1.0, 0.5}));
    // the finest level's own: 1 inside, 1/2 on the boundary with fillWeighted
    const std::vector<double> finest = fine->coefficients(true);
    EXPECT_EQ(std::count(finest.begin(), finest.end(), 0.5), 2);
    EXPECT_EQ(std::count(finest.begin(), finest.end(), 1.0), 18);
}

TEST(SparseGridHierarchy, WithoutAFinerGridNothingIsBuilt) {
    try {
        (void)SparseGridTopology::from_finer(nullptr, true);
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), "SparseGridTopology: no finer grid to build from");
    }
}

}  // namespace
}  // namespace penalty
