// Broad and narrow phase (issue 4): BruteForceBroadPhase + BVHNarrowPhase via per-model bounding
// trees must find exactly what the exhaustive all-element-pairs loop finds (same pairs, same
// outputs, same order, bit for bit), for every method, with any number of threads. Both are
// CollisionPipeline (the one detection driver), with ContactDetection::bvh and ::exhaustive.
#include "detection_scenes.hpp"
#include "fixtures.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <tuple>

namespace penalty {
namespace {

using test::same_bits;

using test::random_cloud;
using test::random_radii;

CollisionModelParams mp(const char* name, int node = -1, bool self = false, std::vector<int> group = {},
                        double cd = 0.0) {
    CollisionModelParams p;
    p.name = name;
    p.node = node;
    p.self_collision = self;
    p.group = std::move(group);
    p.contact_distance = cd;
    return p;
}

// A static obstacle's parameters: not moving, not simulated (its candidate-cache slack is 0).
CollisionModelParams static_mp(const char* name) {
    CollisionModelParams p = mp(name);
    p.moving = false;
    p.simulated = false;
    return p;
}

IntersectionParams method_params(IntersectionMethod m) {
    IntersectionParams p;
    switch (m) {
        case IntersectionMethod::Discrete:
            p = IntersectionParams::discrete();
            break;
        case IntersectionMethod::NewProximity:
            p = IntersectionParams::new_proximity();
            break;
        case IntersectionMethod::MinProximity:
            p = IntersectionParams::min_proximity();
            break;
        case IntersectionMethod::LocalMinDistance:
            p = IntersectionParams::local_min_distance();
            break;
    }
    if (m != IntersectionMethod::Discrete) {
        p.alarm_distance = 0.05;
        p.contact_distance = 0.02;
    }
    return p;
}

bool same_output(const DetectionOutput& a, const DetectionOutput& b) {
    return a.elem1 == b.elem1 && a.elem2 == b.elem2 && a.id == b.id && same_bits(a.point[0], b.point[0]) &&
           same_bits(a.point[1], b.point[1]) && same_bits(a.normal, b.normal) && same_bits(a.value, b.value);
}

/// Same pairs, keys and outputs, in the same order, bit for bit.
void expect_identical(const SceneDetection& got, const SceneDetection& ref) {
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t k = 0; k < ref.size(); ++k) {
        ASSERT_EQ(got[k].model1, ref[k].model1) << "pair " << k;
        ASSERT_EQ(got[k].model2, ref[k].model2) << "pair " << k;
        ASSERT_EQ(got[k].outputs.size(), ref[k].outputs.size())
            << got[k].model1->name() << "-" << got[k].model2->name();
        for (std::size_t i = 0; i < ref[k].outputs.size(); ++i) {
            ASSERT_TRUE(same_output(got[k].outputs[i], ref[k].outputs[i]))
                << got[k].model1->name() << "-" << got[k].model2->name() << " output " << i << " elems ("
                << got[k].outputs[i].elem1 << "," << got[k].outputs[i].elem2 << ") vs (" << ref[k].outputs[i].elem1
                << "," << ref[k].outputs[i].elem2 << ")";
        }
    }
}

std::size_t count_outputs(const SceneDetection& d) {
    std::size_t n = 0;
    for (const auto& p : d) n += p.outputs.size();
    return n;
}

/// The pair (a, b) if it has outputs, else nullptr.
const ModelPairDetection* find_pair(const SceneDetection& d, const CollisionModel* a, const CollisionModel* b) {
    for (const auto& p : d)
        if (p.model1 == a && p.model2 == b && !p.outputs.empty()) return &p;
    return nullptr;
}

/// Outputs in ascending (elem1, elem2): comparable between pipelines made at different steps
/// (SOFA's order depends on the positions at a model's first detection, see SofaOrder below).
CollisionPipelineOptions canonical_order() {
    CollisionPipelineOptions o;
    o.sofa_output_order = false;
    return o;
}

/// The reference: the same driver with the exhaustive all-element-pairs narrow phase.
SceneDetection detect_scene_exhaustive(const IntersectionParams& params, std::vector<CollisionModel*> models) {
    CollisionPipeline pipe(params, canonical_order(), ContactDetection::exhaustive);
    pipe.set_models(std::move(models));
    return pipe.detect();
}

// ---------------------------------------------------------------------------------------------
// Scenes

/// Sphere clouds: self-collision on and off, groups, a rigid sphere model, per-model skins.
struct SphereScene {
    Vec3State sa, sb, sc;
    Rigid3State sr;
    std::unique_ptr<SphereModel> a, b, c;
    std::unique_ptr<RigidSphereModel> r;
    std::vector<CollisionModel*> models;

    explicit SphereScene(std::uint32_t seed) {
        std::mt19937 g(seed);
        sa = random_cloud(400, 1.0, g);
        sb = random_cloud(300, 1.0, g, Vec3(0.3, 0, 0));
        sc = random_cloud(300, 1.0, g, Vec3(0, 0.3, 0));
        sr.resize(150);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (auto& f : sr.position) f.center = Vec3(u(g), u(g), u(g));
        a = std::make_unique<SphereModel>(sa, 0.05, random_radii(400, 0.02, 0.07, g), mp("A", 0, true, {}, 0.01));
        b = std::make_unique<SphereModel>(sb, 0.04, std::vector<double>{}, mp("B", 1, false, {1}));
        c = std::make_unique<SphereModel>(sc, 0.04, random_radii(100, 0.03, 0.05, g), mp("C", 2, true, {1, 2}));
        r = std::make_unique<RigidSphereModel>(sr, 0.06, std::vector<double>{}, mp("R", 3, false, {3}, 0.005));
        models = {a.get(), b.get(), c.get(), r.get()};
    }
    void jiggle(std::mt19937& g, double s) {
        for (auto* st : {&sa, &sb, &sc})
            for (auto& p : st->position) p += test::rand_vec(g, s);
        for (auto& f : sr.position) f.center += test::rand_vec(g, s);
    }
};

/// Triangle meshes with their edges and vertices in the same node (self-collision filters),
/// a second torus, and a point cloud.
struct MeshScene {
    std::unique_ptr<test::TorusMesh> t1, t2;
    Vec3State cloud;
    std::unique_ptr<TriangleModel> tri1, tri2;
    std::unique_ptr<LineModel> line1;
    std::unique_ptr<PointModel> pts1, pts2, free_pts;
    std::unique_ptr<SphereModel> balls;
    std::vector<CollisionModel*> models;

