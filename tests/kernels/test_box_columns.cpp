// The traversal's leaf-level box tests (box_columns.hpp): the vector path against the scalar one
// and against Aabb::overlaps, and bvh_candidates against every overlapping pair, for leaf sizes
// on both sides of the columns' capacity.
#include "detection_scenes.hpp"
#include "fixtures.hpp"
#include "kernels/box_overlap.hpp"
#include "kernels/collision/box_columns.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/core/pair_key.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace penalty {
namespace {

// A random box; some bounds snapped to a coarse grid so that boxes touch exactly (the margin
// test's equality), some set to −0.0, NaN or ±infinity.
Aabb random_box(std::mt19937& g) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> pick(0, 39);
    Aabb b;
    for (int i = 0; i < 3; ++i) {
        double lo = u(g), hi = lo + 1.5 * std::abs(u(g));
        if (pick(g) < 12) {  // on the grid of step 0.25: exact contacts between boxes
            lo = std::round(lo * 4.0) / 4.0;
            hi = std::round(hi * 4.0) / 4.0;
        }
        if (pick(g) == 0) lo = -0.0;
        if (pick(g) == 0) hi = std::numeric_limits<double>::quiet_NaN();
        if (pick(g) == 0) lo = -std::numeric_limits<double>::infinity();
        b.min[i] = lo;
        b.max[i] = hi;
    }
    return b;
}

TEST(BoxColumns, VectorMaskEqualsScalarMaskAndOverlapsForEveryColumnCount) {
    std::mt19937 g(2026);
    const double margins[] = {0.0, 1e-12, 0.05, 0.25};
    std::size_t tests = 0, hits = 0;
    for (int round = 0; round < 400; ++round) {
        const std::uint32_t n = 1 + std::uint32_t(round % detail::BoxColumns::kCapacity);  // 1 … 64
        const double m = margins[round % 4];
        std::vector<Aabb> boxes(n);
        detail::BoxColumns columns;
        for (std::uint32_t k = 0; k < n; ++k) {
            boxes[k] = random_box(g);
            columns.push(boxes[k], m, 100 + k);
        }
        columns.pad();
        ASSERT_EQ(columns.size, n);
        for (int q = 0; q < 8; ++q) {
            const Aabb a = random_box(g);
            std::uint64_t expected = 0;
            for (std::uint32_t k = 0; k < n; ++k)
                if (a.overlaps(boxes[k], m)) expected |= std::uint64_t{1} << k;
            ASSERT_EQ(detail::overlap_mask(a, m, columns, KernelPath::scalar), expected) << "round " << round;
            if (kernel_path_supported(KernelPath::avx)) {
                ASSERT_EQ(detail::overlap_mask(a, m, columns, KernelPath::avx), expected) << "round " << round;
            }
            tests += n;
            hits += std::size_t(std::popcount(expected));
        }
        for (std::uint32_t k = 0; k < n; ++k) ASSERT_EQ(columns.slot[k], 100 + k);
    }
    // both outcomes well represented
    const double rate = double(hits) / double(tests);
    EXPECT_GT(rate, 0.15);
    EXPECT_LT(rate, 0.85);
}

// boxes_overlap_branch_free (the kept candidates' test, two comparisons an instruction with
// SSE2) and its scalar reference give overlaps()'s answer on every pair: touching bounds, −0, NaN and infinite bounds,
// margins whose sums round, both argument orders.
TEST(BoxColumns, BranchFreeOverlapTestEqualsOverlaps) {
    std::mt19937 g(20261125);
    const double margins[] = {0.0, 1e-12, 0.05, 0.25, 0.1 + 0.2};
    std::size_t tests = 0, hits = 0, touching = 0, with_nan = 0;
    for (int k = 0; k < 200000; ++k) {
        const Aabb a = random_box(g), b = random_box(g);
        const double m = margins[k % 5];
        const bool expected = a.overlaps(b, m);
        ASSERT_EQ(detail::boxes_overlap_branch_free(a, b, m), expected) << "pair " << k;
        ASSERT_EQ(detail::boxes_overlap_branch_free(b, a, m), b.overlaps(a, m)) << "pair " << k;
        ASSERT_EQ(detail::boxes_overlap_branch_free_scalar(a, b, m), expected) << "pair " << k;
        ASSERT_EQ(detail::boxes_overlap_branch_free_scalar(b, a, m), b.overlaps(a, m)) << "pair " << k;
        ++tests;
        hits += expected ? 1 : 0;
        for (int i = 0; i < 3; ++i) {
            touching += (a.min[i] == b.max[i] + m || b.min[i] == a.max[i] + m) ? 1 : 0;
            with_nan += (std::isnan(a.max[i]) || std::isnan(b.max[i])) ? 1 : 0;
        }
    }
    const double rate = double(hits) / double(tests);
    EXPECT_GT(rate, 0.15);
    EXPECT_LT(rate, 0.85);
    EXPECT_GT(touching, 1000u);  // the equality case, where > and >= would differ
    EXPECT_GT(with_nan, 5000u);
}

