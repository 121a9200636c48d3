// SOFA's RayTraceNarrowPhase (docs/components/ray_trace_narrow_phase.md): the narrow phase
// against a brute-force reference of the same rules, on tori the tests make (the ray test and the
// octree walk: test_triangle_octree.cpp).
#include "penalty/collision/ray_trace_narrow_phase.hpp"

#include "detection_scenes.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

namespace penalty {
namespace {

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
