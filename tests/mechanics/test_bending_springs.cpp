// TriangularBendingSprings: SOFA's spring list (ends, order, rest lengths) and the derivatives of
// its force.
#include "penalty/mechanics/bending_springs.hpp"

#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

TEST(TriangularBendingSprings, OneSpringPerSharedEdgeBetweenTheOppositeVertices) {
    // A fan around vertex 0: triangles (0,1,2), (0,2,3), (0,3,4), and a lone triangle (5,6,7).
    // Edges from triangles (edge opposite vertex j = (t[j+1], t[j+2])): the shared ones are
    // (0,2) and (0,3); for each, m1 = opposite vertex in the higher-index triangle, m2 in the lower.
    const std::vector<Vec3> x0 = {Vec3(0, 0, 0),    Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                                  Vec3(-1, 1, 0.5), Vec3(5, 0, 0), Vec3(6, 0, 0), Vec3(5, 1, 0)};
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {5, 6, 7}});
    const auto springs = triangular_bending_springs(topo, x0, 300.0, 2.0);
    ASSERT_EQ(springs.size(), 2u);
    // edge order: the topology's edges; the first shared edge met is (2,0) of triangle 0
    EXPECT_EQ(springs[0].a, 3);
    EXPECT_EQ(springs[0].b, 1);
    EXPECT_EQ(springs[1].a, 4);
    EXPECT_EQ(springs[1].b, 2);
    EXPECT_DOUBLE_EQ(springs[0].rest_length, std::sqrt(2.0));
    EXPECT_DOUBLE_EQ(springs[1].rest_length, (x0[4] - x0[2]).norm());
    EXPECT_EQ(springs[0].ks, 300.0);
    EXPECT_EQ(springs[0].kd, 2.0);
    EXPECT_THROW((void)triangular_bending_springs(topo, std::span<const Vec3>(x0).first(4), 1.0, 0.0),
                 std::invalid_argument);
}

TEST(TriangularBendingSprings, ForceDerivativesMatchFiniteDifferences) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(-1, 1, 0.5)};
    s.init();
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}});
    SpringForceField ff(s);
    ff.set_null_length(kBendingSpringNullLength);
    for (const Spring& sp : triangular_bending_springs(topo, s.rest_position, 300.0, 0.0)) ff.add_spring(sp);
    ff.init();
    // fold the fan: the springs are stretched or compressed, the tangent is exact (no damping)
    s.position[1].z() = 0.4;
    s.position[4].z() = -0.3;
    const auto d = test::check_force_field_derivatives(ff, s, {1e-6, 1e-12, 1e-6});
    EXPECT_GT(d.force.norm(), 1.0);
    // a spring shorter than the null length (1e-4 m) gives nothing
    s.position[3] = s.position[1] + Vec3(5e-5, 0, 0);
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    ff.accumulate_force();
    EXPECT_EQ(s.force[3], Vec3::Zero());
}

}  // namespace
}  // namespace penalty
