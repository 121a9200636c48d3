// BarycentricMapping onto a dynamic container's tetrahedra and hexahedra (barycentric_set_mapper.cpp,
// SOFA's BarycentricMapperTetrahedronSetTopology / BarycentricMapperHexahedronSetTopology and
// BarycentricMapperTopologyContainer::init): each point's element from its hash-grid cell, all
// elements when the cell has none; a hexahedron's coordinates in the parallelepiped of its three
// edges from vertex 0, trilinear weights, |p − centre|² outside; the refusals' messages.
#include "penalty/mechanics/mapping.hpp"

#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <stdexcept>
#include <string>

namespace penalty {
namespace {

TEST(Mapping, BarycentricOnSetTetrahedraKeepsAnElementOfThePointsHashCell) {
    // SOFA's BarycentricMapperTetrahedronSetTopology (BarycentricMapperTopologyContainer::init):
    // cells of the mean edge length h = 0.688; p's cell (0, 0, 0) holds tetrahedron B alone (A's
    // bounding box ends at x = −0.01), at |p − c_B|² = 0.1844 ≤ h/2, so B is kept although A's
    // centre is nearer (|p − c_A|² = 0.0729), which the mesh mapper's exhaustive search takes.
    // SOFA HEAD on this pair (a force on A's vertex 1, one step): the point mapped through a
    // TetrahedronSetTopologyContainer stays at y = 0.5, through a MeshTopology it moves to 0.55661
    // (the scene test MassSpringMappingFollowers.SetContainersMapOutsidePointsAsSofasHashGrid).
    Vec3Object in, out;
    in.position = {Vec3(-0.6, 0.3, 0.3), Vec3(-0.01, 0.3, 0.3), Vec3(-0.2, 0.9, 0.3), Vec3(-0.19, 0.5, 0.9),
                   Vec3(0.15, 0.1, 0.3), Vec3(0.7, 0.1, 0.3),   Vec3(0.4, 0.1, 0.75), Vec3(0.35, 0.9, 0.45)};
    in.init();
    MeshTopology topo;
    topo.set_tetrahedra({{0, 1, 2, 3}, {4, 5, 6, 7}});
    const std::vector<Vec3> pts = {Vec3(0.02, 0.5, 0.45)};
    BarycentricMapping hashed(in, out), exhaustive(in, out);
    hashed.map_on_set_tetrahedra(topo, in.position, pts);
    exhaustive.map_on_tetrahedra(topo, in.position, pts);
    EXPECT_EQ(hashed.weights()[0][0].index, 4);
    EXPECT_EQ(exhaustive.weights()[0][0].index, 0);
    // moved away from B's cell by two cells along x: no element in its cell, the exhaustive search
    const std::vector<Vec3> far = {Vec3(2.0, 0.5, 0.45)};
    hashed.map_on_set_tetrahedra(topo, in.position, far);
    exhaustive.map_on_tetrahedra(topo, in.position, far);
    EXPECT_EQ(hashed.weights()[0][0].index, exhaustive.weights()[0][0].index);
}

TEST(Mapping, BarycentricOnSetTetrahedraEqualsTheMeshMapperInsideTheElements) {
    // a point inside a tetrahedron is in its cell: the hash search finds the exhaustive one's
    // element and weights (the same bits); 2000 points of a jittered 3×3×3 grid of 5-tetra cubes,
    // 20 % of them outside the body, where the two may differ
    std::mt19937 g(20261129);
    std::uniform_real_distribution<double> jitter(-0.12, 0.12), box(-0.25, 3.25);
    Vec3Object in, out;
    const auto id = [](int i, int j, int k) { return PointId(i + 4 * (j + 4 * k)); };
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) in.position.push_back(Vec3(i + jitter(g), j + jitter(g), k + jitter(g)));
    in.init();
    std::vector<Tetrahedron> tets;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                const PointId c[8] = {
                    id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
                    id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
                for (const auto& t :
                     {std::array<int, 4>{0, 1, 3, 4}, {1, 2, 3, 6}, {1, 4, 5, 6}, {3, 4, 6, 7}, {1, 3, 4, 6}})
                    tets.push_back({c[t[0]], c[t[1]], c[t[2]], c[t[3]]});
            }
    MeshTopology topo;
    topo.set_tetrahedra(tets);
    std::vector<Vec3> pts(2000);
    for (Vec3& p : pts) p = Vec3(box(g), box(g), box(g));
    BarycentricMapping hashed(in, out), exhaustive(in, out);
    hashed.map_on_set_tetrahedra(topo, in.position, pts);
    exhaustive.map_on_tetrahedra(topo, in.position, pts);
    int inside = 0, differ_outside = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        bool same = true;
        for (int k = 0; k < 4; ++k)
            same = same && hashed.weights()[i][std::size_t(k)].index == exhaustive.weights()[i][std::size_t(k)].index &&
                   test::same_bits(hashed.weights()[i][std::size_t(k)].weight,
                                   exhaustive.weights()[i][std::size_t(k)].weight);
        double least = 0;  // inside when every weight of the exhaustive element is ≥ 0
        for (int k = 0; k < 4; ++k) least = std::min(least, exhaustive.weights()[i][std::size_t(k)].weight);
        if (least >= 0) {
            ++inside;
            EXPECT_TRUE(same) << "point " << i;
        } else if (!same) {
            ++differ_outside;
        }
    }
    EXPECT_GT(inside, 1000);       // the cube holds (3.0/3.5)³ ≈ 63 % of the box
    EXPECT_GT(differ_outside, 0);  // outside, the hash grid's choice is not always the nearest centre
}