    MeshScene(std::uint32_t seed, bool self) {
        std::mt19937 g(seed);
        t1 = test::make_torus(28, 12, 0.5, 0.18, Vec3::Zero(), g, 0.3);
        t2 = test::make_torus(20, 10, 0.4, 0.15, Vec3(0.35, 0.1, 0.12), g, 0.3);
        cloud = random_cloud(500, 0.8, g);
        tri1 = std::make_unique<TriangleModel>(t1->state, t1->topo, mp("torus1", 1, self, {}, 0.005));
        line1 = std::make_unique<LineModel>(t1->state, t1->topo, mp("torus1-edges", 1, self));
        pts1 = std::make_unique<PointModel>(t1->state, &t1->topo, mp("torus1-points", 1, self));
        tri2 = std::make_unique<TriangleModel>(t2->state, t2->topo, mp("torus2", 2, false));
        pts2 = std::make_unique<PointModel>(t2->state, &t2->topo, mp("torus2-points", 2, false));
        free_pts = std::make_unique<PointModel>(cloud, nullptr, mp("cloud", 3, false, {}, 0.01));
        balls = std::make_unique<SphereModel>(cloud, 0.03, std::vector<double>{}, mp("balls", 4, false));
        models = {tri1.get(), line1.get(), pts1.get(), tri2.get(), pts2.get(), free_pts.get(), balls.get()};
    }
    void jiggle(std::mt19937& g, double s) {
        for (auto* st : {&t1->state, &t2->state, &cloud})
            for (auto& p : st->position) p += test::rand_vec(g, s);
    }
};

constexpr IntersectionMethod kMethods[] = {IntersectionMethod::Discrete, IntersectionMethod::NewProximity,
                                           IntersectionMethod::MinProximity, IntersectionMethod::LocalMinDistance};

// ---------------------------------------------------------------------------------------------
// Bounding tree

TEST(Bvh, IsAValidTreeOverTheElementBoxes) {
    std::mt19937 g(7);
    Vec3State st = random_cloud(1000, 1.0, g);
    SphereModel m(st, 0.03, random_radii(1000, 0.01, 0.05, g), mp("s"));
    Bvh t;
    t.build(m, 4);
    ASSERT_FALSE(t.empty());
    EXPECT_EQ(t.build_count(), 1u);
    // permutation of the elements
    auto o = t.order();
    std::sort(o.begin(), o.end());
    for (std::uint32_t i = 0; i < 1000; ++i) ASSERT_EQ(o[i], i);
    // leaves of <= 4 elements, boxes contain their elements / children, counts add up
    std::size_t leaf_elems = 0;
    auto contains = [](const Aabb& outer, const Aabb& inner) {
        return (outer.min.array() <= inner.min.array()).all() && (outer.max.array() >= inner.max.array()).all();
    };
    for (std::size_t k = 0; k < t.nodes().size(); ++k) {
        const BvhNode& n = t.nodes()[k];
        if (n.leaf()) {
            EXPECT_LE(n.count, 4u);
            EXPECT_GE(n.count, 1u);
            leaf_elems += n.count;
            for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
                ASSERT_TRUE(contains(n.box, t.element_boxes()[t.order()[s]]));
        } else {
            const BvhNode& l = t.nodes()[k + 1];
            const BvhNode& r = t.nodes()[n.right];
            EXPECT_EQ(l.count + r.count, n.count);
            EXPECT_EQ(l.first, n.first);
            EXPECT_EQ(r.first, n.first + l.count);
            ASSERT_TRUE(contains(n.box, l.box) && contains(n.box, r.box));
        }
    }
    EXPECT_EQ(leaf_elems, 1000u);
    // balanced median split: 1000 -> 500 -> 250 -> 125 -> 62/63 -> 31/32 -> 15/16 -> 7/8 -> 3/4
    EXPECT_EQ(t.depth(), 9);
    EXPECT_EQ(t.nodes().size(), 2 * 256u - 1);
    for (std::uint32_t i = 0; i < 1000; ++i)
        ASSERT_TRUE(same_bits(t.element_boxes()[i].min, m.element_box(Index(i)).min));
}

TEST(Bvh, RefitKeepsTheTreeForSmallMotionAndRebuildsWhenDegraded) {
    std::mt19937 g(8);
    Vec3State st = random_cloud(2000, 1.0, g);
    SphereModel m(st, 0.02, {}, mp("s"));
    Bvh t;
    t.build(m);
    for (auto& p : st.position) p += test::rand_vec(g, 0.001);
    EXPECT_FALSE(t.refit(m));
    EXPECT_EQ(t.build_count(), 1u);
    EXPECT_TRUE(same_bits(t.root_box().max, m.model_box().max));
    EXPECT_TRUE(same_bits(t.root_box().min, m.model_box().min));
    // scramble: every element moves across the box -> the refitted tree is far worse
    st.position = random_cloud(2000, 1.0, g).position;
    EXPECT_TRUE(t.refit(m));
    EXPECT_EQ(t.build_count(), 2u);
}

TEST(Bvh, NonFinitePositionNamesModelAndElement) {
    std::mt19937 g(9);
    Vec3State st = random_cloud(100, 1.0, g);
    st.position[17].y() = std::numeric_limits<double>::quiet_NaN();
    SphereModel m(st, 0.02, {}, mp("cloud"));
    Bvh t;
    try {
        t.build(m);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("cloud"), std::string::npos) << w;
        EXPECT_NE(w.find("element 17"), std::string::npos) << w;
        EXPECT_NE(w.find("not finite"), std::string::npos) << w;
    }
}

// ---------------------------------------------------------------------------------------------
// Broad phase

TEST(BroadPhase, FollowsBruteForceBroadPhaseOrderAndFilters) {
    std::mt19937 g(11);
    Vec3State s = random_cloud(10, 1.0, g);
    auto tm = test::make_torus(8, 6, 0.5, 0.2, Vec3::Zero(), g);
    SphereModel a(s, 0.1, {}, mp("a", 0, true));             // self pair
    TriangleModel t(tm->state, tm->topo, mp("t", 1, true));  // self pair (Triangle-Triangle NP)
    PointModel p(tm->state, &tm->topo, mp("p", 1, true));    // same node as t: kept (self_collision)
    SphereModel off(s, 0.1, {}, mp("off"));
    off.params().active = false;
    SphereModel ns1(s, 0.1, {}, mp("ns1", 5, true));
    ns1.params().simulated = false;  // no self pair (non-simulated)
    SphereModel ns2(s, 0.1, {}, mp("ns2"));
    ns2.params().simulated = false;  // ns1-ns2 never pair
    SphereModel g1(s, 0.1, {}, mp("g1", -1, false, {4, 7}));
    SphereModel g2(s, 0.1, {}, mp("g2", -1, false, {7}));     // shares group 7 with g1
    PointModel p2(tm->state, &tm->topo, mp("p2", 1, false));  // same node as t, self_collision off
    std::vector<CollisionModel*> models = {&a, &t, &p, &off, &ns1, &ns2, &g1, &g2, &p2};
    std::vector<ModelPair> pairs, unsupported;
    broad_phase(IntersectionParams::new_proximity(), models, pairs, &unsupported);
    std::vector<std::string> got;
    for (const auto& q : pairs) got.push_back(q.model1->name() + "-" + q.model2->name());
    // SOFA's BruteForceBroadPhase::addCollisionModel: per model j, the self pair first, then the
    // earlier models in order; each pair (model j, earlier model) swapped only into registered
    // order (Triangle before Sphere and Point, Sphere before Point), so two models of one type
    // are keyed (later, earlier)
    const std::vector<std::string> expected = {"a-a",    "t-t",    "t-a",    "p-p",    "a-p",   "t-p",  "ns1-a",
                                               "t-ns1",  "ns1-p",  "ns2-a",  "t-ns2",  "ns2-p", "g1-a", "t-g1",
                                               "g1-p",   "g1-ns1", "g1-ns2", "g2-a",   "t-g2",  "g2-p", "g2-ns1",
                                               "g2-ns2", "a-p2",   "ns1-p2", "ns2-p2", "g1-p2", "g2-p2"};
    EXPECT_EQ(got, expected);
    EXPECT_TRUE(unsupported.empty());  // NewProximity detects every pair of these types
    // MinProximity ignores Triangle-Triangle: the kept pair goes to `unsupported`, not `pairs`
    broad_phase(IntersectionParams::min_proximity(), models, pairs, &unsupported);
    ASSERT_EQ(unsupported.size(), 1u);
    EXPECT_EQ(unsupported[0], (ModelPair{&t, &t}));
    EXPECT_EQ(pairs.size(), expected.size() - 1);
}

