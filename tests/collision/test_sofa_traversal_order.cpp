// SOFA's BVHNarrowPhase visiting order (sofa_traversal_order.hpp): the tree of
// CubeCollisionModel::computeBoundingTree and the stack traversal of visitCollisionElements,
// worked out by hand on small point sets, and the pipeline's outputs in that order.
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/collision/models.hpp"
#include "penalty/collision/sofa_traversal_order.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace penalty {
namespace {

CollisionModelParams named(const char* n, int node) {
    CollisionModelParams p;
    p.name = n;
    p.node = node;
    return p;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> steps(const SofaCubeTree& t, Index e) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    const SofaCubeTree::Path p = t.path(e);
    for (std::size_t k = 0; k < p.size(); ++k) out.emplace_back(p[k].index, p[k].size);
    return out;
}

using Steps = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

TEST(SofaOrder, TreeSplitsCellsOfMoreThanFourAtTheMedianAfterSortingAlongTheLongestAxis) {
    // six points on x at 5, 4, …, 0 (element e at x = 5 − e): the root (6 > 4) is sorted by
    // centre along x → elements 5 4 3 2 1 0, split at first + (6 + 1) / 2 = 3 into {5, 4, 3}
    // and {2, 1, 0}, which (3 ≤ 4) are not split
    Vec3State s;
    for (int e = 0; e < 6; ++e) s.position.emplace_back(5.0 - e, 0.1 * e, 0.0);
    PointModel m(s, nullptr, named("line", 0));
    SofaCubeTree t;
    t.build(m, 6);
    ASSERT_EQ(t.size(), 6u);
    EXPECT_EQ(steps(t, 5), (Steps{{0, 2}, {0, 3}}));
    EXPECT_EQ(steps(t, 4), (Steps{{0, 2}, {1, 3}}));
    EXPECT_EQ(steps(t, 3), (Steps{{0, 2}, {2, 3}}));
    EXPECT_EQ(steps(t, 2), (Steps{{1, 2}, {0, 3}}));
    EXPECT_EQ(steps(t, 0), (Steps{{1, 2}, {2, 3}}));
    // depth 0: the root is never split; its elements are its children in element order
    SofaCubeTree flat;
    flat.build(m, 0);
    EXPECT_EQ(steps(flat, 0), (Steps{{0, 6}}));
    EXPECT_EQ(steps(flat, 5), (Steps{{5, 6}}));
    // the longest extent decides the axis: the same points spread more along y than x
    Vec3State sy;
    for (int e = 0; e < 6; ++e) sy.position.emplace_back(0.1 * e, 10.0 - 3.0 * e, 0.0);
    PointModel my(sy, nullptr, named("y", 1));
    SofaCubeTree ty;
    ty.build(my, 6);
    EXPECT_EQ(steps(ty, 5), (Steps{{0, 2}, {0, 3}}));  // lowest y first
    EXPECT_EQ(steps(ty, 0), (Steps{{1, 2}, {2, 3}}));
}

TEST(SofaOrder, PairsOfElementsFirstThenPushedPairsLastPushedFirst) {
    // tree 1: the six points above ({5,4,3} | {2,1,0}); tree 2: two points, root not split.
    // visitCollisionElements on (cells of 1) × (elements of 2) pushes (C0,b0), (C0,b1), (C1,b0),
    // (C1,b1) and pops them in reverse; each pops into element pairs intersected in loop order.
    Vec3State s1, s2;
    for (int e = 0; e < 6; ++e) s1.position.emplace_back(5.0 - e, 0.0, 0.0);
    s2.position = {Vec3(0, 1, 0), Vec3(1, 1, 0)};
    PointModel m1(s1, nullptr, named("six", 0)), m2(s2, nullptr, named("two", 1));
    SofaCubeTree t1, t2;
    t1.build(m1, 6);
    t2.build(m2, 6);
    const std::vector<std::pair<Index, Index>> expected = {{2, 1}, {1, 1}, {0, 1}, {2, 0}, {1, 0}, {0, 0},
                                                           {5, 1}, {4, 1}, {3, 1}, {5, 0}, {4, 0}, {3, 0}};
    std::vector<std::pair<Index, Index>> all;
    for (Index a = 0; a < 6; ++a)
        for (Index b = 0; b < 2; ++b) all.emplace_back(a, b);
    std::sort(all.begin(), all.end(), [&](const auto& x, const auto& y) {
        return sofa_visits_before(t1, t2, x.first, x.second, y.first, y.second);
    });
    EXPECT_EQ(all, expected);
    // outputs sorted the same way; two outputs of one element pair keep their order
    DetectionOutputList out;
    for (auto it = expected.rbegin(); it != expected.rend(); ++it) {
        DetectionOutput o;
        o.elem1 = ElementIndex(it->first);
        o.elem2 = ElementIndex(it->second);
        o.value = double(out.size());
        out.push_back(o);
    }
    DetectionOutput twin = out.front();  // (3, 0) again, after the first one
    twin.value = 99.0;
    out.push_back(twin);
    SofaOrderScratch scratch;
    sort_in_sofa_order(t1, t2, out, scratch);
    ASSERT_EQ(out.size(), 13u);
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(out[i].elem1.value(), expected[i].first) << i;
        EXPECT_EQ(out[i].elem2.value(), expected[i].second) << i;
    }
    EXPECT_EQ(out[11].value, 0.0);   // the first (3, 0)
    EXPECT_EQ(out[12].value, 99.0);  // the second (3, 0)
}

