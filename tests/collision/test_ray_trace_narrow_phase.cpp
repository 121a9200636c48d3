// SOFA's RayTraceNarrowPhase and TriangleOctree (docs/components/ray_trace_narrow_phase.md): the
// ray test's closed form, the octree walk against the brute-force nearest hit, and the narrow
// phase against a brute-force reference of the same rules, on tori the tests make.
#include "penalty/collision/ray_trace_narrow_phase.hpp"

#include "detection_scenes.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

namespace penalty {
namespace {

std::vector<Triangle> triangles_of(const MeshTopology& topo) {
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
    const std::vector<Triangle> tris = triangles_of(torus->topo);
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

/// The narrow phase's rules with the brute-force nearest hit in place of the octree walk.
std::set<std::tuple<Index, Index, std::int64_t>> reference_outputs(const OctreeSurface& a, const OctreeSurface& b) {
    std::set<std::tuple<Index, Index, std::int64_t>> out;
    const TriangleModel& ma = *a.model;
    const auto& x = ma.state().position;
    for (std::size_t j = 0; j < ma.size(); ++j) {
        int rank = 0;
        for (int k = 0; k < 3; ++k) {
            if ((ma.flags(Index(j)) & (1u << k)) == 0) continue;
            const int id_rank = rank++;
            const Vec3& p = x[std::size_t(ma.triangle(Index(j))[std::size_t(k)])];
            const Vec3 n = a.vertex_normals[std::size_t(ma.triangle(Index(j))[std::size_t(k)])];
            if ((p.array() < b.box.min.array()).any() || (p.array() > b.box.max.array()).any()) continue;
            const RayHit hit = b.octree.nearest_hit(p, -n);
            if (hit.triangle < 0 || a.normals[j].dot(b.normals[std::size_t(hit.triangle)]) > 0) continue;
            const RayHit own = a.octree.nearest_hit(p, -n);
            if (own.triangle < 0 || own.t < hit.t || a.normals[j].dot(a.normals[std::size_t(own.triangle)]) > 0)
                continue;
            out.insert({Index(j), Index(hit.triangle), std::int64_t(j) * 3 + id_rank});
        }
    }
    return out;
}

TEST(RayTraceNarrowPhase, OverlappingToriAgainstTheBruteForceRules) {
    std::mt19937 g(7);
    const auto ta = test::make_torus(20, 10, 2.0, 0.8, Vec3(0, 0, 0), g, 0.1);
    const auto tb = test::make_torus(20, 10, 2.0, 0.8, Vec3(0.6, 0.3, 0.5), g, 0.1);
    TriangleModel a(ta->state, ta->topo), b(tb->state, tb->topo);
    RayTraceNarrowPhase narrow;
    narrow.add_surface(a);
    narrow.add_surface(b);
    ModelPairDetection pair;
    pair.model1 = &a;
    pair.model2 = &b;
    // two updates: the stored normals (of the previous update) are then those of these positions
    (void)narrow.detect({pair});
    const SceneDetection& d = narrow.detect({pair});
    ASSERT_EQ(d.size(), 2u);  // (A, B) then (B, A)
    EXPECT_EQ(d[0].model1, &a);
    EXPECT_EQ(d[1].model1, &b);
    std::size_t outputs = 0, agreeing = 0, expected = 0;
    for (const ModelPairDetection& side : d) {
        OctreeSurface& s1 = *narrow.find(*side.model1);
        OctreeSurface& s2 = *narrow.find(*side.model2);
        const auto reference = reference_outputs(s1, s2);
        expected += reference.size();
        const auto& x2 = static_cast<const TriangleModel&>(*side.model2);
        for (const DetectionOutput& o : side.outputs) {
            ++outputs;
            agreeing += reference.count({o.elem1.value(), o.elem2.value(), o.id}) ? 1 : 0;
            // P is a vertex of element 1, Q on element 2 at −value along −normal
            EXPECT_NEAR(o.normal.norm(), 1.0, 1e-12);
            EXPECT_LT(o.value, 0.0);
            EXPECT_NEAR((o.point[1] - o.point[0]).norm(), -o.value, 1e-9);
            EXPECT_NEAR((o.point[1] - (o.point[0] + o.value * o.normal)).norm(), 0.0, 1e-9);
            const Index t2 = o.elem2.value();
            const Vec3 n2 = (x2.p(t2, 1) - x2.p(t2, 0)).cross(x2.p(t2, 2) - x2.p(t2, 0));
            EXPECT_NEAR(n2.dot(o.point[1] - x2.p(t2, 0)), 0.0, 1e-9);
        }
    }
    ASSERT_GT(expected, 20u);
    EXPECT_GT(double(agreeing) / double(expected), 0.99) << agreeing << " of " << expected;
    EXPECT_LE(outputs, expected + expected / 20);
}

TEST(RayTraceNarrowPhase, SeparatedSurfacesAndOtherModelsGiveNothing) {
    std::mt19937 g(3);
    const auto ta = test::make_torus(12, 6, 2.0, 0.8, Vec3(0, 0, 0), g);
    const auto tb = test::make_torus(12, 6, 2.0, 0.8, Vec3(0, 0, 1.7), g);  // stacked, 0.1 apart
    TriangleModel a(ta->state, ta->topo), b(tb->state, tb->topo), plain(tb->state, tb->topo);
    RayTraceNarrowPhase narrow;
    narrow.add_surface(a);
    narrow.add_surface(b);
    ModelPairDetection pair;
    pair.model1 = &a;
    pair.model2 = &b;
    ModelPairDetection other = pair;
    other.model2 = &plain;  // not an octree model: no entry (findPairsVolume returns first)
    const SceneDetection& d = narrow.detect({pair, other});
    ASSERT_EQ(d.size(), 2u);
    EXPECT_TRUE(d[0].outputs.empty());
    EXPECT_TRUE(d[1].outputs.empty());
    // moved into each other: outputs on both sides
    for (Vec3& p : tb->state.position) p.z() -= 0.6;
    const SceneDetection& moved = narrow.detect({pair});
    EXPECT_FALSE(moved[0].outputs.empty());
    EXPECT_FALSE(moved[1].outputs.empty());
}

}  // namespace
}  // namespace penalty