// ---------------------------------------------------------------------------------------------
// Narrow phase: equality with the exhaustive loop

TEST(NarrowPhase, SphereCloudsEqualExhaustiveForEveryMethodOverSteps) {
    for (const auto method : kMethods) {
        SCOPED_TRACE(intersection_method_name(method));
        for (std::uint32_t seed : {1u, 2u, 3u}) {
            SphereScene sc(seed);
            std::mt19937 g(seed + 100);
            const IntersectionParams params = method_params(method);
            CollisionPipeline pipe(params, canonical_order());
            pipe.set_models(sc.models);
            std::size_t total = 0;
            for (int step = 0; step < 3; ++step) {
                const SceneDetection got = pipe.detect();
                const SceneDetection ref = detect_scene_exhaustive(params, sc.models);
                expect_identical(got, ref);
                total += count_outputs(got);
                // groups: B and C share group 1 and never pair
                EXPECT_EQ(find_pair(got, sc.b.get(), sc.c.get()), nullptr);
                EXPECT_EQ(find_pair(got, sc.c.get(), sc.b.get()), nullptr);
                sc.jiggle(g, 0.02);
            }
            // hit rate: about 1000 spheres of radius ~0.045 in a box of side 2
            EXPECT_GT(total, 300u);
            SphereScene fresh(seed);
            const SceneDetection d = detect_scene_exhaustive(params, fresh.models);
            ASSERT_NE(find_pair(d, fresh.a.get(), fresh.a.get()), nullptr);  // self-collision on
            EXPECT_EQ(find_pair(d, fresh.b.get(), fresh.b.get()), nullptr);  // self-collision off
        }
    }
}

TEST(NarrowPhase, MeshScenesEqualExhaustiveForEveryMethodSelfCollisionOnAndOff) {
    for (const auto method : kMethods) {
        SCOPED_TRACE(intersection_method_name(method));
        for (const bool self : {false, true}) {
            for (const bool line_line : {false, true}) {
                MeshScene sc(42, self);
                std::mt19937 g(43);
                IntersectionParams params = method_params(method);
                params.use_line_line = line_line;
                CollisionPipeline pipe(params, canonical_order());
                pipe.set_models(sc.models);
                std::size_t total = 0;
                for (int step = 0; step < 2; ++step) {
                    const SceneDetection got = pipe.detect();
                    const SceneDetection ref = detect_scene_exhaustive(params, sc.models);
                    expect_identical(got, ref);
                    total += count_outputs(got);
                    sc.jiggle(g, 0.005);
                }
                if (method == IntersectionMethod::Discrete) {
                    EXPECT_GT(total, 0u);  // alarm 0: only touching elements
                } else {
                    EXPECT_GT(total, 500u);
                }
                const SceneDetection last = pipe.detect();
                // pairs of two models of torus1's node exist only with self-collision on
                std::size_t self_pairs = 0;
                for (const auto& p : last) self_pairs += same_node(*p.model1, *p.model2) ? 1 : 0;
                if (!self) {
                    EXPECT_EQ(self_pairs, 0u);
                } else if (method == IntersectionMethod::NewProximity || method == IntersectionMethod::MinProximity) {
                    // (LocalMinDistance's cone filters reject these near-surface self contacts)
                    EXPECT_GT(self_pairs, 0u);
                }
            }
        }
    }
}

TEST(NarrowPhase, TriangleTriangleWithoutNormalOverwriteRunsInParallelAndEqualsExhaustive) {
    // with the §14.4 fix the Triangle–Triangle kernel is read-only and evaluated in parallel chunks
    MeshScene sc(44, true);
    IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    params.quirks.fix_newproximity_triangle_triangle_normal_overwrite = true;
    CollisionPipelineOptions opt = canonical_order();
    opt.narrow.chunk_size = 16;
    CollisionPipeline pipe(params, opt);
    pipe.set_models(sc.models);
    const SceneDetection got = pipe.detect();
    expect_identical(got, detect_scene_exhaustive(params, sc.models));
    // same types: SOFA's broad phase keys the pair (later model, earlier model)
    const ModelPairDetection* tt = find_pair(got, sc.tri2.get(), sc.tri1.get());
    ASSERT_NE(tt, nullptr);
    EXPECT_GT(tt->outputs.size(), 100u);
}

TEST(NarrowPhase, TriangleTriangleWithNormalOverwriteWritesInOrderAndEvaluatesInParallel) {
    // SOFA's §14.4 overwrite runs over the candidates in order first, then the outputs are
    // computed in parallel chunks: the outputs and the stored normals are the sequential loop's.
    // Only the two triangle models: later pairs could overwrite the normals again.
    MeshScene par(44, true), seq(44, true), fresh(44, true);
    IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    CollisionPipelineOptions opt = canonical_order();
    opt.narrow.chunk_size = 16;
    CollisionPipeline pipe(params, opt);
    pipe.set_models({par.tri1.get(), par.tri2.get()});
    const SceneDetection got = pipe.detect();
    const SceneDetection ref = detect_scene_exhaustive(params, {seq.tri1.get(), seq.tri2.get()});
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t k = 0; k < got.size(); ++k) {
        ASSERT_EQ(got[k].outputs.size(), ref[k].outputs.size());
        for (std::size_t i = 0; i < got[k].outputs.size(); ++i)
            ASSERT_TRUE(same_output(got[k].outputs[i], ref[k].outputs[i])) << "pair " << k << " output " << i;
    }
    const ModelPairDetection* tt = find_pair(got, par.tri2.get(), par.tri1.get());
    ASSERT_NE(tt, nullptr);
    EXPECT_GT(tt->outputs.size(), 100u);
    fresh.tri1->update();
    fresh.tri2->update();
    std::size_t overwritten = 0;
    for (const auto& [a, b, f] : {std::tuple{par.tri1.get(), seq.tri1.get(), fresh.tri1.get()},
                                  std::tuple{par.tri2.get(), seq.tri2.get(), fresh.tri2.get()}}) {
        for (Index e = 0; e < Index(a->size()); ++e) {
            ASSERT_TRUE(same_bits(a->normal(e), b->normal(e))) << a->name() << " triangle " << e;
            overwritten += a->normal(e) != f->normal(e);
        }
    }
    EXPECT_GT(overwritten, 50u);  // the overwrite really happened, on many triangles
}

