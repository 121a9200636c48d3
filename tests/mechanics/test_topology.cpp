#include "penalty/mechanics/topology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>

namespace penalty {
namespace {

using IdList = std::vector<std::int32_t>;

TEST(MeshTopology, SurfaceEdgesKeepTriangleOrientationInFirstOccurrenceOrder) {
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}, {0, 2, 3}});
    EXPECT_EQ(topo.num_points(), 4u);
    const std::vector<Edge> expected{{1, 2}, {2, 0}, {0, 1}, {2, 3}, {3, 0}};
    EXPECT_EQ(topo.edges(), expected);
    ASSERT_EQ(topo.edges_in_triangle().size(), 2u);
    EXPECT_EQ(topo.edges_in_triangle()[0], (std::array<std::int32_t, 3>{0, 1, 2}));
    EXPECT_EQ(topo.edges_in_triangle()[1], (std::array<std::int32_t, 3>{3, 4, 1}));
    // Edge 1 = (2,0) runs along triangle 0 (left side, front) and against triangle 1 (back).
    EXPECT_EQ(topo.triangles_around_edge()[1], (IdList{0, 1}));
    EXPECT_EQ(topo.triangles_around_vertex()[0], (IdList{0, 1}));
    EXPECT_EQ(topo.triangles_around_vertex()[3], (IdList{1}));
    EXPECT_EQ(topo.edges_around_vertex()[0], (IdList{1, 2, 4}));
    EXPECT_EQ(topo.vertices_around_vertex()[0], (std::vector<PointId>{2, 1, 3}));
    EXPECT_TRUE(topo.quads().empty());
    EXPECT_FALSE(topo.has_volume());
}

TEST(MeshTopology, TriangleAlongAnExistingEdgeIsInsertedFirstAroundIt) {
    // Triangle 1 is oriented inconsistently: it runs along edge (2,0) like triangle 0, so SOFA
    // inserts it at the front of trianglesAroundEdge and it owns the edge.
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}, {0, 3, 2}});
    EXPECT_EQ(topo.edges()[1], (Edge{2, 0}));
    EXPECT_EQ(topo.edges_in_triangle()[1][1], 1);
    EXPECT_EQ(topo.triangles_around_edge()[1], (IdList{1, 0}));
}

TEST(MeshTopology, QuadEdgesAreSortedAndFollowTriangleEdges) {
    MeshTopology topo;
    topo.set_triangles({{4, 1, 0}});
    topo.set_quads({{0, 1, 2, 3}});
    // triangle: (1,0), (0,4), (4,1); quad: (1,2), (2,3), (3,0)->(0,3), (0,1) already known.
    const std::vector<Edge> expected{{1, 0}, {0, 4}, {4, 1}, {1, 2}, {2, 3}, {0, 3}};
    EXPECT_EQ(topo.edges(), expected);
    EXPECT_EQ(topo.edges_in_quad()[0], (std::array<std::int32_t, 4>{3, 4, 5, 0}));
    EXPECT_EQ(topo.quads_around_edge()[0], (IdList{0}));
    EXPECT_EQ(topo.quads_around_vertex()[2], (IdList{0}));
}

TEST(MeshTopology, TetrahedraGiveSortedEdgesAndRotatedOutwardFaces) {
    MeshTopology topo;
    topo.set_tetrahedra({{0, 1, 2, 3}, {4, 1, 3, 2}});
    const std::vector<Edge> edges{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}, {1, 4}, {3, 4}, {2, 4}};
    EXPECT_EQ(topo.edges(), edges);
    // Shared face (1,2,3) appears once; tetra 1's faces rotated to start at their smallest vertex.
    const std::vector<Triangle> triangles{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}, {2, 3, 4}, {1, 2, 4}, {1, 4, 3}};
    EXPECT_EQ(topo.triangles(), triangles);
    EXPECT_TRUE(topo.quads().empty());
    EXPECT_EQ(topo.tetrahedra_around_vertex()[1], (IdList{0, 1}));
    EXPECT_EQ(topo.tetrahedra_around_vertex()[4], (IdList{1}));
    // edges_in_triangle of (1,4,3): opposite 1 -> (4,3) = edge 7, opposite 4 -> (3,1) = 4, opposite 3 -> (1,4) = 6
    EXPECT_EQ(topo.edges_in_triangle()[6], (std::array<std::int32_t, 3>{7, 4, 6}));
    EXPECT_EQ(topo.edge_index(4, 3), 7);
    EXPECT_EQ(topo.edge_index(0, 4), -1);
    EXPECT_TRUE(topo.has_volume());
}