/// The unit cube (SOFA's hexahedron numbering) and, with `second`, the cube beside it along x.
std::vector<Vec3> set_mapper_cubes() {
    return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, 0, 1),
            Vec3(1, 1, 1), Vec3(0, 1, 1), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(2, 0, 1), Vec3(2, 1, 1)};
}

TEST(BarycentricSetMapper, HexahedronWeightsAreTrilinearInTheCubesCoordinates) {
    Vec3Object in, out;
    in.position = set_mapper_cubes();
    in.init();
    MeshTopology topo;
    topo.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}, {1, 8, 9, 2, 5, 10, 11, 6}});
    // (0.25, 0.5, 0.75) in the first cube; (1.5, 0.25, 0.5) in the second, b = (0.5, 0.25, 0.5)
    const std::vector<Vec3> points{Vec3(0.25, 0.5, 0.75), Vec3(1.5, 0.25, 0.5)};
    BarycentricMapping map(in, out);
    map.map_on_set_hexahedra(topo, in.position, points);
    ASSERT_EQ(map.weights().size(), 2U);
    const std::array<double, 8> first{0.75 * 0.5 * 0.25, 0.25 * 0.5 * 0.25, 0.25 * 0.5 * 0.25, 0.75 * 0.5 * 0.25,
                                      0.75 * 0.5 * 0.75, 0.25 * 0.5 * 0.75, 0.25 * 0.5 * 0.75, 0.75 * 0.5 * 0.75};
    const std::array<double, 8> second{0.5 * 0.75 * 0.5, 0.5 * 0.75 * 0.5, 0.5 * 0.25 * 0.5, 0.5 * 0.25 * 0.5,
                                       0.5 * 0.75 * 0.5, 0.5 * 0.75 * 0.5, 0.5 * 0.25 * 0.5, 0.5 * 0.25 * 0.5};
    const std::array<Index, 8> second_points{1, 8, 9, 2, 5, 10, 11, 6};
    ASSERT_EQ(map.weights()[0].size(), 8U);
    ASSERT_EQ(map.weights()[1].size(), 8U);
    for (std::size_t k = 0; k < 8; ++k) {
        EXPECT_EQ(map.weights()[0][k].index, Index(k));
        EXPECT_EQ(map.weights()[0][k].weight, first[k]) << k;
        EXPECT_EQ(map.weights()[1][k].index, second_points[k]);
        EXPECT_EQ(map.weights()[1][k].weight, second[k]) << k;
    }
    out.position = points;
    out.init();
    map.init();
    map.apply_position();
    EXPECT_EQ(out.position[0], points[0]);
    EXPECT_EQ(out.position[1], points[1]);
}

