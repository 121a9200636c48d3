// CollisionPipeline (collision/collision_pipeline.cpp), the detection driver: its refusals (bad
// options, a null model, a model it does not hold), SOFA's depth reset, which model pairs a
// detection lists (BruteForceBroadPhase's root-cube test with the pair's margin, empty models,
// a model with itself, inactive models), the closed-form outputs of a point pair through it,
// models added after detections, detect_pair, the unsupported pairs, a narrow-phase override,
// each near pair's output list kept with it, when the pairs run in parallel, and a static model's tree (built once,
// again when its size changes). The outputs against the exhaustive loop and SOFA's order are test_narrow_phase.cpp's
// and test_sofa_traversal_order.cpp's.
#include "pipeline_references.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace penalty {
namespace test_collision_pipeline {

using namespace test_pipeline;
using ::testing::HasSubstr;

/// The message of the std::invalid_argument `f` throws ("no error" if none).
template <class F>
std::string invalid_argument_of(F&& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

/// NewProximity, alarmDistance 0.05, contactDistance 0.02.
IntersectionParams proximity() { return method_params(IntersectionMethod::NewProximity); }

/// Two point models of one point each (different nodes), their states kept with them.
struct TwoPoints {
    Vec3State sa, sb;
    std::unique_ptr<PointModel> a, b;
    TwoPoints(const Vec3& pa, const Vec3& pb, double cd_a = 0.0, double cd_b = 0.0) {
        sa = test::make_state({pa});
        sb = test::make_state({pb});
        a = std::make_unique<PointModel>(sa, nullptr, mp("a", 0, false, {}, cd_a));
        b = std::make_unique<PointModel>(sb, nullptr, mp("b", 1, false, {}, cd_b));
    }
    [[nodiscard]] std::vector<CollisionModel*> models() const { return {a.get(), b.get()}; }
};

TEST(CollisionPipeline, RefusesLeafSizeZeroRebuildRatioBelowOneAndBadParameters) {
    CollisionPipelineOptions leaf;
    leaf.leaf_size = 0;
    EXPECT_EQ(invalid_argument_of([&] { CollisionPipeline p(proximity(), leaf); }),
              "CollisionPipeline: leaf_size must be >= 1");
    for (const double ratio : {0.5, std::numeric_limits<double>::quiet_NaN()}) {
        CollisionPipelineOptions o;
        o.rebuild_ratio = ratio;
        EXPECT_EQ(invalid_argument_of([&] { CollisionPipeline p(proximity(), o); }),
                  "CollisionPipeline: rebuild_ratio must be >= 1");
    }
    CollisionPipelineOptions one;  // the bounds themselves are accepted
    one.leaf_size = 1;
    one.rebuild_ratio = 1.0;
    EXPECT_EQ(invalid_argument_of([&] { CollisionPipeline p(proximity(), one); }), "no error");
    IntersectionParams bad = proximity();
    bad.alarm_distance = -1.0;
    EXPECT_EQ(invalid_argument_of([&] { CollisionPipeline p(bad); }),
              "NewProximityIntersection: parameter alarmDistance is -1 (must be finite and >= 0)");
}

TEST(CollisionPipeline, ANegativeDepthIsSofasSixAndOthersAreKept) {
    for (const auto& [given, kept] : {std::pair{-1, 6}, std::pair{-7, 6}, std::pair{0, 0}, std::pair{3, 3}}) {
        CollisionPipelineOptions o;
        o.depth = given;
        EXPECT_EQ(CollisionPipeline(proximity(), o).options().depth, kept) << "depth " << given;
    }
}

TEST(CollisionPipeline, SetModelsRefusesANullModelByItsPlace) {
    TwoPoints sc(Vec3(0, 0, 0), Vec3(1, 0, 0));
    CollisionPipeline pipe(proximity());
    EXPECT_EQ(invalid_argument_of([&] {
                  pipe.set_models({sc.a.get(), nullptr, sc.b.get()});
              }),
              "CollisionPipeline::set_models(): model 1 is null");
}

TEST(CollisionPipeline, DetectPairRefusesAModelItDoesNotHold) {
    TwoPoints sc(Vec3(0, 0, 0), Vec3(0.01, 0, 0));
    Vec3State other_state = test::make_state({Vec3(0, 0, 0)});
    PointModel stranger(other_state, nullptr, mp("stranger", 2));
    CollisionPipeline pipe(proximity());
    pipe.set_models(sc.models());
    (void)pipe.detect();
    DetectionOutputList out;
    EXPECT_EQ(invalid_argument_of([&] { pipe.detect_pair(stranger, *sc.a, out); }),
              "CollisionPipeline: model 'stranger' is not registered");
    EXPECT_EQ(invalid_argument_of([&] { pipe.detect_pair(*sc.b, stranger, out); }),
              "CollisionPipeline: model 'stranger' is not registered");
}

TEST(CollisionPipeline, APointPairGivesTheClosedFormOutputWithEitherDetection) {
    // points 0.06 m apart along (3, 0, 4)/5, model contact distances 0.01 and 0.004: alarm
    // 0.05 + 0.014 = 0.064 > 0.06, so one output of value 0.06 − (0.02 + 0.014) (NewProximity's
    // point–point: distance minus the full contact distance), normal from b's point to a's,
    // keyed (b, a) since of two models of one type the later comes first (registered order).
    const Vec3 u(0.6, 0.0, 0.8);
    const Vec3 pa(0.1, -0.2, 0.3);
    const Vec3 pb = pa + 0.06 * u;
    for (const auto detection : {ContactDetection::bvh, ContactDetection::exhaustive}) {
        SCOPED_TRACE(detection == ContactDetection::bvh ? "bvh" : "exhaustive");
        TwoPoints sc(pa, pb, 0.01, 0.004);
        CollisionPipeline pipe(proximity(), {}, detection);
        pipe.set_models(sc.models());
        const SceneDetection& got = pipe.detect();
        ASSERT_EQ(got.size(), 1u);
        EXPECT_EQ(got[0].model1, sc.b.get());
        EXPECT_EQ(got[0].model2, sc.a.get());
        EXPECT_EQ(got[0].support, PairSupport::Supported);
        EXPECT_TRUE(got[0].narrow_phase);
        EXPECT_FALSE(got[0].skipped);
        ASSERT_EQ(got[0].outputs.size(), 1u);
        const DetectionOutput& o = got[0].outputs[0];
        EXPECT_EQ(o.elem1.value(), 0);
        EXPECT_EQ(o.elem2.value(), 0);
        EXPECT_NEAR(o.value, 0.06 - 0.034, 1e-15);
        EXPECT_TRUE((o.point[0] - pb).isZero(0.0));
        EXPECT_TRUE((o.point[1] - pa).isZero(0.0));
        EXPECT_NEAR((o.normal + u).norm(), 0.0, 1e-15);
        EXPECT_EQ(pipe.detections().size(), 1u);  // detections() is the last detect()'s result
        EXPECT_EQ(&pipe.detections(), &got);
    }
}

TEST(CollisionPipeline, APairIsListedWhenItsRootBoxesAreWithinTheMarginOnEveryAxis) {
    // a: two points along y; b: one point off a's box in x and z by the gaps (y in a's range).
    // Each point's box is grown by its model's contact distance (SOFA's cubes: 0.01 and 0.02)
    // and the pair's margin is alarm + both contact distances = 0.05 + 0.01 + 0.02 = 0.08
    // (BaseProximityIntersection::testIntersection(Cube&, Cube&)): gaps up to 0.11 on every
    // axis, SOFA's broad phase hands the pair to the narrow phase (listed, with no output: the
    // points are 0.5 m apart); beyond on one axis, the pair is not listed.
    for (const auto detection : {ContactDetection::bvh, ContactDetection::exhaustive}) {
        SCOPED_TRACE(detection == ContactDetection::bvh ? "bvh" : "exhaustive");
        for (const auto& [gap_x, gap_z, listed] : {std::tuple{0.105, 0.105, true}, std::tuple{0.115, 0.0, false},
                                                   std::tuple{0.0, 0.115, false}, std::tuple{0.109, 0.0, true}}) {
            Vec3State sa = test::make_state({Vec3(0, 0, 0), Vec3(0, 1, 0)});
            Vec3State sb = test::make_state({Vec3(gap_x, 0.5, -gap_z)});
            PointModel a(sa, nullptr, mp("a", 0, false, {}, 0.01));
            PointModel b(sb, nullptr, mp("b", 1, false, {}, 0.02));
            CollisionPipeline pipe(proximity(), {}, detection);
            pipe.set_models({&a, &b});
            const SceneDetection& got = pipe.detect();
            ASSERT_EQ(got.size(), listed ? 1u : 0u) << "gaps " << gap_x << ", " << gap_z;
            if (listed) {
                EXPECT_TRUE(got[0].narrow_phase);
                EXPECT_TRUE(got[0].outputs.empty());
            }
        }
    }
}

TEST(CollisionPipeline, EmptyModelsAreNeverListedAndAModelWithItselfAlwaysIs) {
    // a self-colliding model far from everything is listed with itself (its root box meets
    // itself), without outputs; an empty self-colliding model overlapping it is listed with
    // nothing, itself included.
    Vec3State lone = test::make_state({Vec3(5, 5, 5)});
    Vec3State none;
    PointModel a(lone, nullptr, mp("lone", 0, true));
    PointModel e(none, nullptr, mp("empty", 1, true));
    for (const auto detection : {ContactDetection::bvh, ContactDetection::exhaustive}) {
        CollisionPipeline pipe(proximity(), {}, detection);
        pipe.set_models({&a, &e});
        const SceneDetection& got = pipe.detect();
        ASSERT_EQ(got.size(), 1u);
        EXPECT_EQ(got[0].model1, &a);
        EXPECT_EQ(got[0].model2, &a);
        EXPECT_TRUE(got[0].outputs.empty());
    }
}

TEST(CollisionPipeline, EachNearPairKeepsItsOwnOutputListAndALeavingPairsListIsFreed) {
    // a: 40 points within the alarm distance of b's point (40 outputs); (c, d) and (e, f): one
    // output each, far away. A second detection with nothing moved: each pair writes into the
    // list it had (the same storage). Then b leaves: (c, d) and (e, f) move up one place each,
    // and neither may take the departed pair's list (its capacity of 40 outputs or more).
    std::vector<Vec3> cloud;
    for (int i = 0; i < 40; ++i) cloud.emplace_back(0.001 * i, 0.0, 0.0);
    Vec3State sa = test::make_state(cloud);
    Vec3State sb = test::make_state({Vec3(0.02, 0.03, 0.0)});
    Vec3State sc = test::make_state({Vec3(10, 0, 0)});
    Vec3State sd = test::make_state({Vec3(10.03, 0, 0)});
    Vec3State se = test::make_state({Vec3(20, 0, 0)});
    Vec3State sf = test::make_state({Vec3(20.03, 0, 0)});
    PointModel a(sa, nullptr, mp("a", 0)), b(sb, nullptr, mp("b", 1)), c(sc, nullptr, mp("c", 2)),
        d(sd, nullptr, mp("d", 3)), e(se, nullptr, mp("e", 4)), f(sf, nullptr, mp("f", 5));
    CollisionPipeline pipe(proximity(), {}, ContactDetection::bvh);
    pipe.set_models({&a, &b, &c, &d, &e, &f});
    const auto outputs_of = [&](const CollisionModel* m) -> const DetectionOutputList& {
        for (const ModelPairDetection& p : pipe.detections())
            if (p.model1 == m || p.model2 == m) return p.outputs;
        throw std::logic_error("pair not listed");
    };
    ASSERT_EQ(pipe.detect().size(), 3u);
    ASSERT_EQ(outputs_of(&a).size(), 40u);
    ASSERT_EQ(outputs_of(&c).size(), 1u);
    ASSERT_EQ(outputs_of(&e).size(), 1u);
    const DetectionOutput* storage_a = outputs_of(&a).data();
    const DetectionOutput* storage_c = outputs_of(&c).data();
    ASSERT_EQ(pipe.detect().size(), 3u);
    EXPECT_EQ(outputs_of(&a).data(), storage_a);
    EXPECT_EQ(outputs_of(&c).data(), storage_c);
    sb.position[0] = Vec3(-10, 0, 0);
    const SceneDetection& got = pipe.detect();
    ASSERT_EQ(got.size(), 2u);
    for (const ModelPairDetection& p : got) {
        EXPECT_EQ(p.outputs.size(), 1u) << p.model1->name();
        EXPECT_LT(p.outputs.capacity(), 40u) << p.model1->name();
    }
}

TEST(CollisionPipeline, AnInactiveModelHasNoTreeAndNoPairTheExhaustiveDetectionNoTrees) {
    TwoPoints sc(Vec3(0, 0, 0), Vec3(0.01, 0, 0));
    Vec3State sc_state = test::make_state({Vec3(0.02, 0, 0)});
    PointModel off(sc_state, nullptr, mp("off", 2));
    off.params().active = false;
    CollisionPipeline bvh(proximity(), {}, ContactDetection::bvh);
    bvh.set_models({sc.a.get(), sc.b.get(), &off});
    const SceneDetection& got = bvh.detect();
    ASSERT_EQ(got.size(), 1u);  // (b, a) only
    EXPECT_EQ(got[0].model1, sc.b.get());
    EXPECT_FALSE(bvh.tree(0).empty());
    EXPECT_FALSE(bvh.tree(1).empty());
    EXPECT_TRUE(bvh.tree(2).empty());
    EXPECT_EQ(bvh.candidates_evaluated(), 1u);
    CollisionPipeline exhaustive(proximity(), {}, ContactDetection::exhaustive);
    exhaustive.set_models({sc.a.get(), sc.b.get(), &off});
    expect_identical(exhaustive.detect(), got);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(exhaustive.tree(i).empty());
    EXPECT_EQ(exhaustive.candidates_evaluated(), 0u);
}

TEST(CollisionPipeline, AModelAddedAfterDetectionsJoinsTheNextAsIfSetWithTheOthers) {
    for (const auto detection : {ContactDetection::bvh, ContactDetection::exhaustive}) {
        TwoPoints sc(Vec3(0, 0, 0), Vec3(0.03, 0, 0));
        CollisionPipeline grown(proximity(), {}, detection);
        grown.add_model(*sc.a);
        EXPECT_TRUE(grown.detect().empty());  // a alone, no self-collision
        EXPECT_TRUE(grown.detect().empty());
        grown.add_model(*sc.b);
        ASSERT_EQ(grown.models().size(), 2u);
        EXPECT_EQ(grown.models()[1], sc.b.get());
        const SceneDetection got = grown.detect();
        CollisionPipeline set(proximity(), {}, detection);
        set.set_models(sc.models());
        ASSERT_EQ(got.size(), 1u);
        EXPECT_EQ(got[0].outputs.size(), 1u);
        expect_identical(got, set.detect());
        if (detection == ContactDetection::bvh) {
            EXPECT_EQ(grown.tree(1).build_count(), 1u);
        }
    }
}

TEST(CollisionPipeline, DetectPairClearsItsListAndGivesTheOutputsOfDetect) {
    std::mt19937 g(5);
    Vec3State s1 = random_cloud(40, 0.2, g), s2 = random_cloud(40, 0.2, g, Vec3(0.1, 0, 0));
    SphereModel a(s1, 0.03, {}, mp("a", 0));
    SphereModel b(s2, 0.02, {}, mp("b", 1));
    CollisionPipeline pipe(proximity());
    pipe.set_models({&a, &b});
    const SceneDetection got = pipe.detect();
    ASSERT_EQ(got.size(), 1u);
    ASSERT_GT(got[0].outputs.size(), 10u);
    DetectionOutputList out(3);  // left over from elsewhere: cleared first
    out[0].value = -7.0;
    pipe.detect_pair(*got[0].model1, *got[0].model2, out);
    SceneDetection by_pair = got;
    by_pair[0].outputs = out;
    expect_identical(by_pair, got);
}

TEST(CollisionPipeline, PairsWithoutAnActiveIntersectorAreListedApartAndNotDetected) {
    // MinProximity with usePointPoint off: SOFA ignores Point–Point pairs
    IntersectionParams params = method_params(IntersectionMethod::MinProximity);
    params.use_point_point = false;
    TwoPoints sc(Vec3(0, 0, 0), Vec3(0.01, 0, 0));
    CollisionPipeline pipe(params);
    pipe.set_models(sc.models());
    EXPECT_TRUE(pipe.detect().empty());
    ASSERT_EQ(pipe.unsupported_pairs().size(), 1u);
    EXPECT_EQ(pipe.unsupported_pairs()[0], (ModelPair{sc.b.get(), sc.a.get()}));
    params.use_point_point = true;  // the same pair with its intersector
    CollisionPipeline on(params);
    on.set_models(sc.models());
    EXPECT_EQ(on.detect().size(), 1u);
    EXPECT_TRUE(on.unsupported_pairs().empty());
}

/// A narrow phase that records the pairs it is handed and answers one output per pair.
class RecordingNarrowPhase final : public NarrowPhaseOverride {
public:
    const std::vector<ModelPairDetection>& detect(const std::vector<ModelPairDetection>& broad_pairs) override {
        handed = broad_pairs;
        answer = broad_pairs;
        for (ModelPairDetection& d : answer) d.outputs.emplace_back().value = 1.5;
        return answer;
    }
    [[nodiscard]] const std::vector<ModelPairDetection>& detections() const override { return answer; }
    std::vector<ModelPairDetection> handed, answer;
};

TEST(CollisionPipeline, ANarrowPhaseOverrideIsHandedTheListedPairsAndGivesTheDetections) {
    TwoPoints sc(Vec3(0, 0, 0), Vec3(0.01, 0, 0));
    auto recording = std::make_shared<RecordingNarrowPhase>();
    CollisionPipelineOptions o;
    o.narrow_phase_override = recording;
    CollisionPipeline pipe(proximity(), o);
    pipe.set_models(sc.models());
    const SceneDetection& got = pipe.detect();
    EXPECT_EQ(&got, &recording->answer);
    EXPECT_EQ(&pipe.detections(), &recording->answer);
    ASSERT_EQ(recording->handed.size(), 1u);
    EXPECT_EQ(recording->handed[0].model1, sc.b.get());
    EXPECT_EQ(recording->handed[0].model2, sc.a.get());
    EXPECT_TRUE(recording->handed[0].narrow_phase);
    EXPECT_TRUE(recording->handed[0].outputs.empty());  // the pipeline's own narrow phase did not run
    EXPECT_EQ(pipe.candidates_evaluated(), 0u);
    ASSERT_EQ(got[0].outputs.size(), 1u);
    EXPECT_EQ(got[0].outputs[0].value, 1.5);
}

/// Overlapping sphere clouds of 150 spheres, simulated but not moving (no refit: the automatic
/// rule's moving elements are 0), and a far moving point cloud, in `threads` threads: per
/// detection whether the pairs ran in parallel, and the outputs of the last one.
struct ConcurrencyRun {
    std::vector<bool> concurrent;
    SceneDetection last;
};

ConcurrencyRun detect_three_clouds(int threads, const CollisionPipelineOptions& options, ContactDetection detection,
                                   std::size_t clouds = 3, std::size_t far_moving_points = 0) {
    ConcurrencyRun run;
    tbb::task_arena arena(threads);
    arena.execute([&] {
        std::mt19937 g(8);
        std::vector<Vec3State> states;
        for (std::size_t i = 0; i < clouds; ++i) states.push_back(random_cloud(150, 0.2, g, Vec3(0.05 * i, 0, 0)));
        std::vector<std::unique_ptr<SphereModel>> owned;
        std::vector<CollisionModel*> models;
        for (std::size_t i = 0; i < clouds; ++i) {
            CollisionModelParams p = mp("cloud", int(i));
            p.moving = false;
            owned.push_back(std::make_unique<SphereModel>(states[i], 0.02, std::vector<double>{}, p));
            models.push_back(owned.back().get());
        }
        // far from the clouds, moving: refitted at each detection, in no pair
        Vec3State far = random_cloud(far_moving_points, 0.5, g, Vec3(100, 0, 0));
        PointModel far_points(far, nullptr, mp("far", 99));
        if (far_moving_points > 0) models.push_back(&far_points);
        CollisionPipeline pipe(proximity(), options, detection);
        pipe.set_models(models);
        for (int step = 0; step < 3; ++step) {
            run.last = pipe.detect();
            run.concurrent.push_back(pipe.last_detection_concurrent());
        }
        for (ModelPairDetection& d : run.last) {  // the models die here: kept as their places
            d.model1 = reinterpret_cast<CollisionModel*>(
                std::uintptr_t(std::find(models.begin(), models.end(), d.model1) - models.begin()));
            d.model2 = reinterpret_cast<CollisionModel*>(
                std::uintptr_t(std::find(models.begin(), models.end(), d.model2) - models.begin()));
        }
    });
    return run;
}

TEST(CollisionPipeline, PairsRunInParallelAsTheOptionsAndTheLastDetectionSay) {
    using Flags = std::vector<bool>;
    CollisionPipelineOptions automatic;
    CollisionPipelineOptions always;
    always.pair_concurrency = PairConcurrency::always;
    CollisionPipelineOptions never;
    never.pair_concurrency = PairConcurrency::never;
    CollisionPipelineOptions sequential_narrow = always;
    sequential_narrow.narrow.parallel = false;
    const ConcurrencyRun one_thread = detect_three_clouds(1, always, ContactDetection::bvh);
    ASSERT_EQ(one_thread.last.size(), 3u);
    for (const ModelPairDetection& d : one_thread.last)
        EXPECT_GE(d.outputs.size(), 32u);  // each pair evaluates at least kMinCandidatesPerConcurrentPair
    EXPECT_EQ(one_thread.concurrent, Flags(3, false));
    // automatic: the first detection knows no pair's work; then 3 pairs of >= 32 candidates
    const ConcurrencyRun automatic_run = detect_three_clouds(2, automatic, ContactDetection::bvh);
    EXPECT_EQ(automatic_run.concurrent, (Flags{false, true, true}));
    expect_identical(automatic_run.last, one_thread.last);
    const ConcurrencyRun always_run = detect_three_clouds(2, always, ContactDetection::bvh);
    EXPECT_EQ(always_run.concurrent, Flags(3, true));
    expect_identical(always_run.last, one_thread.last);
    EXPECT_EQ(detect_three_clouds(2, never, ContactDetection::bvh).concurrent, Flags(3, false));
    EXPECT_EQ(detect_three_clouds(2, sequential_narrow, ContactDetection::bvh).concurrent, Flags(3, false));
    EXPECT_EQ(detect_three_clouds(2, always, ContactDetection::exhaustive).concurrent, Flags(3, false));
    // automatic, but more moving elements to refit than candidates (about 3 × 1000): in order
    EXPECT_EQ(detect_three_clouds(2, automatic, ContactDetection::bvh, 3, 20000).concurrent, Flags(3, false));
    EXPECT_EQ(detect_three_clouds(2, automatic, ContactDetection::bvh, 3, 200).concurrent, (Flags{false, true, true}));
    // one listed pair: nothing to run beside it
    EXPECT_EQ(detect_three_clouds(2, always, ContactDetection::bvh, 2).concurrent, Flags(3, false));
}

TEST(CollisionPipeline, AStaticModelsTreeIsBuiltOnceAndAgainWhenItsSizeChanges) {
    Vec3State floor_state = test::make_state({Vec3(0, 0, 0), Vec3(1, 0, 0)});
    Vec3State ball_state = test::make_state({Vec3(2, 0.01, 0)});
    PointModel floor(floor_state, nullptr, static_mp("floor"));
    PointModel ball(ball_state, nullptr, mp("ball", 1));
    CollisionPipeline pipe(proximity());
    pipe.set_models({&floor, &ball});
    EXPECT_TRUE(pipe.detect().empty());         // 1 m from the nearest floor point
    floor_state.position[1] = Vec3(1.9, 0, 0);  // moved, same size: a static model is not refitted
    EXPECT_TRUE(pipe.detect().empty());
    EXPECT_EQ(pipe.tree(0).build_count(), 1u);
    floor_state.resize(3);  // a third point next to the ball: the tree is built again
    floor_state.position[1] = Vec3(1, 0, 0);
    floor_state.position[2] = Vec3(2, 0, 0);
    const SceneDetection& got = pipe.detect();
    EXPECT_EQ(pipe.tree(0).build_count(), 2u);
    ASSERT_EQ(got.size(), 1u);
    ASSERT_EQ(got[0].outputs.size(), 1u);
    EXPECT_EQ(got[0].model1, &ball);
    EXPECT_EQ(got[0].outputs[0].elem2.value(), 2);
    EXPECT_NEAR(got[0].outputs[0].value, 0.01 - 0.02, 1e-15);
}

}  // namespace test_collision_pipeline
}  // namespace penalty
