// SOFA's ray–triangle test and TriangleOctree (triangle_octree.cpp): the ray test's closed form,
// the cells a triangle is stored in, the walk against the brute-force nearest hit, and the walk's
// first-cell answer where a later cell holds a nearer hit.
#include "penalty/collision/ray_trace_narrow_phase.hpp"

#include "detection_scenes.hpp"

#include <gtest/gtest.h>

#include <random>

namespace penalty {
namespace {

std::vector<Triangle> octree_triangles_of(const MeshTopology& topo) {
    return {topo.triangles().begin(), topo.triangles().end()};
}

TEST(RayTriangleHit, ClosedFormOnTheUnitTriangle) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    double t = 0, u = 0, v = 0;
    ASSERT_TRUE(ray_triangle_hit(a, b, c, Vec3(0.2, 0.3, 2.0), Vec3(0, 0, -0.5), t, u, v));
    EXPECT_DOUBLE_EQ(t, 4.0);  // the ray's parameter, in units of its direction
    EXPECT_DOUBLE_EQ(u, 0.2);
    EXPECT_DOUBLE_EQ(v, 0.3);
    EXPECT_FALSE(ray_triangle_hit(a, b, c, Vec3(0.2, 0.3, 2.0), Vec3(0, 0, 1), t, u, v));   // behind
    EXPECT_FALSE(ray_triangle_hit(a, b, c, Vec3(0.8, 0.3, 2.0), Vec3(0, 0, -1), t, u, v));  // u + v > 1
    EXPECT_FALSE(ray_triangle_hit(a, b, c, Vec3(0.2, 0.3, 2.0), Vec3(1, 0, 0), t, u, v));   // parallel
    EXPECT_FALSE(ray_triangle_hit(a, b, c, Vec3(0.2, 0.3, 0.0), Vec3(0, 0, -1), t, u, v));  // t = 0 < ε
}

TEST(TriangleOctree, WalkFindsTheNearestHitOfTheFirstCellWithOne) {
    std::mt19937 g(20261129);
    const auto torus = test::make_torus(24, 12, 3.0, 1.0, Vec3(0.5, -0.25, 0.3), g, 0.2);
    const std::vector<Triangle> tris = octree_triangles_of(torus->topo);
    TriangleOctree tree;
    tree.build(torus->state.position, tris);
    ASSERT_GT(tree.node_count(), 8u);
    std::uniform_real_distribution<double> coordinate(-4.5, 4.5);
    std::normal_distribution<double> gauss(0.0, 1.0);
    int rays_hitting = 0, found = 0, same = 0;
    for (int r = 0; r < 3000; ++r) {
        const Vec3 origin(coordinate(g), coordinate(g), coordinate(g) * 0.4);
        const Vec3 direction(gauss(g), gauss(g), gauss(g));
        const RayHit reference = tree.nearest_hit(origin, direction);
        const RayHit hit = tree.trace(origin, direction);
        if (reference.triangle < 0) {
            EXPECT_LT(hit.triangle, 0) << "ray " << r;  // no triangle is hit: the walk finds none
            continue;
        }
        ++rays_hitting;
        if (hit.triangle < 0) continue;
        ++found;
        // a real hit, never nearer than the nearest
        double t = 0, u = 0, v = 0;
        const Triangle& tri = tris[std::size_t(hit.triangle)];
        ASSERT_TRUE(ray_triangle_hit(torus->state.position[tri[0]], torus->state.position[tri[1]],
                                     torus->state.position[tri[2]], origin, direction, t, u, v));
        EXPECT_EQ(t, hit.t);
        EXPECT_EQ(u, hit.u);
        EXPECT_EQ(v, hit.v);
        EXPECT_GE(hit.t, reference.t);
        same += hit.t == reference.t ? 1 : 0;
    }
    ASSERT_GT(rays_hitting, 1000);
    // every ray that hits the torus finds a triangle; nearly always the nearest one
    EXPECT_EQ(found, rays_hitting);
    EXPECT_GT(double(same) / rays_hitting, 0.99) << same << " of " << rays_hitting;
}

TEST(TriangleOctree, RaysAlongAnAxisWithNegativeZeroComponents) {
    // SOFA's trace sets a zero direction component to +0 (its EPSILON): a −0 (the negation of a
    // vertex normal (0, 0, −1)) must walk the same cells
    const std::vector<Vec3> x = {Vec3(-1, -1, 1), Vec3(1, -1, 1), Vec3(0, 1, 1)};
    const std::vector<Triangle> tris = {Triangle{0, 1, 2}};
    TriangleOctree tree;
    tree.build(x, tris);
    for (const Vec3& d : {Vec3(-0.0, -0.0, 1.0), Vec3(0.0, -0.0, 1.0), Vec3(-0.0, 0.0, 1.0), Vec3(0.0, 0.0, 1.0)}) {
        const RayHit hit = tree.trace(Vec3(-0.1, 0.05, 0.6), d);
        EXPECT_EQ(hit.triangle, 0) << d.transpose();
        EXPECT_DOUBLE_EQ(hit.t, 0.4);
    }
}

TEST(TriangleOctree, ATriangleIsStoredInTheCellsItsBoxsGridPointsFallIn) {
    // extent 90: depth ⌊log2(1600/90)⌋ = 4, cells of 100; the box x ∈ [10, 100] has the grid
    // points x = 0 and x = 100 (≤ hi, the cell it only touches included), y and z one each:
    // the root, one node at depths 1 to 3 ([0,800), [0,400), [0,200)) and two at depth 4
    const std::vector<Vec3> x = {Vec3(10, 10, 10), Vec3(100, 10, 10), Vec3(10, 50, 10)};
    const std::vector<Triangle> tris = {Triangle{0, 1, 2}};
    TriangleOctree tree;
    tree.build(x, tris);
    EXPECT_EQ(tree.node_count(), 6u);
    // moved by 1e-9 below x = 100: one cell at depth 4
    const std::vector<Vec3> inside = {Vec3(10, 10, 10), Vec3(100 - 1e-9, 10, 10), Vec3(10, 50, 10)};
    tree.build(inside, tris);
    EXPECT_EQ(tree.node_count(), 5u);
    // a triangle of extent 45 (depth 5, cells of 50) at the other corner of the cube, [−800, −750)
    const std::vector<Vec3> corner = {Vec3(-799, -799, -799), Vec3(-754, -799, -799), Vec3(-799, -760, -799)};
    tree.build(corner, tris);
    EXPECT_EQ(tree.node_count(), 6u);
    const RayHit hit = tree.trace(Vec3(-790, -790, -700), Vec3(0, 0, -1));
    EXPECT_EQ(hit.triangle, 0);
    EXPECT_DOUBLE_EQ(hit.t, 99.0);
}

TEST(TriangleOctree, ATriangleOutsideTheCubeIsNotStored) {
    // a vertex at x = 801, beyond SOFA's cube [−800, 800]³: the tree keeps the root only and the
    // walk finds nothing, where the brute-force hit finds the triangle
    const std::vector<Vec3> x = {Vec3(700, 0, 0), Vec3(801, 0, 0), Vec3(700, 50, 0)};
    const std::vector<Triangle> tris = {Triangle{0, 1, 2}};
    TriangleOctree tree;
    tree.build(x, tris);
    EXPECT_EQ(tree.node_count(), 1u);
    const Vec3 origin(710, 10, 5);
    const Vec3 down(0, 0, -1);
    EXPECT_EQ(tree.nearest_hit(origin, down).triangle, 0);
    EXPECT_EQ(tree.trace(origin, down).triangle, -1);
    // a ray that starts outside the cube and misses it: nothing
    EXPECT_EQ(tree.trace(Vec3(900, 900, 900), Vec3(1, 0, 0)).triangle, -1);
}

TEST(TriangleOctree, TheFirstCellsHitWinsOverANearerHitInALaterCell) {
    // cells of 100 (extents 90 and 85, depth 4). Triangle 0 spans the cells x ∈ [0,100) and
    // [100,200) (box x ∈ [90,180]) and meets the ray y = z = 50.5 along +x at
    // x = 90 + 7650·44.5/7225 ≈ 137.1; triangle 1, in the plane x = 110, lies in [100,200) only.
    // The walk stops in the first cell with a hit, [0,100): triangle 0, although triangle 1 is
    // nearer (SOFA's TriangleOctree::trace)
    const std::vector<Vec3> x = {Vec3(90, 50, 95),  Vec3(180, 10, 10), Vec3(180, 95, 10),
                                 Vec3(110, 10, 10), Vec3(110, 95, 10), Vec3(110, 50, 95)};
    const std::vector<Triangle> tris = {Triangle{0, 1, 2}, Triangle{3, 4, 5}};
    TriangleOctree tree;
    tree.build(x, tris);
    const Vec3 origin(-50, 50.5, 50.5);
    const Vec3 along(1, 0, 0);
    const RayHit nearest = tree.nearest_hit(origin, along);
    EXPECT_EQ(nearest.triangle, 1);
    EXPECT_DOUBLE_EQ(nearest.t, 160.0);
    const RayHit walked = tree.trace(origin, along);
    EXPECT_EQ(walked.triangle, 0);
    EXPECT_NEAR(walked.t, 140.0 + 7650.0 * 44.5 / 7225.0, 1e-12);
    // from inside [100,200), the walk starts there: triangle 1
    const RayHit later = tree.trace(Vec3(105, 50.5, 50.5), along);
    EXPECT_EQ(later.triangle, 1);
    EXPECT_DOUBLE_EQ(later.t, 5.0);
}

}  // namespace
}  // namespace penalty
