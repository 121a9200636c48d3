// SOFA's SparseGridMultipleTopology (sparse_grid_multiple.cpp, SparseGridTopology::from_surfaces):
// one sparse grid voxelising several closed surfaces, each cell with the stiffness and mass
// coefficients of the surfaces it lies in (SparseGridMultipleTopology::buildAsFinest,
// assembleRegularGrids), and the coarser levels' averages; the cells kept with
// only_inside_cells, and a call without a surface refused.
#include "penalty/mechanics/sparse_grid_topology.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace penalty {
namespace {

using Cell = SparseCellType;

// Outer cube [0.5, 5.5]³ and inner cube [1.5, 4.5]³ on unit cells over [0, 6]³: the outer's
// BOUNDARY cells have an index 0 or 5, the inner's are the shell of indices 1..4, its INSIDE ones
// indices 2..3.
struct NestedCubes {
    std::vector<Vec3> outer_points, inner_points;
    std::vector<Triangle> triangles;
    NestedCubes() {
        for (int k = 0; k < 8; ++k) {
            const Vec3 corner(k & 1, (k >> 1) & 1, (k >> 2) & 1);
            outer_points.push_back(Vec3::Constant(0.5) + 5.0 * corner);
            inner_points.push_back(Vec3::Constant(1.5) + 3.0 * corner);
        }
        const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& q : quads) {
            triangles.push_back({q[0], q[1], q[2]});
            triangles.push_back({q[0], q[2], q[3]});
        }
    }
    [[nodiscard]] SparseGridTopology grid(bool fill, bool erase) const {
        const SparseGridTopology::WeightedSurface surfaces[] = {{outer_points, triangles, 10.0f, 3.0f},
                                                                {inner_points, triangles, 0.2f, 5.0f}};
        return SparseGridTopology::from_surfaces({7, 7, 7}, Vec3::Zero(), Vec3::Constant(6), surfaces, fill, erase);
    }
};

TEST(SparseGridMultiple, CellsTakeTheCoefficientsOfTheSurfacesTheyLieIn) {
    const NestedCubes cubes;
    const auto at = [](const SparseGridTopology& g, const Vec3& p, bool stiffness) {
        const auto [cell, fraction] = g.locate(p);
        return (stiffness ? g.stiffness_coefficients(true) : g.mass_coefficients(true))[std::size_t(cell)];
    };
    const SparseGridTopology g = cubes.grid(true, false);
    EXPECT_EQ(g.hexahedra().size(), 216u);  // every cell is in the outer cube
    // outer BOUNDARY only: the mean of 0 and the outer's
    EXPECT_EQ(at(g, {0.5, 0.5, 0.5}, true), 5.0);
    EXPECT_EQ(at(g, {0.5, 0.5, 0.5}, false), 1.5);
    // outer INSIDE, inner BOUNDARY: stays INSIDE, the mean of both, in single precision
    EXPECT_EQ(at(g, {1.5, 1.5, 1.5}, true), double((10.0f + 0.2f) * 0.5f));
    EXPECT_EQ(at(g, {1.5, 1.5, 1.5}, false), 4.0);
    // inside both: the last surface's
    EXPECT_EQ(at(g, {2.5, 2.5, 2.5}, true), double(0.2f));
    EXPECT_EQ(at(g, {2.5, 2.5, 2.5}, false), 5.0);
    EXPECT_EQ(g.cell_types()[std::size_t(g.locate({1.5, 1.5, 1.5}).first)], Cell::inside);
    EXPECT_EQ(g.cell_types()[std::size_t(g.locate({0.5, 0.5, 0.5}).first)], Cell::boundary);
    // erasePreviousCoef: a BOUNDARY cell takes the last surface's
    const SparseGridTopology erased = cubes.grid(true, true);
    EXPECT_EQ(at(erased, {1.5, 1.5, 1.5}, true), double(0.2f));
    EXPECT_EQ(at(erased, {0.5, 0.5, 0.5}, true), 10.0);
    // without fillWeighted a BOUNDARY cell counts as INSIDE
    const SparseGridTopology filled = cubes.grid(false, false);
    EXPECT_EQ(at(filled, {0.5, 0.5, 0.5}, true), 10.0);
    EXPECT_EQ(at(filled, {1.5, 1.5, 1.5}, true), double(0.2f));
    for (const Cell t : filled.cell_types()) EXPECT_EQ(t, Cell::inside);
}

TEST(SparseGridMultiple, CoarserLevelsAverageTheFinestCoefficientsInSinglePrecision) {
    const NestedCubes cubes;
    auto finest = std::make_shared<const SparseGridTopology>(cubes.grid(true, false));
    const SparseGridTopology coarse = SparseGridTopology::from_finer(finest, true);
    ASSERT_EQ(coarse.hexahedra().size(), 27u);
    // coarse cell (1,1,1) = finest cells 2..3: all inside both cubes
    const auto [middle, f] = coarse.locate({3.0, 3.0, 3.0});
    float inner = 0;
    for (int k = 0; k < 8; ++k) inner += 0.2f;
    EXPECT_EQ(coarse.stiffness_coefficients(true)[std::size_t(middle)], double(float(double(inner) / 8.0)));
    // coarse cell (0,0,0) = finest (0..1)³: 7 outer-BOUNDARY cells (5) and (1,1,1) (5.1f)
    const auto [corner, g] = coarse.locate({0.5, 0.5, 0.5});
    float sum = 0;
    for (int k = 0; k < 7; ++k) sum += 5.0f;
    sum += (10.0f + 0.2f) * 0.5f;
    EXPECT_EQ(coarse.stiffness_coefficients(true)[std::size_t(corner)], double(float(double(sum) / 8.0)));
    EXPECT_EQ(coarse.mass_coefficients(true)[std::size_t(corner)], double(float((7 * 1.5 + 4.0) / 8.0)));
}

TEST(SparseGridMultiple, OnlyInsideCellsKeepsTheCellsInsideASurface) {
    // with fillWeighted (BOUNDARY cells stay BOUNDARY): the outer cube's shell (indices 0 and 5)
    // is BOUNDARY, every other cell of the 6³ INSIDE: 4³ cells kept, their coefficients kept too
    const NestedCubes cubes;
    const SparseGridTopology::WeightedSurface surfaces[] = {{cubes.outer_points, cubes.triangles, 10.0f, 3.0f},
                                                            {cubes.inner_points, cubes.triangles, 0.2f, 5.0f}};
    const SparseGridTopology inside =
        SparseGridTopology::from_surfaces({7, 7, 7}, Vec3::Zero(), Vec3::Constant(6), surfaces, true, false, true);
    ASSERT_EQ(inside.hexahedra().size(), 64u);
    for (const Cell t : inside.cell_types()) EXPECT_EQ(t, Cell::inside);
    const auto [cell, fraction] = inside.locate({2.5, 2.5, 2.5});
    EXPECT_EQ(inside.stiffness_coefficients(true)[std::size_t(cell)], double(0.2f));
    // the outer shell's cells are gone: every point lies in [1, 5]³
    for (const Vec3& p : inside.points()) {
        EXPECT_GE(p.minCoeff(), 1.0) << p.transpose();
        EXPECT_LE(p.maxCoeff(), 5.0) << p.transpose();
    }
    EXPECT_EQ(inside.points().size(), 125u);
}

TEST(SparseGridMultiple, NoSurfaceIsRefused) {
    try {
        (void)SparseGridTopology::from_surfaces({3, 3, 3}, Vec3::Zero(), Vec3::Ones(), {}, true, false);
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), "SparseGridMultipleTopology: no surface");
    }
}

}  // namespace
}  // namespace penalty