TEST(MeshTopology, HexahedraGiveSharedQuadsOnce) {
    // 3 x 2 x 2 grid of points (index = i + 3 j + 6 k), two hexahedra along x.
    MeshTopology topo;
    topo.set_hexahedra({{0, 1, 4, 3, 6, 7, 10, 9}, {1, 2, 5, 4, 7, 8, 11, 10}});
    const auto& quads = topo.quads();
    ASSERT_EQ(quads.size(), 11u);
    EXPECT_EQ(quads[0], (Quad{0, 3, 4, 1}));
    EXPECT_EQ(quads[1], (Quad{6, 7, 10, 9}));
    EXPECT_EQ(quads[2], (Quad{0, 1, 7, 6}));
    EXPECT_EQ(quads[3], (Quad{1, 4, 10, 7}));  // shared with hexa 1 (its face 5)
    EXPECT_EQ(quads[4], (Quad{3, 9, 10, 4}));
    EXPECT_EQ(quads[5], (Quad{0, 6, 9, 3}));  // (3,0,6,9) rotated
    EXPECT_EQ(quads[6], (Quad{1, 4, 5, 2}));
    // 12 edges of hexa 0 (sorted), then the 8 new ones of hexa 1.
    const auto& edges = topo.edges();
    ASSERT_EQ(edges.size(), 20u);
    EXPECT_EQ(edges[0], (Edge{0, 1}));
    EXPECT_EQ(edges[1], (Edge{0, 3}));
    EXPECT_EQ(edges[2], (Edge{0, 6}));
    EXPECT_EQ(edges[11], (Edge{9, 10}));
    EXPECT_EQ(edges[12], (Edge{1, 2}));  // hexa 1 edge (0,1) = (1,2)
    EXPECT_TRUE(topo.triangles().empty());
    EXPECT_EQ(topo.hexahedra_around_vertex()[4], (IdList{0, 1}));
}

TEST(MeshTopology, GivenElementsTakePrecedenceOverDerivation) {
    MeshTopology topo;
    topo.set_tetrahedra({{0, 1, 2, 3}});
    topo.set_triangles({{0, 1, 2}});
    topo.set_edges({{3, 2}});
    EXPECT_EQ(topo.triangles(), (std::vector<Triangle>{{0, 1, 2}}));
    EXPECT_EQ(topo.edges(), (std::vector<Edge>{{3, 2}}));
    EXPECT_EQ(topo.edges_in_triangle()[0], (std::array<std::int32_t, 3>{-1, -1, -1}));
    topo.set_edges({});  // back to derivation
    EXPECT_EQ(topo.edges().size(), 6u);
}

TEST(MeshTopology, PointCountAndBadInput) {
    MeshTopology topo;
    topo.set_num_points(10);
    topo.set_triangles({{0, 1, 2}});
    EXPECT_EQ(topo.num_points(), 10u);
    EXPECT_EQ(topo.triangles_around_vertex().size(), 10u);
    EXPECT_THROW(topo.set_triangles({{0, -1, 2}}), std::invalid_argument);
    topo.set_num_points(2);
    EXPECT_THROW((void)topo.edges(), std::invalid_argument);
    MeshTopology empty;
    EXPECT_EQ(empty.num_points(), 0u);
    EXPECT_TRUE(empty.edges().empty());
}

