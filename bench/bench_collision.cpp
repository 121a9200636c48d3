// Element-pair intersection throughput (items = element-pair tests per second) for the pairs
// that dominate penalty scenes: point–triangle, sphere–triangle, line–line, sphere–sphere
// (NewProximity and MinProximity), plus the exact geometric kernels for reference.
// Random configurations in a unit box so that roughly half the tests report a contact.
// Each test goes through intersect_elements, the call CollisionPipeline's narrow phase makes for
// every candidate element pair in `penalty run` (whole-scene detection: bench_detection.cpp);
// BM_CandidateFilter times the candidate filters that run before some kernels.
#include "kernels/collision/candidate_filters.hpp"
#include "penalty/collision/intersection.hpp"
#include "penalty/collision/models.hpp"
#include "penalty/core/pair_key.hpp"
#include "penalty/geometry/point_triangle.hpp"
#include "penalty/geometry/segment_segment.hpp"

#include <benchmark/benchmark.h>

#include <initializer_list>
#include <random>
#include <vector>

namespace penalty {
namespace {

constexpr std::size_t kN = 1024;

struct Scene {
    Vec3State points, spheres, tri_state, line_state;
    MeshTopology tri_topo, line_topo;
    Scene() {
        std::mt19937 g(12345);
        std::uniform_real_distribution<double> u(-0.5, 0.5);
        auto rv = [&] { return Vec3(u(g), u(g), u(g)); };
        points.resize(kN);
        spheres.resize(kN);
        for (std::size_t i = 0; i < kN; ++i) {
            points.position[i] = rv();
            spheres.position[i] = rv();
        }
        tri_state.resize(3 * kN);
        std::vector<Triangle> tris;
        line_state.resize(2 * kN);
        std::vector<Edge> edges;
        for (std::size_t i = 0; i < kN; ++i) {
            const Vec3 c = rv();
            for (int k = 0; k < 3; ++k) tri_state.position[3 * i + std::size_t(k)] = c + 0.3 * rv();
            tris.push_back({PointId(3 * i), PointId(3 * i + 1), PointId(3 * i + 2)});
            line_state.position[2 * i] = c + 0.4 * rv();
            line_state.position[2 * i + 1] = c + 0.4 * rv();
            edges.push_back({PointId(2 * i), PointId(2 * i + 1)});
        }
        tri_topo.set_num_points(3 * kN);
        tri_topo.set_triangles(tris);
        line_topo.set_num_points(2 * kN);
        line_topo.set_edges(edges);
    }
};

const Scene& scene() {
    static const Scene s;
    return s;
}

IntersectionParams method(int m) {
    auto p = m == 0 ? IntersectionParams::new_proximity() : IntersectionParams::min_proximity();
    p.alarm_distance = 0.3;
    p.contact_distance = 0.1;
    return p;
}

template <class Make>
void run_pairs(benchmark::State& state, CollisionModel& a, CollisionModel& b, const IntersectionParams& p) {
    a.update();
    b.update();
    DetectionOutputList out;
    out.reserve(kN * 4);
    std::size_t i = 0, j = 0, hits = 0, tests = 0;
    for (auto _ : state) {
        for (int k = 0; k < 256; ++k) {
            hits += std::size_t(intersect_elements(p, a, Index(i), b, Index(j), out));
            j = (j + 1) % kN;
            if (j == 0) i = (i + 1) % kN;
            if (out.size() > kN * 3) out.clear();
        }
        tests += 256;
    }
    state.SetItemsProcessed(std::int64_t(tests));
    state.counters["hit_rate"] = double(hits) / double(tests);
}
struct Tag {};

void BM_PointTriangle(benchmark::State& state) {
    const Scene& s = scene();
    TriangleModel tri(s.tri_state, s.tri_topo);
    PointModel pts(s.points);
    run_pairs<Tag>(state, tri, pts, method(int(state.range(0))));
}
void BM_SphereTriangle(benchmark::State& state) {
    const Scene& s = scene();
    TriangleModel tri(s.tri_state, s.tri_topo);
    SphereModel sph(s.spheres, 0.05);
    run_pairs<Tag>(state, tri, sph, method(int(state.range(0))));
}
void BM_LineLine(benchmark::State& state) {
    const Scene& s = scene();
    LineModel a(s.line_state, s.line_topo), b(s.line_state, s.line_topo);
    run_pairs<Tag>(state, a, b, method(int(state.range(0))));
}
void BM_SphereSphere(benchmark::State& state) {
    const Scene& s = scene();
    SphereModel a(s.spheres, 0.05), b(s.points, 0.05);
    run_pairs<Tag>(state, a, b, method(int(state.range(0))));
}
// Arg: 0 = NewProximity, 1 = MinProximity
BENCHMARK(BM_PointTriangle)->Arg(0)->Arg(1);
BENCHMARK(BM_SphereTriangle)->Arg(0)->Arg(1);
BENCHMARK(BM_LineLine)->Arg(0)->Arg(1);
BENCHMARK(BM_SphereSphere)->Arg(0)->Arg(1);

// The candidate filters (penalty/collision/candidate_filters.hpp) over the same element pairs
// (1024 × 256 candidates a pass, in the order of run_pairs): items = candidates filtered a
// second; kept_share = the share the kernel then evaluates. Args: pair (0 point–triangle,
// 1 sphere–triangle, 2 line–line), method (0 NewProximity, 1 MinProximity), path (0 scalar,
// 1 AVX, skipped without AVX). Compare with BM_PointTriangle etc.: the kernel a candidate.
void BM_CandidateFilter(benchmark::State& state) {
    const Scene& s = scene();
    const int pair = int(state.range(0));
    const IntersectionParams p = method(int(state.range(1)));
    const KernelPath path = state.range(2) == 0 ? KernelPath::scalar : KernelPath::avx;
    if (!kernel_path_supported(path)) {
        state.SkipWithError("no AVX on this CPU");
        return;
    }
    TriangleModel tri(s.tri_state, s.tri_topo);
    PointModel pts(s.points);
    SphereModel sph(s.spheres, 0.05);
    LineModel a(s.line_state, s.line_topo), b(s.line_state, s.line_topo);
    for (CollisionModel* m : std::initializer_list<CollisionModel*>{&tri, &pts, &sph, &a, &b}) m->update();
    std::vector<std::uint64_t> keys;
    for (std::size_t i = 0; i < 256; ++i)
        for (std::size_t j = 0; j < kN; ++j) keys.push_back(pair_key::make(i, j));
    std::vector<std::uint64_t> kept;
    kept.reserve(keys.size());
    for (auto _ : state) {
        kept.clear();
        if (pair == 2) detail::keep_line_line_candidates(p, a, b, keys, kept, path);
        else
            detail::keep_triangle_candidates(p, tri, pair == 0 ? static_cast<CollisionModel&>(pts) : sph, keys, kept,
                                             path);
        benchmark::DoNotOptimize(kept.data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(keys.size()));
    state.counters["kept_share"] = double(kept.size()) / double(keys.size());
}
BENCHMARK(BM_CandidateFilter)->ArgsProduct({{0, 1, 2}, {0, 1}, {0, 1}});

// exact geometric kernels (no SOFA thresholds, no output)
void BM_GeometryPointTriangle(benchmark::State& state) {
    const Scene& s = scene();
    std::size_t i = 0, j = 0;
    for (auto _ : state) {
        const auto r = point_triangle_closest_point(s.points.position[j], s.tri_state.position[3 * i],
                                                    s.tri_state.position[3 * i + 1], s.tri_state.position[3 * i + 2]);
        benchmark::DoNotOptimize(r);
        j = (j + 1) % kN;
        if (j == 0) i = (i + 1) % kN;
    }
    state.SetItemsProcessed(state.iterations());
}
void BM_GeometrySegmentSegment(benchmark::State& state) {
    const Scene& s = scene();
    std::size_t i = 0, j = 0;
    for (auto _ : state) {
        const auto r = segment_segment_closest_points(s.line_state.position[2 * i], s.line_state.position[2 * i + 1],
                                                      s.line_state.position[2 * j], s.line_state.position[2 * j + 1]);
        benchmark::DoNotOptimize(r);
        j = (j + 1) % kN;
        if (j == 0) i = (i + 1) % kN;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_GeometryPointTriangle);
BENCHMARK(BM_GeometrySegmentSegment);

}  // namespace
}  // namespace penalty