// Outside both cubes the score is |p − centre|²: (1.75, 0.5, -3) is nearer the second cube's centre
// (1.5, 0.5, 0.5) than the first's; its cell holds no element, so every element is searched.
TEST(BarycentricSetMapper, AHexahedronOutsidePointGoesToTheNearestCentre) {
    Vec3Object in, out;
    in.position = set_mapper_cubes();
    in.init();
    MeshTopology topo;
    topo.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}, {1, 8, 9, 2, 5, 10, 11, 6}});
    const std::vector<Vec3> points{Vec3(1.75, 0.5, -3), Vec3(0.25, 0.5, -3)};
    BarycentricMapping map(in, out);
    map.map_on_set_hexahedra(topo, in.position, points);
    EXPECT_EQ(map.weights()[0][0].index, 1);  // the second cube's vertex 0
    EXPECT_EQ(map.weights()[1][0].index, 0);
    // b = (0.75, 0.5, -3) in the second cube: the trilinear weights, extrapolated
    EXPECT_EQ(map.weights()[0][0].weight, 0.25 * 0.5 * 4.0);
    EXPECT_EQ(map.weights()[0][6].weight, 0.75 * 0.5 * -3.0);
}

std::string set_mapper_refusal(const MeshTopology& topo, const std::vector<Vec3>& x, bool hexahedra) {
    Vec3Object in, out;
    in.position = x;
    in.init();
    BarycentricMapping map(in, out);
    const std::vector<Vec3> points{Vec3(0.1, 0.1, 0.1)};
    try {
        if (hexahedra) map.map_on_set_hexahedra(topo, x, points);
        else map.map_on_set_tetrahedra(topo, x, points);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(BarycentricSetMapper, RefusesWhatItCannotMapNamingTheCause) {
    const std::vector<Vec3> cube = set_mapper_cubes();
    MeshTopology none;
    none.set_edges({{0, 1}});
    EXPECT_EQ(set_mapper_refusal(none, cube, false), "BarycentricMapping: topology has no tetrahedron");
    EXPECT_EQ(set_mapper_refusal(none, cube, true), "BarycentricMapping: topology has no hexahedron");
    MeshTopology flat;  // vertex 4 on the plane of 0, 1, 3
    flat.set_hexahedra({{0, 1, 2, 3, 2, 5, 6, 7}});
    EXPECT_EQ(set_mapper_refusal(flat, cube, true),
              "BarycentricMapping: hexahedron 0 is degenerate (its edges from vertex 0 are coplanar)");
    MeshTopology outside;
    outside.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 12}});
    EXPECT_EQ(set_mapper_refusal(outside, cube, true), "BarycentricMapping: hexahedron 0 vertex out of range");
    MeshTopology far_edge;
    far_edge.set_tetrahedra({{0, 1, 3, 4}});
    far_edge.set_edges({{0, 20}});
    EXPECT_EQ(set_mapper_refusal(far_edge, cube, false), "BarycentricMapping: an edge's vertex is out of range");
    MeshTopology zero_edges;  // the listed edges (not the tetrahedron's) give the grid's cell: 0 long
    zero_edges.set_tetrahedra({{0, 1, 3, 4}});
    zero_edges.set_edges({{0, 0}});
    EXPECT_EQ(set_mapper_refusal(zero_edges, cube, false),
              "BarycentricMapping: the elements' mean edge length is 0 (SOFA's hash grid needs a positive one)");
    // the cubes moved 10¹² m away: more unit cells from the origin than an int counts (SOFA's
    // getGridIndices would overflow)
    std::vector<Vec3> far = cube;
    for (Vec3& p : far) p += Vec3(1e12, 0, 0);
    MeshTopology far_tetra;
    far_tetra.set_tetrahedra({{0, 1, 3, 4}});
    EXPECT_EQ(set_mapper_refusal(far_tetra, far, false),
              "BarycentricMapping: a point at (1000000000000, 0, 0) has no cell in SOFA's hash grid of cell "
              "1.2071067811865475 m");
}

}  // namespace
}  // namespace penalty