TEST(NarrowPhase, NormalOverwriteLastsThroughTheLaterPairsOfOneDetection) {
    // SOFA updates each model's normals once per detection (computeBoundingTree), so a normal that
    // one pair overwrote (§14.4) is the one a later pair of the same detection reads. Three
    // one-triangle models: B 0.1 above A, C 0.1 below A, B and C beyond each other's reach.
    // Pair (B, A), B one-sided: n_A := −n_B. Pair (C, A), C two-sided, A one-sided: n_C := −n_A,
    // which is n_B = +z; had A's normal been computed again between the pairs, n_C = −(+z).
    // With the pairs run in parallel on two threads (bvh), their writes run after them, in pair
    // order: the same normals.
    const tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    tbb::task_arena arena(2);
    for (const bool concurrent : {false, true})
        for (const ContactDetection detection : {ContactDetection::bvh, ContactDetection::exhaustive}) {
            if (concurrent && detection == ContactDetection::exhaustive) continue;
            auto a = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});           // n = +z
            auto b = test::triangle_mesh({{0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}}, {{0, 1, 2}});     // n = +z
            auto c = test::triangle_mesh({{0, 0, -0.1}, {0, 1, -0.1}, {1, 0, -0.1}}, {{0, 1, 2}});  // n = −z
            CollisionModelParams two_sided;
            two_sided.both_side = true;
            TriangleModel ta(a->state, a->topo), tb(b->state, b->topo), tc(c->state, c->topo, two_sided);
            IntersectionParams params = IntersectionParams::new_proximity();
            params.alarm_distance = 0.15;
            params.contact_distance = 0.05;
            CollisionPipelineOptions options;
            options.pair_concurrency = concurrent ? PairConcurrency::always : PairConcurrency::never;
            CollisionPipeline pipe(params, options, detection);
            pipe.set_models({&ta, &tb, &tc});
            for (int step = 0; step < 2; ++step) {  // the next detection computes them again first
                const SceneDetection* detected = nullptr;
                arena.execute([&] { detected = &pipe.detect(); });
                const SceneDetection& got = *detected;
                EXPECT_EQ(pipe.last_detection_concurrent(), concurrent);
                ASSERT_NE(find_pair(got, &tb, &ta), nullptr);
                ASSERT_NE(find_pair(got, &tc, &ta), nullptr);
                const ModelPairDetection* cb = find_pair(got, &tc, &tb);
                ASSERT_TRUE(cb == nullptr || cb->outputs.empty());
                EXPECT_EQ(ta.normal(0), Vec3(0, 0, -1))
                    << (detection == ContactDetection::bvh ? "bvh" : "exhaustive") << ", step " << step;
                EXPECT_EQ(tb.normal(0), Vec3(0, 0, 1))
                    << (detection == ContactDetection::bvh ? "bvh" : "exhaustive") << ", step " << step;
                EXPECT_EQ(tc.normal(0), Vec3(0, 0, 1))
                    << (detection == ContactDetection::bvh ? "bvh" : "exhaustive") << ", step " << step;
            }
        }
}

/// Every model type, with the beyond-SOFA pairs (Cylinder, Tetrahedron–Point) enabled.
TEST(NarrowPhase, MixedModelsWithBeyondSofaPairsEqualExhaustive) {
    std::mt19937 g(55);
    Rigid3State cyl_state, rs_state;
    cyl_state.resize(60);
    rs_state.resize(80);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (auto& f : cyl_state.position) f = RigidFrame{Vec3(u(g), u(g), u(g)), test::rand_quat(g)};
    for (auto& f : rs_state.position) f = RigidFrame{Vec3(u(g), u(g), u(g)), test::rand_quat(g)};
    // a soup of 200 small tetrahedra
    Vec3State tet_state;
    tet_state.resize(800);
    MeshTopology tet_topo;
    std::vector<Tetrahedron> tets;
    for (int t = 0; t < 200; ++t) {
        const Vec3 c(u(g), u(g), u(g));
        const Vec3 e0 = 0.1 * test::rand_unit(g), e1 = 0.1 * test::rand_unit(g), e2 = 0.1 * test::rand_unit(g);
        const bool pos = e0.dot(e1.cross(e2)) > 0.0;
        tet_state.position[std::size_t(4 * t)] = c;
        tet_state.position[std::size_t(4 * t + 1)] = c + e0;
        tet_state.position[std::size_t(4 * t + 2)] = c + (pos ? e1 : e2);
        tet_state.position[std::size_t(4 * t + 3)] = c + (pos ? e2 : e1);
        tets.push_back({4 * t, 4 * t + 1, 4 * t + 2, 4 * t + 3});
    }
    tet_topo.set_num_points(800);
    tet_topo.set_tetrahedra(tets);
    Vec3State cloud = random_cloud(1500, 1.0, g);
    auto torus = test::make_torus(24, 10, 0.6, 0.2, Vec3::Zero(), g, 0.2);
    CylinderModel cyl(cyl_state, 0.05, 0.3, Vec3::UnitY(), mp("cylinders", 1));
    RigidSphereModel rs(rs_state, 0.05, {}, mp("rigid-spheres", 2, false, {}, 0.01));
    TetrahedronModel tet(tet_state, tet_topo, mp("tetras", 3));
    PointModel pts(cloud, nullptr, mp("cloud", 4));
    SphereModel balls(cloud, 0.02, {}, mp("balls", 5, true));
    TriangleModel tri(torus->state, torus->topo, mp("torus", 6));
    LineModel lines(torus->state, torus->topo, mp("torus-edges", 6));
    std::vector<CollisionModel*> models = {&cyl, &rs, &tet, &pts, &balls, &tri, &lines};
    for (const auto method : kMethods) {
        SCOPED_TRACE(intersection_method_name(method));
        IntersectionParams params = method_params(method);
        params.enable_beyond_sofa_pairs = true;
        CollisionPipeline pipe(params, canonical_order());
        pipe.set_models(models);
        const SceneDetection got = pipe.detect();
        expect_identical(got, detect_scene_exhaustive(params, models));
        EXPECT_GT(count_outputs(got), method == IntersectionMethod::Discrete ? 20u : 500u);
        if (method == IntersectionMethod::NewProximity) {
            EXPECT_NE(find_pair(got, &cyl, &balls), nullptr);
            EXPECT_NE(find_pair(got, &tet, &pts), nullptr);
        }
    }
}

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

