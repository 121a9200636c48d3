// Whole-scene scaling (issues 17, 54): k×k×k deformable cubes dropped into a bowl, k = 1 … 8, 10,
// 12 and 16 (4 096 cubes, 98 304 DOFs) — time per step against contacts per step. The scene is generated
// (tests/support/penalty_test/ cubes_in_bowl.hpp: one-cell FEM cubes of 0.1 m with a triangle surface, a static bowl (a
// spherical cap), one implicit Euler + CG over every cube, NewProximity, SOFA's penalty response) and built
// by the scene builder, so a step is the one `penalty run` takes. bench/plot_scaling.py reads the
// JSON output (--benchmark_out=FILE --benchmark_out_format=json), fits the log-log slope and
// draws docs/images/scaling.png; docs/performance.md ("Scaling: k×k×k cubes in a bowl") quotes it.
//
// Method. Per k: the scene is built and run kWarmupSteps steps untimed (1.5 s of simulated time:
// the cubes have fallen, slid to the bottom and piled up; at k = 12 the kinetic energy is then
// about 7 % of its peak of about 720 J and falling), then timed_steps(k) steps are timed, one benchmark
// iteration per step (manual time = wall time of Scene::step() alone). Threads (narrow phase,
// independent solvers): TBB's default, or $PENALTY_BENCH_THREADS (bench/scene_probe.hpp, which
// also says how to count the timed steps' instructions with callgrind).
//
// Columns and counters (per step, over the timed steps):
//   Time                       wall time of Scene::step() (ms)
//   CPU                        process CPU time (all threads) of the iteration (ms): on a loaded
//                              machine the wall time includes waiting for a core, the CPU time not
//   cubes, dofs                k³; Σ scalar DOFs of the cubes (3 per node)
//   contacts, active           mean Σ contact springs after the step; of them, with pen > 0
//   cg_its                     mean CG iterations (Scene::last_solver_stats)
//   kinetic_j                  mean kinetic energy of the cubes (J): how far from rest the pile is
//   sunk                       cube nodes farther than R + C from the bowl's centre after the last
//                              timed step: corners pushed through the bowl (0 for a sound pile)
//   detect_ms, response_ms, solve_ms   mean of Scene::last_timings() (wall)
//   heap_mb                    live heap after the timed steps (mallinfo2), MB
//   bytes_per_dof              that heap / dofs
//   bytes_per_contact          (heap after the timed steps − heap after the first step, when no
//                              cube touches yet) / contacts
//   peak_rss_mb                the process's peak RSS so far (run one k per process for its own)
//
// $PENALTY_SCALING_SCENES=DIR also writes the scenes as DIR/cubes_in_bowl_k<k>.scn (for
// `penalty run`, e.g. with --stats to see the phases of every step).
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/cubes_in_bowl.hpp"
#include "scene_probe.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <memory>
#include <string>

namespace penalty::scene {
namespace {

namespace bowl = penalty::test::cubes_in_bowl;

constexpr int kSizes[] = {1, 2, 3, 4, 5, 6, 7, 8, 10, 12, 16};
/// The pile's time step (s) and contact springs (N/m). The cubes_in_bowl defaults (5 ms, 5e3 N/m)
/// hold piles up to k = 8; deeper piles press the lower springs past C and corners cross the
/// bowl: at k = 12 the largest penetration passed C = 1 cm at step 125 and the kinetic energy,
/// 258 J at step 225, grew to 5.1 kJ at step 375 (k = 16: 7.8 kJ, 114 nodes beyond the bowl).
/// Stiffer springs at 5 ms diverged from the first steps (1e4 N/m: 12 kJ at step 100); at 2.5 ms
/// and 1e4 N/m the k = 12 pile stays below 0.9 cm and settles (47 J at 1.5 s).
constexpr double kTimeStep = 0.0025;
constexpr double kSpringStiffness = 1e4;
constexpr int kWarmupSteps = 600;  // 1.5 s at kTimeStep

/// Timed steps for k: about 2000 cube-steps, at least 10 and at most 200.
int timed_steps(int k) { return std::clamp(2000 / (k * k * k), 10, 200); }

bowl::Setup setup(int k) {
    bowl::Setup s;
    s.k = k;
    s.dt = kTimeStep;
    s.spring_stiffness = kSpringStiffness;
    return s;
}

void BM_CubesInBowl(benchmark::State& state, int k) {
    std::unique_ptr<Scene> scene;
    double heap_without_contacts = 0;
    try {
        const std::string name = "cubes_in_bowl_k" + std::to_string(k);
        {
            const std::string xml = bowl::scene_xml(setup(k));
            bench::write_scene_if_asked(name, xml);
            scene = build_scene(io::parse_scene_string(xml, name), bench::build_options());
        }
        scene->step();  // no cube touches the bowl yet: the heap of the scene and the solve's scratch
        heap_without_contacts = bench::live_heap_bytes();
        for (int i = 1; i < kWarmupSteps; ++i) scene->step();
    } catch (const std::exception& e) {
        bench::skip(state, "build or warm-up failed: " + std::string(e.what()));
        return;
    }
    bench::StepSums sums;
    if (!bench::run_timed_steps(state, *scene, sums)) return;
    const bowl::Setup s = setup(k);
    const auto c = bowl::bowl_centre(s);
    int sunk = 0;
    for (const auto& r : scene->states()) {
        if (!r.in_solver_subtree) continue;  // the bowl
        for (const Vec3& x : dynamic_cast<const Vec3Object&>(*r.state).position)
            if ((x - Vec3(c[0], c[1], c[2])).norm() > bowl::bowl_radius(s) + s.contact_distance) ++sunk;
    }
    state.counters["k"] = k;
    state.counters["cubes"] = k * k * k;
    bench::report_step_sums(state, *scene, sums, heap_without_contacts);
    state.counters["sunk"] = sunk;
}

[[maybe_unused]] const bool registered = [] {
    for (const int k : kSizes)
        benchmark::RegisterBenchmark(("BM_CubesInBowl/k:" + std::to_string(k)).c_str(), BM_CubesInBowl, k)
            ->Iterations(timed_steps(k))
            ->UseManualTime()
            ->MeasureProcessCPUTime()
            ->Unit(benchmark::kMillisecond);
    return true;
}();

}  // namespace
}  // namespace penalty::scene
