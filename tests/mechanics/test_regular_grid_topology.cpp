// RegularGridTopology (mechanics/regular_grid_topology.cpp): point indexing, springs and the
// barycentric mapping of a grid.
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>

namespace penalty {
namespace {

TEST(RegularGridTopology, IndexingSpringsAndBarycentricMapping) {
    RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
    EXPECT_EQ(g.num_points(), 12u);
    EXPECT_EQ(g.point_index(2, 1, 1), 11);
    EXPECT_EQ(g.point(1, 1, 0), Vec3(1, 1, 0));
    const MeshTopology m = g.mesh();
    ASSERT_EQ(m.hexahedra().size(), 2u);
    EXPECT_EQ(m.hexahedra()[1], (Hexahedron{1, 2, 5, 4, 7, 8, 11, 10}));
    // 20 edges + 2·11 face diagonals + 4·2 cell diagonals.
    EXPECT_EQ(regular_grid_springs(g, MeshSpringParameters::uniform(1, 0)).size(), 20u + 22u + 8u);
    MeshSpringParameters lines;
    lines.lines_stiffness = 2.0;
    const auto ls = regular_grid_springs(g, lines);
    ASSERT_EQ(ls.size(), 20u);
    EXPECT_NEAR(ls[0].ks, 2.0, 1e-15);
    Vec3Object in, out;
    in.position = g.points();
    in.init();
    BarycentricMapping map(in, out);
    const std::vector<Vec3> pts = {Vec3(1.5, 0.25, 0.75), Vec3(0.2, 0.9, 0.1), Vec3(2.5, 0.5, 0.5)};
    map_on_regular_grid(map, g, pts);
    map.init();
    for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_TRUE(out.position[i].isApprox(pts[i], 1e-14)) << i;
    EXPECT_EQ(map.weights()[0][0].index, 1);  // cell 1
    double wsum = 0;
    for (const auto& e : map.weights()[1]) wsum += e.weight;
    EXPECT_NEAR(wsum, 1.0, 1e-15);
    RegularGridTopology quads({3, 3, 1}, Vec3::Zero(), Vec3(1, 1, 0));
    EXPECT_EQ(quads.mesh().quads().size(), 4u);
    EXPECT_TRUE(quads.mesh().hexahedra().empty());
    EXPECT_EQ(quads.mesh().edges().size(), 12u);
    // SOFA GridTopology order: XY quads first, then XZ, then YZ; edges X, Y, Z lines.
    EXPECT_EQ(m.quads().size(), 2u * 2 + 2u * 2 + 3u * 1);  // (nx−1)(ny−1)nz + (nx−1)ny(nz−1) + nx(ny−1)(nz−1)
    EXPECT_EQ(m.quads()[0], (Quad{0, 1, 4, 3}));
    EXPECT_EQ(m.quads()[4], (Quad{0, 1, 7, 6}));
    EXPECT_EQ(m.quads()[8], (Quad{0, 3, 9, 6}));
    EXPECT_EQ(m.edges()[0], (Edge{0, 1}));
    EXPECT_EQ(m.edges()[8], (Edge{0, 3}));
    EXPECT_EQ(m.edges()[14], (Edge{0, 6}));
    const MeshTopology mt = g.mesh(true);
    EXPECT_EQ(mt.triangles().size(), 2 * m.quads().size());
    EXPECT_EQ(mt.triangles()[1], (Triangle{0, 4, 3}));
    EXPECT_EQ(mt.edges().size(), 20u + 11u);  // + one diagonal per quad
    EXPECT_THROW(RegularGridTopology({0, 2, 2}, Vec3::Zero(), Vec3::Ones()), std::invalid_argument);
    EXPECT_THROW(RegularGridTopology({2, 2, 2}, Vec3::Zero(), Vec3(1, std::nan(""), 1)), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