TEST(NarrowPhase, PairsWhoseRootBoxesAreApartAreNeitherTraversedNorLookedUp) {
    // A row of 12 sphere clouds 0.22 m apart (each about 0.24 m wide with its radii): each
    // overlaps its neighbours only. One cloud travels along the row, 4 mm a step (within the
    // cache's slack: every pair detection uses the cache). Of the 66 pairs only those whose root boxes are within the
    // margin reach the trees and the candidate cache (one cache statistic each); the outputs stay the exhaustive
    // loop's, with the pairs run in order and in parallel.
    constexpr int kClouds = 12;
    std::mt19937 g(21);
    std::vector<Vec3State> states(kClouds);
    std::vector<std::unique_ptr<SphereModel>> clouds;
    std::vector<std::string> names;
    for (int i = 0; i < kClouds; ++i) names.push_back("cloud" + std::to_string(i));
    std::vector<CollisionModel*> models;
    for (int i = 0; i < kClouds; ++i) {
        states[std::size_t(i)] = random_cloud(60, 0.1, g, Vec3(0.22 * i, 0.0, 0.0));
        clouds.push_back(std::make_unique<SphereModel>(states[std::size_t(i)], 0.02, std::vector<double>{},
                                                       mp(names[std::size_t(i)].c_str(), i)));
        models.push_back(clouds.back().get());
    }
    const IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    for (const auto concurrency : {PairConcurrency::never, PairConcurrency::always}) {
        SCOPED_TRACE(concurrency == PairConcurrency::never ? "pairs in order" : "pairs in parallel");
        std::vector<Vec3State> start = states;
        CollisionPipelineOptions options = canonical_order();
        options.pair_concurrency = concurrency;
        CollisionPipeline pipe(params, options);
        pipe.set_models(models);
        std::size_t pairs = 0, near_pairs = 0, outputs = 0;
        for (int step = 0; step < 60; ++step) {
            const SceneDetection& got = pipe.detect();
            expect_identical(got, detect_scene_exhaustive(params, models));
            pairs += got.size();
            for (const ModelPairDetection& d : got) {
                near_pairs += d.narrow_phase ? 1 : 0;
                if (!d.narrow_phase) {
                    EXPECT_TRUE(d.outputs.empty());
                }
            }
            outputs += count_outputs(got);
            for (Vec3& p : states[3].position) p += Vec3(0.004, 0.0, 0.0);
        }
        states = start;
        EXPECT_EQ(pairs, 60u * 66u);
        EXPECT_GT(outputs, 1000u);
        // neighbours only: 11 pairs a step, one more or less while the travelling cloud
        // is near a third one
        EXPECT_GE(near_pairs, 60u * 10u);
        EXPECT_LE(near_pairs, 60u * 13u);
        const auto& stats = pipe.candidate_cache_stats();
        EXPECT_EQ(stats.reused + stats.collected, near_pairs);
    }
}

TEST(NarrowPhase, ManyMovingModelsNearPairsEqualTheTestOfEveryPair) {
    // 160 sphere clouds (6 spheres, 0.05 m wide) drift in a 0.8 m box, each with its own skin
    // (contactDistance 0-20 mm, so margins differ by pair), some sharing a node (self-collision
    // filters), two of them empty: the BVH detection keeps its broad phase and finds the pairs
    // whose root boxes are within the margin by a sweep. Every step: the exhaustive driver's
    // pairs, narrow-phase flags and outputs. Between steps the models' filters change (one made
    // inactive then active again, groups, self-collision, both-sided), which must give the new
    // broad phase at once.
    constexpr int kClouds = 160;
    std::mt19937 g(20261127);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Vec3State> states(kClouds);
    std::vector<Vec3> velocity(kClouds);
    std::vector<std::unique_ptr<SphereModel>> clouds;
    std::vector<std::string> names;
    for (int i = 0; i < kClouds; ++i) names.push_back("cloud" + std::to_string(i));
    std::vector<CollisionModel*> models;
    for (int i = 0; i < kClouds; ++i) {
        const Vec3 centre(0.8 * unit(g), 0.8 * unit(g), 0.8 * unit(g));
        states[std::size_t(i)] = random_cloud(i == 7 || i == 50 ? 0 : 6, 0.025, g, centre);
        velocity[std::size_t(i)] = Vec3(unit(g) - 0.5, unit(g) - 0.5, unit(g) - 0.5) * 0.01;
        clouds.push_back(
            std::make_unique<SphereModel>(states[std::size_t(i)], 0.01, std::vector<double>{},
                                          mp(names[std::size_t(i)].c_str(), i % 150, false, {}, 0.02 * unit(g))));
        models.push_back(clouds.back().get());
    }
    const IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    for (const auto concurrency : {PairConcurrency::never, PairConcurrency::always}) {
        SCOPED_TRACE(concurrency == PairConcurrency::never ? "pairs in order" : "pairs in parallel");
        const std::vector<Vec3State> start = states;
        CollisionPipelineOptions options = canonical_order();
        options.pair_concurrency = concurrency;
        CollisionPipeline pipe(params, options);
        pipe.set_models(models);
        std::size_t pairs = 0, near_pairs = 0, outputs = 0, flag_steps = 0, most_near = 0;
        for (int step = 0; step < 60; ++step) {
            // the filters the broad phase reads, changed between detections
            if (step == 10) clouds[3]->params().active = false;
            if (step == 20) clouds[3]->params().active = true;
            if (step == 25) clouds[11]->params().group = {4}, clouds[12]->params().group = {4};
            if (step == 35) clouds[5]->params().self_collision = true, clouds[155]->params().self_collision = true;
            if (step == 45) clouds[20]->params().both_side = true;
            const SceneDetection& got = pipe.detect();
            const SceneDetection ref = detect_scene_exhaustive(params, models);
            expect_identical(got, ref);
            bool same_flags = true;
            for (std::size_t k = 0; k < ref.size(); ++k)
                same_flags = same_flags && got[k].narrow_phase == ref[k].narrow_phase;
            flag_steps += same_flags ? 1 : 0;
            pairs += got.size();
            std::size_t near_now = 0;
            for (const ModelPairDetection& d : got) {
                near_now += d.narrow_phase ? 1 : 0;
                if (!d.narrow_phase) {
                    EXPECT_TRUE(d.outputs.empty());
                }
            }
            near_pairs += near_now;
            most_near = std::max(most_near, near_now);
            outputs += count_outputs(got);
            for (int i = 0; i < kClouds; ++i) {
                Vec3& v = velocity[std::size_t(i)];
                for (Vec3& p : states[std::size_t(i)].position) p += v;
                if (!states[std::size_t(i)].position.empty()) {
                    const Vec3& p = states[std::size_t(i)].position[0];
                    for (int a = 0; a < 3; ++a)
                        if (p[a] < 0.0 || p[a] > 0.8) v[a] = -v[a];
                }
            }
        }
        states = start;
        EXPECT_EQ(flag_steps, 60u);
        // of about 12 800 pairs a step, a few per cent are near (more than 256 at some steps:
        // near_ is then radix-sorted); the clouds meet
        EXPECT_GT(pairs, 60u * 12000u);
        EXPECT_GT(near_pairs, pairs / 200);
        EXPECT_LT(near_pairs, pairs / 10);
        EXPECT_GT(most_near, 256u);
        EXPECT_GT(outputs, 100u);
    }
}

