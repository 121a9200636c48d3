// The candidate cache (collision/candidate_cache.cpp): the outputs of the traversals it replaces, over many steps,
// moving and fast-moving models, its slack.
#include "pipeline_references.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <random>

namespace penalty {
namespace {

using namespace test_pipeline;

// Two pipelines over the same models: with the candidate cache (the default) and without it
// (the trees traversed at every step, the reference).
struct CachedAndPlain {
    CollisionPipeline cached;
    CollisionPipeline plain;
    CachedAndPlain(const IntersectionParams& params, const std::vector<CollisionModel*>& models)
        : cached(params), plain(params, without_cache()) {
        cached.set_models(models);
        plain.set_models(models);
    }
    static CollisionPipelineOptions without_cache() {
        CollisionPipelineOptions o;
        o.candidate_cache = false;
        return o;
    }
};

TEST(NarrowPhase, CandidateCacheGivesTheTraversalsOutputsOverManyStepsAndIsReused) {
    // the kept candidates of a pair are re-tested with the exact box test, so a pipeline with the
    // cache must give bit for bit what one traversing the trees at every step gives, in SOFA's
    // order, over slow drifts (kept) and sudden jumps (collected again), self-collision included
    for (const auto method : {IntersectionMethod::NewProximity, IntersectionMethod::MinProximity}) {
        SCOPED_TRACE(intersection_method_name(method));
        MeshScene sc(7, true);
        std::mt19937 g(8);
        const IntersectionParams params = method_params(method);
        CachedAndPlain pipelines(params, sc.models);
        CollisionPipeline& cached = pipelines.cached;
        CollisionPipeline& plain = pipelines.plain;
        std::size_t total = 0;
        for (int step = 0; step < 27; ++step) {
            const SceneDetection& got = cached.detect();
            const SceneDetection& ref = plain.detect();
            expect_identical(got, ref);
            total += count_outputs(got);
            // drift of ~1 mm per step (the tori's edges are ~0.1 m), a jump of 5 cm every 13 steps
            sc.jiggle(g, step % 13 == 12 ? 0.05 : 0.001);
            for (auto& p : sc.t2->state.position) p += Vec3(0.002, 0.0, 0.0);
        }
        EXPECT_GT(total, 3000u);
        const auto& stats = cached.candidate_cache_stats();
        EXPECT_EQ(plain.candidate_cache_stats().reused + plain.candidate_cache_stats().collected, 0u);
        // every pair detection is one or the other; most are answered from the kept candidates,
        // and the jumps force new collections
        EXPECT_GT(stats.reused, stats.collected) << stats.reused << " reused, " << stats.collected << " collected";
        EXPECT_GT(stats.collected, 3u * 10u);
        // both ways to SOFA's order were taken: outputs sorted at a step, and kept candidates
        // sorted once (rent-or-buy) so that later steps' outputs came sorted
        EXPECT_GT(stats.sofa_order_sorts, 5u) << stats.sofa_order_sorts;
        EXPECT_GT(stats.in_sofa_order, stats.sofa_order_sorts);
        EXPECT_LT(stats.in_sofa_order, stats.reused + stats.collected);
        // the kept keys' box test, with and without a branch per key, leaves the traversal's
        // candidates: the kernels saw the same element pairs
        EXPECT_GT(stats.branch_free_tests, 0u);
        EXPECT_LT(stats.branch_free_tests, stats.reused + stats.collected);  // with a branch too
        EXPECT_EQ(cached.candidates_evaluated(), plain.candidates_evaluated());
    }
}

// The kept keys sure to overlap (PairCandidates::sure) are made at some detection of a
// generation, and a box may move by its slack s away from the generation's reference in one
// direction before and in the other after: 2·s between the two. A sphere (slack 2r/8) swings
// by ±0.99 s along x past a row of static points, and the flags are made with the sphere near
// the points; points just inside the margin then, and outside it at the next swing, must be
// box-tested again (a margin that allows only one s keeps one of them too many).
TEST(NarrowPhase, KeysSureToOverlapStayWithinTheBoxTestAcrossASwingOfTwiceTheSlack) {
    const double r = 0.1;
    const double slack = 0.125 * 2.0 * r;  // the sphere model's first slack: an eighth of its extent
    IntersectionParams params = IntersectionParams::new_proximity();
    params.alarm_distance = 0.2;
    params.contact_distance = 0.05;
    const double reach = r + params.alarm_distance;  // the boxes overlap on x iff p <= c + reach
    std::vector<Vec3> row;
    for (int k = 0; k < 60; ++k) row.emplace_back(-0.2 + 0.45 * k / 59.0, 0.0, 0.0);
    for (const double d : {-0.001, -0.004, -0.03, 0.01, 0.04}) row.emplace_back(reach + d, 0.0, 0.0);
    Vec3State points_state = test::make_state(row);
    Vec3State ball_state = test::make_state({Vec3::Zero()});
    PointModel points(points_state, nullptr, static_mp("row"));
    SphereModel ball(ball_state, r, {}, mp("ball"));
    const std::vector<CollisionModel*> models = {&ball, &points};
    CachedAndPlain pipelines(params, models);
    std::size_t total = 0;
    for (int step = 0; step < 12; ++step) {
        SCOPED_TRACE(step);
        // 0, then -0.99 s and +0.99 s in turn: always within s of the first position. (The
        // flags are made at step 1 and again at step 2, after the kept keys are put in SOFA's
        // order, with the sphere near the points.)
        ball_state.position[0].x() = step == 0 ? 0.0 : (step % 2 == 1 ? -0.99 : 0.99) * slack;
        const SceneDetection& got = pipelines.cached.detect();
        const SceneDetection& ref = pipelines.plain.detect();
        expect_identical(got, ref);
        ASSERT_EQ(pipelines.cached.candidates_evaluated(), pipelines.plain.candidates_evaluated());
        total += count_outputs(got);
    }
    const auto& stats = pipelines.cached.candidate_cache_stats();
    EXPECT_EQ(stats.collected, 1u);  // one generation throughout
    EXPECT_EQ(stats.reused, 11u);
    // the points deep inside (x <= c + reach - 2 s at the flags' detection: 61) skip their box
    // test at every detection after the flags' last one (steps 3 to 11)
    EXPECT_EQ(stats.sure_keys_skipped, 61u * 9u);
    EXPECT_GT(total, 12u * 60u);
}

// A Point model's elements have no extent: its slack starts at 1/8 of 10⁻³ of its extent and
// may grow up to a quarter of the points' spacing (root extent / √n), so a cube's corners
// drifting 4 mm a step over a static floor soon keep their candidates for two steps or more
// (bounded by a quarter of 10⁻³ of the extent, the slack gave up at once and the pair was
// traversed at every step), and give the traversal's outputs.
TEST(NarrowPhase, MovingPointsKeepTheirCandidatesForSeveralSteps) {
    IntersectionParams params = IntersectionParams::min_proximity();
    params.alarm_distance = 0.5;
    params.contact_distance = 0.1;
    auto floor =
        test::triangle_mesh({Vec3(-5, -5, 0), Vec3(5, -5, 0), Vec3(5, 5, 0), Vec3(-5, 5, 0)}, {{0, 1, 2}, {0, 2, 3}});
    TriangleModel tris(floor->state, floor->topo, static_mp("floor"));
    std::vector<Vec3> corners;
    for (int k = 0; k < 8; ++k) corners.emplace_back(0.3 + (k & 1), 0.1 + ((k >> 1) & 1), 0.3 + ((k >> 2) & 1));
    Vec3State cube = test::make_state(corners);
    PointModel points(cube, nullptr, mp("corners"));
    const std::vector<CollisionModel*> models = {&tris, &points};
    CachedAndPlain pipelines(params, models);
    std::size_t total = 0;
    for (int step = 0; step < 60; ++step) {
        SCOPED_TRACE(step);
        const SceneDetection& got = pipelines.cached.detect();
        expect_identical(got, pipelines.plain.detect());
        total += count_outputs(got);
        for (Vec3& p : cube.position) p += Vec3(0.001, 0.0, -0.004);
    }
    EXPECT_GE(total, 60u * 4u);  // the four lower corners are within the alarm distance throughout
    const auto& stats = pipelines.cached.candidate_cache_stats();
    EXPECT_EQ(stats.reused + stats.collected, 60u);  // never traversed without the cache
    EXPECT_GT(stats.reused, stats.collected) << stats.collected << " collected, " << stats.reused << " reused";
}

// One sphere falling under gravity past a static grid of points, its alarm box covering most of
// the grid (CompositeCollisionPipeline's sphere and torus): nearly every kept key overlaps, so
// the slack, bounded by a quarter of the sphere's extent before, also doubles while generations
// last up to kCheapSlackRefits refits, up to half the alarm distance, and the pair is collected
// far less often; the outputs stay the traversal's.
TEST(NarrowPhase, ASlackThatAddsFewCandidatesGrowsPastAQuarterOfTheExtent) {
    IntersectionParams params = IntersectionParams::new_proximity();
    params.alarm_distance = 5.0;
    params.contact_distance = 1.0;
    std::vector<Vec3> grid;
    for (int i = 0; i < 13; ++i)
        for (int j = 0; j < 13; ++j) grid.emplace_back(-3.0 + 0.5 * i, 0.0, -3.0 + 0.5 * j);
    Vec3State plane = test::make_state(grid);
    PointModel points(plane, nullptr, static_mp("grid"));
    Vec3State ball = test::make_state({Vec3(0.3, 10.0, 0.2)});
    SphereModel sphere(ball, 1.0, {}, mp("ball"));
    const std::vector<CollisionModel*> models = {&sphere, &points};
    CachedAndPlain pipelines(params, models);
    double speed = 0.0;
    std::size_t total = 0;
    for (int step = 0; step < 300; ++step) {
        SCOPED_TRACE(step);
        const SceneDetection& got = pipelines.cached.detect();
        expect_identical(got, pipelines.plain.detect());
        total += count_outputs(got);
        speed += 9.81 * 0.01;  // m/s after each 10 ms step
        ball.position[0].y() -= speed * 0.01;
    }
    EXPECT_EQ(total, 13471u);  // the ball passes through the grid's alarm zone in 91 steps
    const auto& stats = pipelines.cached.candidate_cache_stats();
    // 28 collected and 63 reused with the slack bounded by a quarter of the sphere's extent
    EXPECT_EQ(stats.collected, 11u) << stats.reused << " reused";
    EXPECT_EQ(stats.reused, 80u);
}

TEST(NarrowPhase, CandidateCacheInSofaOrderGivesTheSortedOutputsOfAnUnchangedScene) {
    // a scene that does not move: one collection, then kept candidates sorted into SOFA's order
    // as soon as the outputs sorted at the steps outnumber them; every step's outputs stay the
    // sorted outputs of the first step, bit for bit
    MeshScene sc(11, true);
    const IntersectionParams params = method_params(IntersectionMethod::MinProximity);
    CachedAndPlain pipelines(params, sc.models);
    CollisionPipeline& cached = pipelines.cached;
    CollisionPipeline& plain = pipelines.plain;
    const SceneDetection ref = plain.detect();
    EXPECT_GT(count_outputs(ref), 100u);
    for (int step = 0; step < 40; ++step) expect_identical(cached.detect(), ref);
    const auto& stats = cached.candidate_cache_stats();
    EXPECT_GT(stats.sofa_order_sorts, 0u);
    EXPECT_GT(stats.in_sofa_order, 20u * stats.sofa_order_sorts);
}

TEST(NarrowPhase, CandidateCacheFollowsSphereCloudsThatMoveFast) {
    // motion larger than any slack at every step: a new collection each step, same outputs
    SphereScene sc(4);
    std::mt19937 g(5);
    const IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    CachedAndPlain pipelines(params, sc.models);
    CollisionPipeline& cached = pipelines.cached;
    CollisionPipeline& plain = pipelines.plain;
    std::size_t total = 0;
    for (int step = 0; step < 8; ++step) {
        expect_identical(cached.detect(), plain.detect());
        total += count_outputs(cached.detections());
        sc.jiggle(g, 0.2);
    }
    EXPECT_GT(total, 800u);
}

}  // namespace
}  // namespace penalty