TEST(SofaOrder, IsAStrictTotalOrderOnRandomClouds) {
    std::mt19937 g(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int compared = 0;
    for (int n1 : {1, 4, 5, 13, 40}) {
        for (int n2 : {3, 9, 33}) {
            Vec3State s1, s2;
            for (int i = 0; i < n1; ++i) s1.position.emplace_back(u(g), u(g), u(g));
            for (int i = 0; i < n2; ++i) s2.position.emplace_back(u(g), u(g), u(g));
            PointModel m1(s1, nullptr, named("a", 0)), m2(s2, nullptr, named("b", 1));
            SofaCubeTree t1, t2;
            t1.build(m1, 3);
            t2.build(m2, 2);
            std::vector<std::pair<Index, Index>> all;
            for (int a = 0; a < n1; ++a)
                for (int b = 0; b < n2; ++b) all.emplace_back(Index(a), Index(b));
            for (const auto& x : all) {
                EXPECT_FALSE(sofa_visits_before(t1, t2, x.first, x.second, x.first, x.second));
                for (const auto& y : all) {
                    if (x == y) continue;
                    ++compared;
                    const bool xy = sofa_visits_before(t1, t2, x.first, x.second, y.first, y.second);
                    const bool yx = sofa_visits_before(t1, t2, y.first, y.second, x.first, x.second);
                    ASSERT_NE(xy, yx) << x.first << "," << x.second << " vs " << y.first << "," << y.second;
                }
            }
        }
    }
    EXPECT_GT(compared, 1000000);
}

TEST(SofaOrder, PackedKeySortEqualsTheComparatorsOrderOnRandomOutputs) {
    // sort_in_sofa_order packs each output's place into one integer; it must give exactly the
    // stable sort by sofa_visits_before, duplicates of an element pair kept in their order;
    // sort_keys_in_sofa_order the same order on the distinct element pairs
    std::mt19937 g(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int cases = 0, reordered = 0, radix_key_cases = 0;
    // 400 outputs: sorted by std::sort; 3000: by the radix sort (512 or more), most cases with
    // that many distinct element pairs too
    for (int count : {400, 3000})
        for (int depth : {0, 1, 2, 6, 12}) {
            for (int n1 : {1, 5, 37, 300}) {
                for (int n2 : {1, 2, 9, 120}) {  // a one-element model: keys precomputed at build
                    Vec3State s1, s2;
                    for (int i = 0; i < n1; ++i) s1.position.emplace_back(u(g), u(g), u(g));
                    for (int i = 0; i < n2; ++i) s2.position.emplace_back(u(g), u(g), u(g));
                    PointModel m1(s1, nullptr, named("a", 0)), m2(s2, nullptr, named("b", 1));
                    SofaCubeTree t1, t2;
                    t1.build(m1, depth);
                    t2.build(m2, depth == 12 ? 3 : depth);
                    DetectionOutputList out;
                    std::uniform_int_distribution<int> e1(0, n1 - 1), e2(0, n2 - 1);
                    for (int k = 0; k < count; ++k) {
                        DetectionOutput o;
                        o.elem1 = ElementIndex(e1(g));
                        o.elem2 = ElementIndex(e2(g));
                        o.value = double(k);  // the kernel order, to check stability
                        out.push_back(o);
                    }
                    DetectionOutputList expected = out;
                    std::stable_sort(expected.begin(), expected.end(),
                                     [&](const DetectionOutput& x, const DetectionOutput& y) {
                                         return sofa_visits_before(t1, t2, x.elem1.value(), x.elem2.value(),
                                                                   y.elem1.value(), y.elem2.value());
                                     });
                    // sort_keys_in_sofa_order: the same order on the element pairs, each once (the
                    // candidate cache's keys), given in the outputs' random order
                    std::vector<std::uint64_t> keys, expected_keys;
                    const auto key_of = [](const DetectionOutput& o) { return PairKey(o.elem1, o.elem2).bits(); };
                    std::set<std::uint64_t> seen;
                    for (const DetectionOutput& o : out)
                        if (seen.insert(key_of(o)).second) keys.push_back(key_of(o));
                    if (keys.size() >= 512) ++radix_key_cases;
                    for (const DetectionOutput& o : expected)
                        if (expected_keys.empty() || expected_keys.back() != key_of(o))
                            expected_keys.push_back(key_of(o));
                    SofaOrderScratch key_scratch;
                    sort_keys_in_sofa_order(t1, t2, keys, key_scratch);
                    ASSERT_EQ(keys, expected_keys) << depth << " " << n1 << " " << n2;
                    SofaOrderScratch scratch;
                    sort_in_sofa_order(t1, t2, out, scratch);
                    ASSERT_EQ(out.size(), expected.size());
                    for (std::size_t i = 0; i < out.size(); ++i) {
                        ASSERT_EQ(out[i].elem1, expected[i].elem1) << depth << " " << n1 << " " << n2 << " " << i;
                        ASSERT_EQ(out[i].elem2, expected[i].elem2) << i;
                        ASSERT_EQ(out[i].value, expected[i].value) << i;
                    }
                    ++cases;
                    for (std::size_t i = 0; i < out.size(); ++i)
                        if (out[i].value != double(i)) {
                            ++reordered;
                            break;
                        }
                }
            }
        }
    EXPECT_EQ(cases, 160);
    // the order is not the input's (1×1 elements cannot change it, 1×2 could keep it)
    EXPECT_GE(reordered, 148);
    // key lists of 512 or more at 3000 outputs, at every depth: n1 × n2 = 300 × 2, 5 × 120 (600
    // pairs, nearly all drawn), 300 × 9, 37 × 120, 300 × 120
    EXPECT_EQ(radix_key_cases, 25);
}

TEST(SofaOrder, BvhAndExhaustiveDetectionGiveTheSameOrderOverMovingSteps) {
    // both pipelines build SOFA's trees at their first detection, from the same positions
    std::mt19937 g(21);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Vec3State s1, s2;
    for (int i = 0; i < 300; ++i) s1.position.emplace_back(u(g), u(g), u(g));
    for (int i = 0; i < 300; ++i) s2.position.emplace_back(u(g), u(g), u(g));
    SphereModel m1(s1, 0.04, {}, named("a", 0)), m2(s2, 0.04, {}, named("b", 1));
    IntersectionParams params = IntersectionParams::new_proximity();
    params.alarm_distance = 0.02;
    params.contact_distance = 0.01;
    CollisionPipeline bvh(params), exhaustive(params, {}, ContactDetection::exhaustive);
    bvh.set_models({&m1, &m2});
    exhaustive.set_models({&m1, &m2});
    std::size_t outputs = 0, unsorted = 0;
    for (int step = 0; step < 3; ++step) {
        const SceneDetection& a = bvh.detect();
        const SceneDetection& b = exhaustive.detect();
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t k = 0; k < a.size(); ++k) {
            ASSERT_EQ(a[k].outputs.size(), b[k].outputs.size());
            for (std::size_t i = 0; i < a[k].outputs.size(); ++i) {
                EXPECT_EQ(a[k].outputs[i].elem1, b[k].outputs[i].elem1);
                EXPECT_EQ(a[k].outputs[i].elem2, b[k].outputs[i].elem2);
                if (i > 0 && std::pair(a[k].outputs[i - 1].elem1, a[k].outputs[i - 1].elem2) >
                                 std::pair(a[k].outputs[i].elem1, a[k].outputs[i].elem2))
                    ++unsorted;
            }
            outputs += a[k].outputs.size();
        }
        for (auto& p : s1.position) p += Vec3(0.01, 0.0, 0.0);
    }
    EXPECT_GT(outputs, 300u);
    EXPECT_GT(unsorted, 30u);  // SOFA's order is not the ascending element order
}

}  // namespace
}  // namespace penalty