TEST(NarrowPhase, SelfCollisionFiltersAreApplied) {
    // torus1 triangles vs its own vertices (same node): no output of a triangle with one of its vertices
    MeshScene sc(5, true);
    const IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    CollisionPipeline pipe(params, canonical_order());
    pipe.set_models(sc.models);
    const SceneDetection d = pipe.detect();
    const ModelPairDetection* tp = find_pair(d, sc.tri1.get(), sc.pts1.get());
    ASSERT_NE(tp, nullptr);
    EXPECT_GT(tp->outputs.size(), 10u);
    for (const auto& o : tp->outputs)
        for (auto v : sc.tri1->triangle(o.elem1)) ASSERT_NE(v, o.elem2);
}

TEST(NarrowPhase, PointAndLineSelfCollisionSkipTopologicalNeighbours) {
    // a chain of 40 points 0.02 apart: neighbours (0.02) are filtered, second neighbours (0.04 <
    // alarm 0.05) collide, third neighbours (0.06) are too far -> exactly the 38 pairs (i+2, i)
    const int n = 40;
    Vec3State st;
    st.resize(n);
    for (int i = 0; i < n; ++i) st.position[std::size_t(i)] = Vec3(0.02 * i, 0.0, 0.0);
    MeshTopology topo;
    topo.set_num_points(std::size_t(n));
    std::vector<Edge> edges;
    for (int i = 0; i + 1 < n; ++i) edges.push_back({i, i + 1});
    topo.set_edges(edges);
    PointModel pts(st, &topo, mp("chain-points", 0, true));
    LineModel lines(st, topo, mp("chain-lines", 0, true));
    IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    params.use_line_line = true;
    CollisionPipeline pipe(params, canonical_order());
    pipe.set_models({&pts, &lines});
    const SceneDetection d = pipe.detect();
    expect_identical(d, detect_scene_exhaustive(params, {&pts, &lines}));
    const ModelPairDetection* pp = find_pair(d, &pts, &pts);
    ASSERT_NE(pp, nullptr);
    ASSERT_EQ(pp->outputs.size(), std::size_t(n - 2));
    for (std::size_t k = 0; k < pp->outputs.size(); ++k) {
        EXPECT_EQ(pp->outputs[k].elem1, Index(k + 2));
        EXPECT_EQ(pp->outputs[k].elem2, Index(k));
    }
    const ModelPairDetection* ll = find_pair(d, &lines, &lines);
    ASSERT_NE(ll, nullptr);
    EXPECT_GT(ll->outputs.size(), std::size_t(n / 2));
    for (const auto& o : ll->outputs) {
        EXPECT_GE(o.elem1 - o.elem2, 2) << "edges sharing a vertex must be filtered";
    }
    // the line-point pair of the same state and node: a line never meets its own end points
    const ModelPairDetection* lp = find_pair(d, &lines, &pts);
    ASSERT_NE(lp, nullptr);
    for (const auto& o : lp->outputs) {
        EXPECT_NE(lines.edge(o.elem1)[0], o.elem2);
        EXPECT_NE(lines.edge(o.elem1)[1], o.elem2);
    }
}

TEST(NarrowPhase, StaticModelIsBuiltOnce) {
    std::mt19937 g(21);
    Vec3State fixed = random_cloud(500, 1.0, g);
    Vec3State mov = random_cloud(500, 1.0, g);
    SphereModel f(fixed, 0.05, {}, mp("floor"));
    f.params().moving = false;
    f.params().simulated = false;
    SphereModel m(mov, 0.05, {}, mp("balls"));
    const IntersectionParams params = method_params(IntersectionMethod::NewProximity);
    CollisionPipeline pipe(params, canonical_order());
    pipe.set_models({&f, &m});
    for (int step = 0; step < 4; ++step) {
        const SceneDetection got = pipe.detect();
        expect_identical(got, detect_scene_exhaustive(params, {&f, &m}));
        EXPECT_GT(count_outputs(got), 20u);
        for (auto& p : mov.position) p += test::rand_vec(g, 0.01);
    }
    EXPECT_EQ(pipe.tree(0).build_count(), 1u);
    EXPECT_EQ(pipe.tree(1).build_count(), 1u);  // small motion: refitted, not rebuilt
    mov.position = random_cloud(500, 1.0, g).position;
    const SceneDetection got = pipe.detect();
    expect_identical(got, detect_scene_exhaustive(params, {&f, &m}));
    EXPECT_EQ(pipe.tree(1).build_count(), 2u);
}

// ---------------------------------------------------------------------------------------------
// Determinism with 1, 2 and 4 threads

SceneDetection run_with_threads(int threads, std::uint32_t seed, IntersectionMethod method) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    tbb::task_arena arena(threads);
    SceneDetection out;
    arena.execute([&] {
        MeshScene sc(seed, true);
        std::mt19937 g(seed);
        Vec3State big = random_cloud(20000, 1.0, g);
        SphereModel cloud(big, 0.01, random_radii(20000, 0.004, 0.012, g), mp("big", 9, true));
        std::vector<CollisionModel*> models = sc.models;
        models.push_back(&cloud);
        NarrowPhaseOptions narrow;
        narrow.chunk_size = 64;        // many chunks so that threads really interleave
        CollisionPipelineOptions opt;  // SOFA's order: thread-independent too
        opt.narrow = narrow;
        CollisionPipeline pipe(method_params(method), opt);
        pipe.set_models(models);
        out = pipe.detect();
        // the pointers die with the scene: keep the names in model-free form
        for (auto& p : out) {
            p.model1 = reinterpret_cast<CollisionModel*>(
                std::uintptr_t(std::find(models.begin(), models.end(), p.model1) - models.begin()));
            p.model2 = reinterpret_cast<CollisionModel*>(
                std::uintptr_t(std::find(models.begin(), models.end(), p.model2) - models.begin()));
        }
    });
    return out;
}

TEST(NarrowPhase, BitIdenticalWith1And2And4Threads) {
    for (const auto method : {IntersectionMethod::NewProximity, IntersectionMethod::LocalMinDistance}) {
        SCOPED_TRACE(intersection_method_name(method));
        const SceneDetection one = run_with_threads(1, 77, method);
        EXPECT_GT(count_outputs(one), 5000u);
        expect_identical(run_with_threads(2, 77, method), one);
        expect_identical(run_with_threads(4, 77, method), one);
    }
}