// bvh_candidates against the all-pairs box test, for leaf sizes below, at and above the columns'
// capacity (the leaf-level loop's two branches) and for one element against many.
TEST(BoxColumns, BvhCandidatesEqualEveryOverlappingPairForEveryLeafSize) {
    std::mt19937 g(31);
    Vec3State sa = test::random_cloud(700, 1.0, g);
    Vec3State sb = test::random_cloud(500, 1.0, g, Vec3(0.3, 0.0, 0.0));
    Vec3State one = test::random_cloud(1, 0.2, g);
    SphereModel a(sa, 0.0, test::random_radii(700, 0.03, 0.12, g), test::named("A"));
    SphereModel b(sb, 0.0, test::random_radii(500, 0.03, 0.12, g), test::named("B"));
    SphereModel c(one, 0.7, std::vector<double>{}, test::named("C"));
    const double margin = 0.02;
    auto expected_pairs = [&](const CollisionModel& m1, const CollisionModel& m2) {
        std::vector<std::uint64_t> keys;
        for (std::size_t i = 0; i < m1.size(); ++i)
            for (std::size_t j = 0; j < m2.size(); ++j)
                if (m1.element_box(Index(i)).overlaps(m2.element_box(Index(j)), margin))
                    keys.push_back(pair_key::make(i, j));
        return keys;
    };
    const std::vector<std::uint64_t> ab = expected_pairs(a, b);
    const std::vector<std::uint64_t> ca = expected_pairs(c, a);
    ASSERT_GT(ab.size(), 1000u);             // a real test: many pairs …
    ASSERT_LT(ab.size(), 700u * 500u / 10);  // … but far from all
    ASSERT_GT(ca.size(), 20u);
    for (const std::size_t leaf : {1, 3, 8, 64, 65, 200}) {
        Bvh ta, tb, tc;
        ta.build(a, leaf);
        tb.build(b, leaf);
        tc.build(c, leaf);
        for (const bool parallel : {false, true}) {
            EXPECT_EQ(bvh_candidates(ta, tb, false, margin, parallel), ab) << "leaf " << leaf;
            EXPECT_EQ(bvh_candidates(tc, ta, false, margin, parallel), ca) << "leaf " << leaf;
        }
    }
}

// bvh_candidates sorts its keys by comparisons (< 256), by a radix sort of the packed element
// indices (< 4 096, or fewer than a quarter of the first model's elements), by two counting sorts
// (more), or by a counting sort and per-element sorts in parallel (2¹⁸ keys and more, with
// threads): each path against the all-pairs box test, which gives the keys in order.
TEST(BoxColumns, BvhCandidatesAreSortedOnEveryPathOfTheSort) {
    struct Case {
        std::size_t n1, n2;
        double radius;  // of every sphere; cloud of side 1 (and the second one of side `side2`)
        double side2;
        std::size_t min_keys, max_keys;  // the path's range
    };
    const Case cases[] = {
        // expected keys n1·n2·P³ with P = 2r − r² for two clouds of side 2 (about 100, 1 500,
        // 50 000 and 600 000), n1·n2·(2r)³ for a small second cloud (about 7 000)
        {100, 100, 0.114, 1.0, 20, 255},            // comparisons
        {300, 300, 0.137, 1.0, 256, 4095},          // radix (few keys)
        {40000, 40, 0.0818, 0.1, 4096, 9999},       // radix (fewer keys than n1 / 4)
        {1000, 1000, 0.205, 1.0, 4096, 262143},     // two counting sorts
        {2000, 2000, 0.315, 1.0, 262144, 4000000},  // counting + per-element sorts (parallel)
    };
    std::mt19937 g(20261127);
    int paths = 0;
    for (const Case& c : cases) {
        Vec3State sa = test::random_cloud(c.n1, 1.0, g);
        Vec3State sb = test::random_cloud(c.n2, c.side2, g);
        SphereModel a(sa, c.radius, std::vector<double>{}, test::named("A"));
        SphereModel b(sb, c.radius, std::vector<double>{}, test::named("B"));
        std::vector<std::uint64_t> expected;
        for (std::size_t i = 0; i < c.n1; ++i)
            for (std::size_t j = 0; j < c.n2; ++j)
                if (a.element_box(Index(i)).overlaps(b.element_box(Index(j)), 0.0))
                    expected.push_back(pair_key::make(i, j));
        ASSERT_GE(expected.size(), c.min_keys) << c.n1 << " x " << c.n2;
        ++paths;
        ASSERT_LE(expected.size(), c.max_keys) << c.n1 << " x " << c.n2;
        Bvh ta, tb;
        ta.build(a, 8);
        tb.build(b, 8);
        for (const bool parallel : {false, true})
            EXPECT_EQ(bvh_candidates(ta, tb, false, 0.0, parallel), expected)
                << c.n1 << " x " << c.n2 << (parallel ? " parallel" : "");
    }
    EXPECT_EQ(paths, 5);
}

}  // namespace
}  // namespace penalty
