// The dual-tree traversal of two bounding trees (bvh_traversal.cpp): the candidate element pairs
// whose boxes pass the §3.8 test with the margin, against every pair tested; a model against
// itself (each unordered pair once, keyed (larger, smaller)); the row mode of long triangles,
// whose planes drop the far elements, against the exhaustive detection.
#include "penalty/core/pair_key.hpp"
#include "pipeline_references.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace penalty {
namespace {

using namespace test_pipeline;

TEST(BvhTraversal, AModelAgainstItselfGivesEachOverlappingPairOnceLargerIndexFirst) {
    // 6 000 spheres (enough for the traversal to fork into tasks, at 4 096 elements) in a cube
    // of side 2: every pair i > j whose boxes overlap, keyed (i, j), in key order
    std::mt19937 g(20261130);
    Vec3State cloud = random_cloud(6000, 1.0, g);
    SphereModel spheres(cloud, 0.0, random_radii(6000, 0.01, 0.04, g), test::named("cloud"));
    const double margin = 0.01;
    std::vector<std::uint64_t> expected;
    for (std::size_t i = 0; i < spheres.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (spheres.element_box(Index(i)).overlaps(spheres.element_box(Index(j)), margin))
                expected.push_back(pair_key::make(i, j));
    std::sort(expected.begin(), expected.end());
    // about 4 000 pairs of the 1.8·10⁷
    ASSERT_GT(expected.size(), 2000u);
    ASSERT_LT(expected.size(), 20000u);
    for (const std::size_t leaf : {1, 4, 16, 65}) {
        Bvh tree;
        tree.build(spheres, leaf);
        for (const bool parallel : {false, true})
            EXPECT_EQ(bvh_candidates(tree, tree, true, margin, parallel), expected)
                << "leaf " << leaf << (parallel ? " parallel" : "");
    }
}

TEST(BvhTraversal, TheMarginIsAGapBetweenBoxesTheTestKeepsInclusive) {
    // spheres of radius 0.5 at x = 0, 1.125, 2.25 + 2⁻²⁰: the gaps between their boxes are
    // 0.125 and 0.125 + 2⁻²⁰, exactly; with the margin 0.125 the first pair is a candidate (a
    // box min > the other's max + margin rejects; equal keeps), the second is not
    const double far = 2.25 + std::ldexp(1.0, -20);
    Vec3State row = test::make_state({{0, 0, 0}, {1.125, 0, 0}, {far, 0, 0}});
    SphereModel spheres(row, 0.5, {}, test::named("row"));
    Vec3State one = test::make_state({{1.125, 0, 0}});
    SphereModel single(one, 0.5, {}, test::named("single"));
    Bvh tree;
    Bvh single_tree;
    tree.build(spheres, 1);
    single_tree.build(single, 1);
    EXPECT_EQ(bvh_candidates(tree, tree, true, 0.125, false), (std::vector<std::uint64_t>{pair_key::make(1, 0)}));
    // against the single sphere at 1.125: itself (0 gap) and the first (0.125), not the third
    EXPECT_EQ(bvh_candidates(tree, single_tree, false, 0.125, false),
              (std::vector<std::uint64_t>{pair_key::make(0, 0), pair_key::make(1, 0)}));
    EXPECT_EQ(bvh_candidates(single_tree, tree, false, 0.125, false),
              (std::vector<std::uint64_t>{pair_key::make(0, 0), pair_key::make(0, 1)}));
    // a margin one ulp larger than the second gap takes it too
    EXPECT_EQ(bvh_candidates(tree, tree, true, std::nextafter(0.125 + std::ldexp(1.0, -20), 1.0), false).size(), 2u);
    // an empty tree: no candidates
    Bvh empty;
    EXPECT_TRUE(bvh_candidates(tree, empty, false, 1.0, false).empty());
}

TEST(BvhTraversal, LongTrianglesDropTheFarPointsAndKeepTheExhaustiveOutputs) {
    // a slope z = x/2 of two long triangles (side 8, more than 16 times the margin R = 0.05)
    // in a cloud of 3 000 points within 0.3 of it: every point lies in the triangles' boxes,
    // and the row mode descends the points' tree with each triangle's planes, dropping the
    // points beyond R. The outputs are the exhaustive detection's, with and without the
    // candidate cache, without it from far fewer candidates than the box test leaves
    auto slope = test::triangle_mesh({{-4, -4, -2}, {4, -4, 2}, {4, 4, 2}, {-4, 4, -2}}, {{0, 1, 2}, {0, 2, 3}});
    TriangleModel triangles(slope->state, slope->topo, mp("slope"));
    std::mt19937 g(7);
    std::uniform_real_distribution<double> across(-3.5, 3.5);
    std::uniform_real_distribution<double> offset(-0.3, 0.3);
    Vec3State cloud;
    cloud.resize(3000);
    for (Vec3& p : cloud.position) {
        const double u = offset(g);
        const double y = across(g);
        const double x = across(g);
        p = Vec3(x, y, 0.5 * x + u);
    }
    PointModel points(cloud, nullptr, mp("cloud"));
    const IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    std::vector<CollisionModel*> models{&triangles, &points};
    const SceneDetection reference = detect_scene_exhaustive(params, models);
    // the points within the alarm distance 0.05 of the slope (0.05·√1.25 vertically): about
    // 3 000·0.112/0.6 ≈ 560
    const std::size_t outputs = count_outputs(reference);
    EXPECT_GT(outputs, 450u);
    EXPECT_LT(outputs, 700u);
    std::size_t box_pairs = 0;
    for (std::size_t t = 0; t < triangles.size(); ++t)
        for (std::size_t i = 0; i < points.size(); ++i)
            box_pairs += triangles.element_box(Index(t)).overlaps(points.element_box(Index(i)), 0.05) ? 1 : 0;
    EXPECT_GT(box_pairs, 3000u);
    for (const bool cache : {false, true}) {
        CollisionPipelineOptions options = canonical_order();
        options.candidate_cache = cache;
        CollisionPipeline pipe(params, options);
        pipe.set_models(models);
        expect_identical(pipe.detect(), reference);
        // (the cache collects with its boxes grown by how far they may move: its planes keep all)
        if (!cache) {
            EXPECT_LT(pipe.candidates_evaluated(), box_pairs / 3);
        }
    }
}

}  // namespace
}  // namespace penalty