// Model pairs detected in parallel (CollisionPipeline::detect, more than one thread): over
// moving meshes, with the candidate cache's collections and reuses, the outputs, the cache's
// statistics and the candidates evaluated are those of one thread, pair by pair, bit for bit,
// and so are the triangles' stored normals after each detection. With NewProximity Triangle–
// Triangle's normal overwrite (read by the later pairs of those models), the pairs' writes run
// after them, in pair order.
struct ThreadedDetections {
    std::vector<SceneDetection> steps;
    std::vector<std::vector<Vec3>> normals;  // after each detection: torus 1's, then torus 2's
    std::size_t overwritten = 0;             // of those, the ones update() computes otherwise
    CollisionPipeline::CandidateCacheStats stats;
    std::size_t candidates = 0;
    int concurrent_steps = 0;
};

ThreadedDetections detect_moving_meshes(int threads, const IntersectionParams& params, bool both_sides) {
    const tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    tbb::task_arena arena(threads);
    ThreadedDetections r;
    arena.execute([&] {
        MeshScene sc(21, true);
        sc.tri1->params().both_side = both_sides;
        sc.tri2->params().both_side = both_sides;
        std::mt19937 g(22);
        CollisionPipelineOptions options;
        options.pair_concurrency = PairConcurrency::always;
        CollisionPipeline pipe(params, options);
        pipe.set_models(sc.models);
        for (int step = 0; step < 24; ++step) {
            r.steps.push_back(pipe.detect());
            // the models die with the scene: pairs named by the models' places in sc.models
            for (auto& p : r.steps.back()) {
                const auto place = [&](const CollisionModel* m) {
                    return reinterpret_cast<CollisionModel*>(
                        std::uintptr_t(std::find(sc.models.begin(), sc.models.end(), m) - sc.models.begin()));
                };
                p.model1 = place(p.model1);
                p.model2 = place(p.model2);
            }
            r.concurrent_steps += pipe.last_detection_concurrent() ? 1 : 0;
            std::vector<Vec3>& normals = r.normals.emplace_back();
            for (TriangleModel* t : {sc.tri1.get(), sc.tri2.get()}) {
                for (Index e = 0; e < Index(t->size()); ++e) normals.push_back(t->normal(e));
                t->update();  // the detection computes them again first (moving models)
            }
            for (std::size_t i = 0; i < sc.tri1->size(); ++i) r.overwritten += normals[i] != sc.tri1->normal(Index(i));
            for (std::size_t i = 0; i < sc.tri2->size(); ++i)
                r.overwritten += normals[sc.tri1->size() + i] != sc.tri2->normal(Index(i));
            sc.jiggle(g, step % 11 == 10 ? 0.04 : 0.001);
            for (auto& p : sc.t2->state.position) p += Vec3(0.002, 0.0, 0.0);
        }
        r.stats = pipe.candidate_cache_stats();
        r.candidates = pipe.candidates_evaluated();
    });
    return r;
}

TEST(NarrowPhase, PairsDetectedInParallelGiveTheBitsOfOneThreadOverSteps) {
    struct Case {
        const char* name;
        IntersectionParams params;
        bool both_sides;
        bool pairs_in_parallel;
    };
    IntersectionParams np_fixed = method_params(IntersectionMethod::NewProximity);
    np_fixed.quirks.fix_newproximity_triangle_triangle_normal_overwrite = true;
    const Case cases[] = {
        {"MinProximity", method_params(IntersectionMethod::MinProximity), false, true},
        {"LocalMinDistance", method_params(IntersectionMethod::LocalMinDistance), false, true},
        {"Discrete", method_params(IntersectionMethod::Discrete), false, true},
        // Triangle–Triangle without the overwrite reads planes kept per model (update_planes),
        // shared by the pairs of a model: made before the pairs run
        {"NewProximity, two-sided triangles", method_params(IntersectionMethod::NewProximity), true, true},
        {"NewProximity, overwrite fixed", np_fixed, false, true},
        // the overwrite by two pairs of torus 1 (with itself, and with torus 2), deferred
        {"NewProximity, with SOFA's normal overwrite", method_params(IntersectionMethod::NewProximity), false, true},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const ThreadedDetections one = detect_moving_meshes(1, c.params, c.both_sides);
        const ThreadedDetections two = detect_moving_meshes(2, c.params, c.both_sides);
        EXPECT_EQ(one.concurrent_steps, 0);
        EXPECT_EQ(two.concurrent_steps, c.pairs_in_parallel ? 24 : 0);
        ASSERT_EQ(one.steps.size(), two.steps.size());
        std::size_t outputs = 0, pairs_with_outputs = 0;
        for (std::size_t s = 0; s < one.steps.size(); ++s) {
            SCOPED_TRACE(s);
            expect_identical(two.steps[s], one.steps[s]);
            outputs += count_outputs(one.steps[s]);
            for (const auto& p : one.steps[s]) pairs_with_outputs += p.outputs.empty() ? 0 : 1;
        }
        // the scene does what it is for: many pairs with outputs at every step, the cache both
        // collecting and reusing
        EXPECT_GE(pairs_with_outputs, 24u * (c.params.method == IntersectionMethod::Discrete ? 2u : 6u))
            << pairs_with_outputs << " pairs, " << outputs << " outputs";
        EXPECT_GT(outputs, c.params.method == IntersectionMethod::Discrete ? 100u : 5000u);
        EXPECT_GT(one.stats.reused, 0u);
        EXPECT_GT(one.stats.collected, 0u);
        EXPECT_EQ(two.stats.reused, one.stats.reused);
        EXPECT_EQ(two.stats.collected, one.stats.collected);
        EXPECT_EQ(two.stats.in_sofa_order, one.stats.in_sofa_order);
        EXPECT_EQ(two.stats.sofa_order_sorts, one.stats.sofa_order_sorts);
        EXPECT_EQ(two.candidates, one.candidates);
        ASSERT_EQ(two.normals.size(), one.normals.size());
        for (std::size_t s = 0; s < one.normals.size(); ++s) {
            ASSERT_EQ(two.normals[s].size(), one.normals[s].size());
            for (std::size_t i = 0; i < one.normals[s].size(); ++i)
                ASSERT_TRUE(same_bits(two.normals[s][i], one.normals[s][i])) << "step " << s << ", triangle " << i;
        }
        EXPECT_EQ(two.overwritten, one.overwritten);
        const bool overwrites = c.params.method == IntersectionMethod::NewProximity && !c.both_sides &&
                                !c.params.quirks.fix_newproximity_triangle_triangle_normal_overwrite;
        if (overwrites) EXPECT_GT(one.overwritten, 24u * 50u) << one.overwritten;
        else EXPECT_EQ(one.overwritten, 0u);
    }
}

