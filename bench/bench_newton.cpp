// Newton with contact-geometry updates vs SOFA's linearised implicit Euler on a stiff drop, and
// ContactPipeline::update() with the BVH vs the exhaustive detection on a mesh scene.
//
//   penalty_bench_newton --benchmark_counters_tabular=true
//
// Stiff drop: 100 spheres (r = 0.1 m, m = 1 kg) in a 10 × 10 grid dropped on a static plane at
// −8 m/s from 5 cm above contact; ks = 1e5 N/m (physical law), dt = 0.01 s (ω·h = 3.2), 100 steps.
// Counters: us_per_step, newton_iters (mean residual evaluations per step), newton_iters_max,
// max_pen_mm (deepest penetration over the run), rest_pen_err (|pen − m·g/ks| at the end, m).
// Mesh scene: static n × n-quad floor (2·n² triangles) + 2000 spheres resting on it + a falling
// 16 × 16 sheet; one update() per iteration (detection + response), after 3 warm-up steps.

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/spheres_on_floor.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace penalty {
namespace {

using namespace test::stiff_drop;

/// The stiff drop (spheres_on_floor.hpp) of 100 spheres, A = 0.1 m; Newton with geometry updates
/// or SOFA's linearised step.
struct StiffDrop : test::SpheresOnFloor {
    explicit StiffDrop(bool newton) : SpheresOnFloor(setup("spheres", start_positions(), start_velocities(), 0.1)) {
        configure_solver(*this, newton, newton);
    }
    /// A 10 × 10 grid, 0.5 m apart, 0.150–0.159 m high.
    static std::vector<Vec3> start_positions() {
        std::vector<Vec3> x;
        for (int i = 0; i < 10; ++i)
            for (int j = 0; j < 10; ++j)
                x.emplace_back(0.5 * i - 2.25, 0.15 + 0.001 * ((i * 7 + j * 3) % 10), 0.5 * j - 2.25);
        return x;
    }
    static std::vector<Vec3> start_velocities() { return std::vector<Vec3>(100, Vec3(0.0, -8.0, 0.0)); }
};

void BM_StiffDrop(benchmark::State& state) {
    const bool newton = state.range(0) != 0;
    constexpr int kSteps = 100;
    double seconds = 0.0, iterations = 0.0, max_pen = 0.0, rest_err = 0.0;
    int max_iterations = 0;
    for (auto _ : state) {
        StiffDrop s(newton);
        s.sim.init();
        for (int k = 0; k < kSteps; ++k) {
            const auto t0 = std::chrono::steady_clock::now();
            s.sim.step();
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            iterations += s.solver->last_newton_iterations();
            max_iterations = std::max(max_iterations, s.solver->last_newton_iterations());
            for (const Vec3& p : s.spheres->position) max_pen = std::max(max_pen, kDist - p.y());
        }
        rest_err = 0.0;
        for (const Vec3& p : s.spheres->position) rest_err = std::max(rest_err, std::abs(kDist - p.y() - kG / kKs));
    }
    const double steps = double(kSteps) * double(state.iterations());
    state.counters["us_per_step"] = 1e6 * seconds / steps;
    state.counters["newton_iters"] = newton ? iterations / steps : 0.0;
    state.counters["newton_iters_max"] = newton ? max_iterations : 0;
    state.counters["max_pen_mm"] = 1e3 * max_pen;
    state.counters["rest_pen_err"] = rest_err;
}
BENCHMARK(BM_StiffDrop)->ArgName("newton")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// ---- ContactPipeline::update(): BVH vs exhaustive ------------------------------------------------
struct MeshScene {
    Simulation sim;
    MeshTopology floor_topology, sheet_topology;
    std::vector<std::unique_ptr<CollisionModel>> models;
    std::unique_ptr<ContactPipeline> pipeline;

    MeshScene(int n, const ContactPipelineOptions& options) {
        sim.root().set_dt(0.005);
        Node& floor_node = sim.root().add_child("floor");
        auto& fx = floor_node.add_state<Vec3Types>("floor");
        const double s = 5.0;
        // waviness of amplitude 2 cm along the grid indices
        const auto wavy = [](double y) {
            return
                [y](const test::GridVertex& v) { return y + 0.02 * std::sin(1.7 * double(v.i) + 0.3 * double(v.j)); };
        };
        test::grid_mesh(std::size_t(n), s, wavy(0.0), fx.position, floor_topology);
        Node& bodies = sim.root().add_child("bodies");
        auto& solver = bodies.set_ode_solver<EulerImplicitSolver>();
        solver.cg.iterations = 10;
        Node& cloud_node = bodies.add_child("cloud");
        auto& cloud = cloud_node.add_state<Vec3Types>("cloud");
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (int i = 0; i < 2000; ++i) cloud.position.emplace_back(4.5 * u(rng), 0.06 + 0.03 * u(rng), 4.5 * u(rng));
        cloud_node.set_mass<UniformMass<Vec3Types>>(cloud).set_vertex_mass(0.01);
        Node& sheet_node = bodies.add_child("sheet");
        auto& sheet = sheet_node.add_state<Vec3Types>("sheet");
        test::grid_mesh(16, 1.0, wavy(0.3), sheet.position, sheet_topology);
        sheet.velocity.assign(sheet.position.size(), Vec3(0, -2.0, 0));
        sheet_node.set_mass<UniformMass<Vec3Types>>(sheet).set_vertex_mass(0.01);
        CollisionModelParams p;
        p.name = "floor";
        p.simulated = false;
        p.moving = false;
        models.push_back(std::make_unique<TriangleModel>(fx, floor_topology, p));
        p.simulated = true;
        p.moving = true;
        p.name = "cloud";
        models.push_back(std::make_unique<SphereModel>(cloud, 0.05, std::vector<double>{}, p));
        p.name = "sheet";
        models.push_back(std::make_unique<TriangleModel>(sheet, sheet_topology, p));
        IntersectionParams ip = IntersectionParams::new_proximity();
        ip.alarm_distance = 0.05;
        ip.contact_distance = 0.01;
        pipeline = std::make_unique<ContactPipeline>(sim, ip, CollisionResponse(), &bodies, options);
        pipeline->add_model(*models[0], floor_node);
        pipeline->add_model(*models[1], cloud_node);
        pipeline->add_model(*models[2], sheet_node);
    }
    ~MeshScene() { pipeline.reset(); }
};

void BM_PipelineUpdate(benchmark::State& state) {
    const int n = static_cast<int>(state.range(0));
    ContactPipelineOptions opt;
    opt.detection = state.range(1) == 0 ? ContactDetection::exhaustive : ContactDetection::bvh;
    opt.threads = static_cast<int>(state.range(2));
    MeshScene scene(n, opt);
    scene.sim.init();
    for (int k = 0; k < 3; ++k) scene.sim.step();
    double detection = 0.0, response = 0.0;
    std::size_t outputs = 0;
    for (auto _ : state) {
        scene.pipeline->update();
        detection += scene.pipeline->last_timings().detection_seconds;
        response += scene.pipeline->last_timings().response_seconds;
    }
    for (const auto& d : scene.pipeline->detections()) outputs += d.outputs.size();
    state.counters["triangles"] = 2.0 * n * n;
    state.counters["outputs"] = double(outputs);
    state.counters["detect_ms"] = 1e3 * detection / double(state.iterations());
    state.counters["response_ms"] = 1e3 * response / double(state.iterations());
}
// args: floor quads per side, detection (0 exhaustive, 1 bvh), threads (0 = TBB default)
BENCHMARK(BM_PipelineUpdate)
    ->ArgNames({"n", "bvh", "threads"})
    ->Args({50, 0, 0})
    ->Args({50, 1, 1})
    ->Args({50, 1, 2})
    ->Args({100, 0, 0})
    ->Args({100, 1, 1})
    ->Args({100, 1, 2})
    ->Args({200, 1, 1})
    ->Args({200, 1, 2})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace penalty
