// The narrow phase (collision/narrow_phase.cpp, BVHNarrowPhase through per-model bounding trees)
// finds exactly what the exhaustive all-element-pairs loop finds (same pairs, same outputs, same
// order, bit for bit), for every method, with any number of threads. Both are CollisionPipeline
// (the one detection driver), with ContactDetection::bvh and ::exhaustive.
#include "pipeline_references.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <random>

namespace penalty {
namespace {

using namespace test_pipeline;

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
            // only the near pairs are listed; the others have no outputs
            pairs += expect_listed_pairs_hold_every_output(got, params, models);
            near_pairs += got.size();
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
    // whose root boxes are within the margin by a sweep (158 models: in ranges on TBB's threads
    // where the machine has two cores or more). Every step: the exhaustive driver's
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
        std::size_t pairs = 0, near_pairs = 0, outputs = 0, most_near = 0;
        for (int step = 0; step < 60; ++step) {
            // the filters the broad phase reads, changed between detections
            if (step == 10) clouds[3]->params().active = false;
            if (step == 20) clouds[3]->params().active = true;
            if (step == 25) clouds[11]->params().group = {4}, clouds[12]->params().group = {4};
            if (step == 35) clouds[5]->params().self_collision = true, clouds[155]->params().self_collision = true;
            if (step == 45) clouds[20]->params().both_side = true;
            const SceneDetection& got = pipe.detect();
            const SceneDetection ref = detect_scene_exhaustive(params, models);
            expect_identical(got, ref);  // the same near pairs as the test of every pair, in order
            // every tenth step: the pairs not listed have no outputs (the exhaustive loop over
            // every pair's element pairs); else the pairs counted only
            if (step % 10 == 0) {
                pairs += expect_listed_pairs_hold_every_output(got, params, models);
            } else {
                std::vector<ModelPair> kept;
                broad_phase(params, models, kept);
                pairs += kept.size();
            }
            const std::size_t near_now = got.size();
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
        for (auto v : sc.tri1->triangle(o.elem1.value())) ASSERT_NE(v, o.elem2.value());
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
        EXPECT_EQ(pp->outputs[k].elem1, ElementIndex(Index(k + 2)));
        EXPECT_EQ(pp->outputs[k].elem2, ElementIndex(Index(k)));
    }
    const ModelPairDetection* ll = find_pair(d, &lines, &lines);
    ASSERT_NE(ll, nullptr);
    EXPECT_GT(ll->outputs.size(), std::size_t(n / 2));
    for (const auto& o : ll->outputs) {
        EXPECT_GE(o.elem1.value() - o.elem2.value(), 2) << "edges sharing a vertex must be filtered";
    }
    // the line-point pair of the same state and node: a line never meets its own end points
    const ModelPairDetection* lp = find_pair(d, &lines, &pts);
    ASSERT_NE(lp, nullptr);
    for (const auto& o : lp->outputs) {
        EXPECT_NE(lines.edge(o.elem1.value())[0], o.elem2.value());
        EXPECT_NE(lines.edge(o.elem1.value())[1], o.elem2.value());
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
            if (o.elem1 == ElementIndex(i) || o.elem2 == ElementIndex(i)) mine.push_back(o);
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