// PairConcurrency::automatic: a static floor (3 200 triangles) under four moving clouds of
// 100 spheres. Resting on it, the clouds give each pair hundreds of candidates, more than the
// 400 moving elements: the pairs run in parallel from the second detection on (the first has
// no counts yet). With three clouds lifted off the floor (one busy pair), or with the floor
// moving too and clouds of 25 spheres (about 1 600 candidates against 3 300 moving elements
// to refit), they run in order. The outputs are the same each time.
TEST(NarrowPhase, PairsRunInParallelWhenTheirCandidatesOutweighTheMovingElements) {
    std::vector<Vec3> grid;
    std::vector<Triangle> tris;
    const int n = 40;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            grid.emplace_back(-1.0 + 2.0 * i / n, 0.002 * ((i * 7 + j * 3) % 5), -1.0 + 2.0 * j / n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const int a = i * (n + 1) + j, b = a + n + 1;
            tris.push_back({a, b, b + 1});
            tris.push_back({a, b + 1, a + 1});
        }
    struct Setting {
        const char* name;
        bool floor_moving;
        double lift;          // of clouds 1, 2 and 3 (m)
        std::size_t spheres;  // per cloud
        int concurrent;
    };
    const Setting settings[] = {{"clouds resting", false, 0.0, 100, 9},
                                {"three clouds lifted", false, 0.1, 100, 0},
                                {"floor moving too", true, 0.0, 25, 0}};
    for (const Setting& setting : settings) {
        SCOPED_TRACE(setting.name);
        auto floor_mesh = test::triangle_mesh(grid, tris);
        CollisionModelParams fp = mp("floor", 9);
        fp.moving = setting.floor_moving;
        fp.simulated = setting.floor_moving;
        TriangleModel floor(floor_mesh->state, floor_mesh->topo, fp);
        std::mt19937 g(5);
        std::vector<Vec3State> states;
        std::vector<std::unique_ptr<SphereModel>> clouds;
        states.reserve(4);
        for (int c = 0; c < 4; ++c) {
            Vec3State st = random_cloud(setting.spheres, 0.2, g, Vec3(-0.5 + 0.33 * c, 0.0, 0.1 * c));
            for (auto& p : st.position) p.y() = 0.025 + 0.01 * std::abs(p.y()) + (c >= 1 ? setting.lift : 0.0);
            states.push_back(std::move(st));
        }
        static const char* names[] = {"c0", "c1", "c2", "c3"};
        for (int c = 0; c < 4; ++c)
            clouds.push_back(
                std::make_unique<SphereModel>(states[std::size_t(c)], 0.02, std::vector<double>{},
                                              mp(names[c], c, false, {7})));  // one group: no cloud–cloud pairs
        std::vector<CollisionModel*> models = {&floor};
        for (auto& c : clouds) models.push_back(c.get());
        const IntersectionParams params = method_params(IntersectionMethod::MinProximity);
        const tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
        tbb::task_arena arena(2);
        arena.execute([&] {
            CollisionPipeline automatic(params);
            CollisionPipelineOptions in_order;
            in_order.pair_concurrency = PairConcurrency::never;
            CollisionPipeline never(params, in_order);
            automatic.set_models(models);
            never.set_models(models);
            int concurrent = 0;
            std::size_t outputs = 0;
            for (int step = 0; step < 10; ++step) {
                expect_identical(automatic.detect(), never.detect());
                EXPECT_FALSE(never.last_detection_concurrent());
                concurrent += automatic.last_detection_concurrent() ? 1 : 0;
                outputs += count_outputs(automatic.detections());
                for (auto& st : states)
                    for (auto& p : st.position) p.x() += 0.001;
            }
            EXPECT_EQ(concurrent, setting.concurrent);
            EXPECT_GT(outputs, 10u * setting.spheres);  // the resting clouds touch the floor
            EXPECT_GT(automatic.candidates_evaluated(), 10u * 4u * setting.spheres) << automatic.candidates_evaluated();
        });
    }
}

// ---------------------------------------------------------------------------------------------
// Errors

TEST(NarrowPhase, NaNOrInfinitePositionRaisesNamingModelAndElement) {
    for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        std::mt19937 g(31);
        Vec3State s1 = random_cloud(300, 1.0, g);
        Vec3State s2 = random_cloud(300, 1.0, g);
        SphereModel a(s1, 0.05, {}, mp("alpha"));
        SphereModel b(s2, 0.05, {}, mp("beta"));
        CollisionPipeline pipe(method_params(IntersectionMethod::NewProximity), canonical_order());
        pipe.set_models({&a, &b});
        EXPECT_GT(count_outputs(pipe.detect()), 0u);  // a good first step, then the refit path
        s2.position[123].z() = bad;
        try {
            (void)pipe.detect();
            FAIL() << "no exception";
        } catch (const std::invalid_argument& e) {
            const std::string w = e.what();
            EXPECT_NE(w.find("beta"), std::string::npos) << w;
            EXPECT_NE(w.find("123"), std::string::npos) << w;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Size

TEST(NarrowPhase, HundredThousandSpheresCompleteAndMatchSampledExhaustiveRows) {
    std::mt19937 g(2024);
    const std::size_t n = 100000;
    Vec3State st = random_cloud(n, 0.5, g);
    SphereModel m(st, 0.005, {}, mp("box", 0, true));
    IntersectionParams params = IntersectionParams::new_proximity();
    params.alarm_distance = 0.005;
    params.contact_distance = 0.002;
    CollisionPipeline pipe(params, canonical_order());
    pipe.set_models({&m});
    const SceneDetection d = pipe.detect();
    ASSERT_EQ(d.size(), 1u);
    const auto& out = d[0].outputs;
    // expected neighbours per sphere: n * 4/3 pi 0.015^3 = 1.41 -> about 7e4 pairs
    EXPECT_GT(out.size(), 50000u);
    EXPECT_LT(out.size(), 90000u);
    EXPECT_TRUE(std::is_sorted(out.begin(), out.end(), [](const auto& x, const auto& y) {
        return std::tie(x.elem1, x.elem2) < std::tie(y.elem1, y.elem2);
    }));
    // exhaustive rows for 300 sampled spheres: every pair involving them
    std::uniform_int_distribution<std::size_t> pick(0, n - 1);
    std::vector<Aabb> boxes(n);
    for (std::size_t j = 0; j < n; ++j) boxes[j] = m.element_box(Index(j));
    const double margin = box_margin(params, m, m);
    std::size_t hits = 0;
    for (int s = 0; s < 300; ++s) {
        const auto i = Index(pick(g));
        DetectionOutputList ref;
        const Aabb& bi = boxes[std::size_t(i)];
        for (std::size_t j = 0; j < n; ++j) {
            if (Index(j) == i || !bi.overlaps(boxes[j], margin)) continue;
            intersect_elements(params, m, std::max(i, Index(j)), m, std::min(i, Index(j)), ref);
        }
        DetectionOutputList mine;
        for (const auto& o : out)
            if (o.elem1 == i || o.elem2 == i) mine.push_back(o);
        auto key = [](const DetectionOutput& o) { return std::tie(o.elem1, o.elem2, o.id); };
        std::sort(ref.begin(), ref.end(), [&](const auto& x, const auto& y) { return key(x) < key(y); });
        ASSERT_EQ(mine.size(), ref.size()) << "sphere " << i;
        for (std::size_t k = 0; k < ref.size(); ++k) ASSERT_TRUE(same_output(mine[k], ref[k]));
        hits += ref.size();
    }
    EXPECT_GT(hits, 200u);  // speed is measured by penalty_bench_detection, not here
}

}  // namespace
}  // namespace penalty
