// Scene-level detection (issue 4): CollisionPipeline, the detection driver `penalty run` uses (through
// ContactPipeline), with ContactDetection::bvh (per-model bounding trees, broad phase, parallel BVH
// narrow phase; the default of `penalty run`) against ContactDetection::exhaustive (the
// all-element-pairs loop, `penalty run --exhaustive`), for n = 1e3 … 1e6 elements in
// three scenes:
//   spheres  — n spheres in a box, one self-colliding model, constant density (~1.4 neighbours each);
//   torus    — a torus mesh of n/2 triangles against a cloud of n/2 points;
//   meshes   — two interpenetrating tori of n/2 triangles each (NewProximity Triangle–Triangle).
// A timed iteration is one detection step with unchanged positions (moving models: boxes
// recomputed and trees refitted, broad phase, traversal, evaluation). Method: NewProximity.
// Arguments: {n, threads}; the exhaustive loop runs only where it is affordable (n <= 1e4).
// The spheres scene against Bullet, every sphere moving: bench_detection_bullet.cpp (BM_Against_Bullet,
// in this executable when CMake finds Bullet).
#include "../tests/collision/detection_scenes.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "spheres_scene.hpp"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <memory>
#include <random>

namespace penalty {
namespace {

struct Scene {
    std::unique_ptr<test::TorusMesh> t1, t2;
    Vec3State cloud;
    std::vector<std::unique_ptr<CollisionModel>> owned;
    std::vector<CollisionModel*> models;
    IntersectionParams params = IntersectionParams::new_proximity();

    void add(std::unique_ptr<CollisionModel> m) {
        models.push_back(m.get());
        owned.push_back(std::move(m));
    }
};

CollisionModelParams named(const char* n, int node, bool self = false) {
    CollisionModelParams p;
    p.name = n;
    p.node = node;
    p.self_collision = self;
    return p;
}

std::unique_ptr<Scene> make_scene(int kind, std::size_t n) {
    auto s = std::make_unique<Scene>();
    std::mt19937 g(std::uint32_t(1000 + kind));
    if (kind == 0) {                        // spheres in a box, same density for every n
        s->cloud = bench::sphere_cloud(n);  // seed 1000 = 1000 + kind
        s->add(std::make_unique<SphereModel>(s->cloud, bench::kSphereRadius, std::vector<double>{},
                                             bench::sphere_model_params()));
        s->params = bench::sphere_intersection_params();
        return s;
    }
    // a torus of about m triangles: nu = 4 nv, 2 nu nv = m
    auto torus = [&](std::size_t m, const Vec3& c) {
        const int nv = std::max(4, int(std::lround(std::sqrt(double(m) / 8.0))));
        return test::make_torus(4 * nv, nv, 0.5, 0.15, c, g, 0.2);
    };
    s->t1 = torus(n / 2, Vec3::Zero());
    const double h = 6.283185307179586 * 0.15 / std::sqrt(double(n) / 16.0);  // edge length
    s->params.alarm_distance = 0.5 * h;
    s->params.contact_distance = 0.2 * h;
    s->add(std::make_unique<TriangleModel>(s->t1->state, s->t1->topo, named("torus", 1)));
    if (kind == 1) {
        s->cloud = test::random_cloud(n / 2, 0.7, g);
        s->add(std::make_unique<PointModel>(s->cloud, nullptr, named("cloud", 2)));
    } else {
        s->t2 = torus(n / 2, Vec3(0.3, 0.1, 0.05));
        s->add(std::make_unique<TriangleModel>(s->t2->state, s->t2->topo, named("torus2", 2)));
    }
    return s;
}

std::size_t elements(const Scene& s) {
    std::size_t e = 0;
    for (const auto* m : s.models) e += m->size();
    return e;
}

std::size_t outputs(const SceneDetection& d) {
    std::size_t k = 0;
    for (const auto& p : d) k += p.outputs.size();
    return k;
}

void BM_Pipeline(benchmark::State& state, int kind) {
    const auto n = std::size_t(state.range(0));
    const int threads = int(state.range(1));
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    tbb::task_arena arena(threads);
    auto scene = make_scene(kind, n);
    CollisionPipeline pipe(scene->params);
    pipe.set_models(scene->models);
    std::size_t k = 0;
    arena.execute([&] { k = outputs(pipe.detect()); });  // first step builds the trees
    for (auto _ : state) {
        arena.execute([&] {
            const SceneDetection& d = pipe.detect();
            benchmark::DoNotOptimize(d.data());
        });
    }
    state.counters["elements"] = double(elements(*scene));
    state.counters["outputs"] = double(k);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(elements(*scene)));
}

void BM_Exhaustive(benchmark::State& state, int kind) {
    const auto n = std::size_t(state.range(0));
    auto scene = make_scene(kind, n);
    CollisionPipeline pipe(scene->params, {}, ContactDetection::exhaustive);
    pipe.set_models(scene->models);
    std::size_t k = 0;
    for (auto _ : state) {
        const SceneDetection& d = pipe.detect();
        k = outputs(d);
        benchmark::DoNotOptimize(d.data());
    }
    state.counters["elements"] = double(elements(*scene));
    state.counters["outputs"] = double(k);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(elements(*scene)));
}

void pipeline_args(benchmark::internal::Benchmark* b) {
    for (const long n : {1000L, 10000L, 100000L, 1000000L}) b->Args({n, 1});
    for (const long n : {100000L, 1000000L}) {
        b->Args({n, 2});
        b->Args({n, 4});
    }
    b->Unit(benchmark::kMillisecond)->UseRealTime();
}

void exhaustive_args(benchmark::internal::Benchmark* b) {
    for (const long n : {1000L, 10000L}) b->Args({n});
    b->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(BM_Pipeline, spheres, 0)->Apply(pipeline_args);
BENCHMARK_CAPTURE(BM_Exhaustive, spheres, 0)->Apply(exhaustive_args);
BENCHMARK_CAPTURE(BM_Pipeline, torus_cloud, 1)->Apply(pipeline_args);
BENCHMARK_CAPTURE(BM_Exhaustive, torus_cloud, 1)->Apply(exhaustive_args);
BENCHMARK_CAPTURE(BM_Pipeline, two_meshes, 2)->Apply(pipeline_args);
BENCHMARK_CAPTURE(BM_Exhaustive, two_meshes, 2)->Apply(exhaustive_args);

}  // namespace
}  // namespace penalty
