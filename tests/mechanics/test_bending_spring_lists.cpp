// Spring lists of QuadularBendingSprings, TriangleBendingSprings and QuadBendingSprings (SOFA's
// springs, order and rest lengths, on meshes made here), and the derivatives of the force of
// each (SpringForceField law, QuadularBendingSprings' arithmetic).
#include "penalty/mechanics/bending_spring_lists.hpp"
#include "penalty/mechanics/bending_springs.hpp"

#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>

namespace penalty {
namespace {

/// A 3×3-vertex grid in the x-y plane, spacing 1 in x and 1.5 in y, vertex i + 3 j at (i, 1.5 j):
///   6 7 8
///   3 4 5
///   0 1 2
/// quads q0 = (0,1,4,3), q1 = (1,2,5,4), q2 = (3,4,7,6), q3 = (4,5,8,7), counter-clockwise.
std::vector<Vec3> grid_points() {
    std::vector<Vec3> x;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) x.emplace_back(i, 1.5 * j, 0.0);
    return x;
}

MeshTopology grid_quads() {
    MeshTopology topo;
    topo.set_quads({{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}});
    return topo;
}

using Pair = std::pair<PointId, PointId>;

std::vector<Pair> ends(const std::vector<Spring>& springs) {
    std::vector<Pair> out;
    for (const Spring& s : springs) out.emplace_back(s.a, s.b);
    return out;
}

TEST(QuadularBendingSprings, TwoSpringsPerSharedEdgeInEdgeOrder) {
    const auto x = grid_points();
    const MeshTopology topo = grid_quads();
    // Worked by hand from QuadularBendingSprings::applyQuadCreation (edge j of a quad is
    // (q[j+1], q[j+2]); q2 = the lower quad around the edge, q1 the other):
    //   edge {1,4}: q2 = q0 (i2 = 0), q1 = q1 (i1 = 2): (q1[2], q0[3]) = (5,3), (q1[1], q0[0]) = (2,0)
    //   edge {3,4}: q2 = q0 (i2 = 1), q1 = q2 (i1 = 3): (6,0), (7,1)
    //   edge {4,5}: q2 = q1 (i2 = 1), q1 = q3 (i1 = 3): (7,1), (8,2)   — (7,1) twice: SOFA keeps both
    //   edge {4,7}: q2 = q2 (i2 = 0), q1 = q3 (i1 = 2): (8,6), (5,3)
    // in the topology's edge order.
    std::vector<std::pair<std::int32_t, std::vector<Pair>>> by_edge = {
        {topo.edge_index(1, 4), {{5, 3}, {2, 0}}},
        {topo.edge_index(3, 4), {{6, 0}, {7, 1}}},
        {topo.edge_index(4, 5), {{7, 1}, {8, 2}}},
        {topo.edge_index(4, 7), {{8, 6}, {5, 3}}},
    };
    std::sort(by_edge.begin(), by_edge.end());
    std::vector<Pair> expected;
    for (const auto& [edge, pairs] : by_edge) {
        ASSERT_GE(edge, 0);
        expected.insert(expected.end(), pairs.begin(), pairs.end());
    }
    const auto springs = quadular_bending_springs(topo, x, 3000.0, 1.0);
    EXPECT_EQ(ends(springs), expected);
    for (const Spring& s : springs) {
        const bool horizontal = x[static_cast<std::size_t>(s.a)].y() == x[static_cast<std::size_t>(s.b)].y();
        EXPECT_DOUBLE_EQ(s.rest_length, horizontal ? 2.0 : 3.0) << s.a << "-" << s.b;
        EXPECT_EQ(s.ks, 3000.0);
        EXPECT_EQ(s.kd, 1.0);
    }
    // rest lengths as SOFA: |x_a − x_b| from the given (rest) positions
    auto moved = x;
    moved[5].z() = 0.5;
    const auto springs2 = quadular_bending_springs(topo, moved, 1.0, 0.0);
    for (const Spring& s : springs2)
        EXPECT_EQ(s.rest_length, (moved[static_cast<std::size_t>(s.a)] - moved[static_cast<std::size_t>(s.b)]).norm());
    EXPECT_THROW((void)quadular_bending_springs(topo, std::span<const Vec3>(x).first(6), 1.0, 0.0),
                 std::invalid_argument);
}

TEST(QuadularBendingSprings, NoSpringOnBorderEdgesOrWithoutQuads) {
    MeshTopology one;
    one.set_quads({{0, 1, 2, 3}});
    const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    EXPECT_TRUE(quadular_bending_springs(one, x, 1.0, 0.0).empty());
    MeshTopology triangles;
    triangles.set_triangles({{0, 1, 2}, {0, 2, 3}});
    EXPECT_TRUE(quadular_bending_springs(triangles, x, 1.0, 0.0).empty());
}

TEST(TriangleBendingSprings, OneSpringPerLaterFaceOnAnEdgeQuadsSplit) {
    // t0 = (0,1,2), t1 = (1,3,2), quad (2,3,5,4) → faces (2,3,5), (2,5,4).
    // TriangleBendingSprings::registerTriangle, faces in order, edges {a,b}, {b,c}, {c,a}:
    //   t1's {2,1}: opposite 3, first face's opposite 0       → spring (3, 0)
    //   (2,3,5)'s {2,3}: opposite 5, t1's opposite 1          → spring (5, 1)
    //   (2,5,4)'s {2,5}: opposite 4, (2,3,5)'s opposite 3     → spring (4, 3)
    const std::vector<Vec3> x = {Vec3(0, 0, 0),   Vec3(1, 0, 0), Vec3(0, 1, 0),
                                 Vec3(1, 1, 0.3), Vec3(0, 2, 0), Vec3(1, 2, -0.2)};
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}, {1, 3, 2}});
    topo.set_quads({{2, 3, 5, 4}});
    const auto springs = triangle_bending_springs(topo, x, 100.0, 0.1);
    EXPECT_EQ(ends(springs), (std::vector<Pair>{{3, 0}, {5, 1}, {4, 3}}));
    for (const Spring& s : springs) {
        EXPECT_EQ(s.rest_length, (x[static_cast<std::size_t>(s.a)] - x[static_cast<std::size_t>(s.b)]).norm());
        EXPECT_EQ(s.ks, 100.0);
        EXPECT_EQ(s.kd, 0.1);
    }
    // a third face on an edge adds a spring to the first face's opposite vertex
    MeshTopology fin;
    fin.set_triangles({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
    const std::vector<Vec3> y = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)};
    EXPECT_EQ(ends(triangle_bending_springs(fin, y, 1.0, 0.0)), (std::vector<Pair>{{3, 2}, {4, 2}}));
}