TEST(MeshTopology, CopiesAreIndependentAfterModification) {
    MeshTopology a;
    a.set_triangles({{0, 1, 2}});
    EXPECT_EQ(a.edges().size(), 3u);
    MeshTopology b = a;
    b.set_triangles({{0, 1, 2}, {2, 1, 3}});
    EXPECT_EQ(a.edges().size(), 3u);
    EXPECT_EQ(b.edges().size(), 5u);
}

// Property: a randomly shuffled, consistently oriented tetrahedral grid of a cube is a ball,
// so V - E + F - T = 1, each face is stored once, and each tetra's edges and faces are found.
TEST(MeshTopology, RandomTetraGridsSatisfyEulerCharacteristic) {
    std::mt19937 rng(20240611);
    int checked = 0;
    for (int trial = 0; trial < 20; ++trial) {
        const int n = 1 + static_cast<int>(rng() % 3);  // cells per side
        const int np = n + 1;
        auto id = [np](int i, int j, int k) { return static_cast<PointId>(i + np * (j + np * k)); };
        std::vector<Tetrahedron> tetras;
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    // Kuhn split: one tetra per monotone path from corner (i,j,k) to the
                    // opposite corner, i.e. per permutation of the axes; made positive.
                    std::array<int, 3> axes{0, 1, 2};
                    do {
                        std::array<int, 3> c{i, j, k};
                        Tetrahedron t{};
                        std::array<std::array<int, 3>, 4> pos{};
                        pos[0] = c;
                        t[0] = id(c[0], c[1], c[2]);
                        for (int s = 0; s < 3; ++s) {
                            ++c[static_cast<std::size_t>(axes[static_cast<std::size_t>(s)])];
                            pos[static_cast<std::size_t>(s + 1)] = c;
                            t[static_cast<std::size_t>(s + 1)] = id(c[0], c[1], c[2]);
                        }
                        auto d = [&](int a, int b) {
                            return pos[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] -
                                   pos[0][static_cast<std::size_t>(b)];
                        };
                        const int vol = d(1, 0) * (d(2, 1) * d(3, 2) - d(2, 2) * d(3, 1)) -
                                        d(1, 1) * (d(2, 0) * d(3, 2) - d(2, 2) * d(3, 0)) +
                                        d(1, 2) * (d(2, 0) * d(3, 1) - d(2, 1) * d(3, 0));
                        if (vol < 0) std::swap(t[1], t[2]);
                        tetras.push_back(t);
                    } while (std::next_permutation(axes.begin(), axes.end()));
                }
        std::shuffle(tetras.begin(), tetras.end(), rng);
        MeshTopology topo;
        topo.set_tetrahedra(tetras);
        const auto V = static_cast<long>(topo.num_points());
        const auto E = static_cast<long>(topo.edges().size());
        const auto F = static_cast<long>(topo.triangles().size());
        const auto T = static_cast<long>(tetras.size());
        EXPECT_EQ(V, static_cast<long>(np) * np * np);
        EXPECT_EQ(V - E + F - T, 1) << "n=" << n;
        std::set<std::array<PointId, 3>> unique_faces;
        for (Triangle t : topo.triangles()) {
            EXPECT_LT(t[0], t[1]);
            EXPECT_LT(t[0], t[2]);
            std::sort(t.begin(), t.end());
            unique_faces.insert(t);
        }
        EXPECT_EQ(unique_faces.size(), topo.triangles().size());
        for (const auto& t : tetras)
            for (const auto& le : MeshTopology::kTetraEdges) {
                EXPECT_GE(topo.edge_index(t[le[0]], t[le[1]]), 0);
                ++checked;
            }
    }
    EXPECT_GT(checked, 20 * 6 * 6);
}

}  // namespace
}  // namespace penalty