TEST(QuadBendingSprings, TwoSpringsPerSharedEdgeEachPairOnce) {
    const auto x = grid_points();
    const MeshTopology topo = grid_quads();
    // QuadBendingSprings::registerEdge, worked by hand: q1's edge {1,4} meets q0's → (2,0), (5,3);
    // q2's {3,4} meets q0's → (6,0), (7,1); q3's {4,5} meets q1's → (7,1) again (skipped), (8,2);
    // q3's {4,7} meets q2's → (5,3) again (skipped), (8,6).
    const auto springs = quad_bending_springs(topo, x, 20.0, 0.0);
    EXPECT_EQ(ends(springs), (std::vector<Pair>{{2, 0}, {5, 3}, {6, 0}, {7, 1}, {8, 2}, {8, 6}}));
    for (const Spring& s : springs) {
        EXPECT_EQ(s.rest_length, (x[static_cast<std::size_t>(s.a)] - x[static_cast<std::size_t>(s.b)]).norm());
        EXPECT_EQ(s.ks, 20.0);
    }
    // localRange: both ends below 3 (the spring (2,0)) or both above 7 (none) are skipped
    EXPECT_EQ(ends(quad_bending_springs(topo, x, 20.0, 0.0, {.first = 3, .last = 7})),
              (std::vector<Pair>{{5, 3}, {6, 0}, {7, 1}, {8, 2}, {8, 6}}));
    EXPECT_EQ(ends(quad_bending_springs(topo, x, 20.0, 0.0, {.first = -1, .last = 5})),
              (std::vector<Pair>{{2, 0}, {5, 3}, {6, 0}, {7, 1}, {8, 2}}));
}

/// The folded grid: the centre row lifted, corners pushed, so that every spring is stretched or
/// compressed.
void fold(Vec3Object& s) {
    s.position[3].z() = 0.4;
    s.position[4].z() = 0.7;
    s.position[5].z() = 0.3;
    s.position[8] += Vec3(0.2, -0.1, 0.05);
}

TEST(QuadularBendingSprings, ForceDerivativesMatchFiniteDifferences) {
    Vec3Object s;
    s.position = grid_points();
    s.init();
    const MeshTopology topo = grid_quads();
    SpringForceField ff(s);
    ff.set_null_length(kBendingSpringNullLength);
    ff.set_arithmetic(SpringArithmetic::quadular_bending_springs);
    for (const Spring& sp : quadular_bending_springs(topo, s.rest_position, 3000.0, 0.0)) ff.add_spring(sp);
    ff.init();
    fold(s);
    const auto d = test::check_force_field_derivatives(ff, s, {1e-6, 1e-12, 1e-6});
    EXPECT_GT(d.force.norm(), 10.0);
    EXPECT_GT(d.k_dforce.norm(), 100.0);
    // the two operation orders are the same law: equal up to rounding
    SpringForceField plain(s);
    plain.set_null_length(kBendingSpringNullLength);
    for (const Spring& sp : ff.springs()) plain.add_spring(sp);
    plain.init();
    const auto e = test::check_force_field_derivatives(plain, s, {1e-6, 1e-12, 1e-6});
    EXPECT_LT((e.force - d.force).cwiseAbs().maxCoeff(), 1e-12 * d.force.cwiseAbs().maxCoeff());
    EXPECT_LT((e.k_dforce - d.k_dforce).cwiseAbs().maxCoeff(), 1e-12 * d.k_dforce.cwiseAbs().maxCoeff());
}

TEST(TriangleAndQuadBendingSprings, ForceDerivativesMatchFiniteDifferences) {
    for (const bool quads : {false, true}) {
        Vec3Object s;
        s.position = grid_points();
        s.init();
        const MeshTopology topo = grid_quads();
        SpringForceField ff(s);
        const auto springs = quads ? quad_bending_springs(topo, s.position, 20.0, 0.0)
                                   : triangle_bending_springs(topo, s.position, 100.0, 0.0);
        for (const Spring& sp : springs) ff.add_spring(sp);
        ff.init();
        fold(s);
        const auto d = test::check_force_field_derivatives(ff, s, {1e-6, 1e-12, 1e-6});
        EXPECT_GT(d.force.norm(), 1.0) << (quads ? "QuadBendingSprings" : "TriangleBendingSprings");
    }
}

}  // namespace
}  // namespace penalty
