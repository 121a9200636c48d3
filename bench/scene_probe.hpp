#pragma once
// What the whole-scene benchmarks (bench_scaling.cpp, bench_large_scenes.cpp) measure besides
// time: the scene's DOFs, its memory (live heap bytes, peak RSS), the .scn files on request, the
// thread count from the environment, and the instruction counts of the timed steps alone under
// callgrind.
//
// Environment:
//   PENALTY_SCALING_SCENES=DIR   write each generated scene as DIR/<name>.scn (for `penalty run`)
//   PENALTY_SCALING_SCENES_ONLY=1  with it: exit (0) once the first selected scene is written, running
//                                nothing (bench/scaling-table.sh packs scenes so)
//   PENALTY_BENCH_THREADS=N      BuildOptions::threads (default 0: TBB's default); 1 for callgrind
//
// Callgrind: `valgrind --tool=callgrind --instr-atstart=no --collect-atstart=no BENCH ...` runs
// the build and the warm-up uninstrumented (a few times slower than natively, not fifty), and
// collects the timed Scene::step() calls only (StepProbe): Ir per step = total Ir / steps.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/scene/scene.hpp"

#include <benchmark/benchmark.h>
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define PENALTY_BENCH_CALLGRIND 1
#else
#define PENALTY_BENCH_CALLGRIND 0
#endif

namespace penalty::bench {

/// Marks the benchmark skipped with `why` (Google Benchmark still wants its loop run).
inline void skip(benchmark::State& state, const std::string& why) {
    state.SkipWithError(why.c_str());
    for (auto _ : state) {
    }
}

/// Writes `xml` as $PENALTY_SCALING_SCENES/<name>.scn when that variable is set.
inline void write_scene_if_asked(const std::string& name, const std::string& xml) {
    const char* dir = std::getenv("PENALTY_SCALING_SCENES");
    if (dir == nullptr || *dir == '\0') return;
    std::filesystem::create_directories(dir);
    {
        std::ofstream file(std::filesystem::path(dir) / (name + ".scn"));
        file << xml;
        if (!file) throw std::runtime_error("cannot write the scene " + name + ".scn into " + dir);
    }
    if (const char* only = std::getenv("PENALTY_SCALING_SCENES_ONLY"); only != nullptr && *only == '1') std::exit(0);
}

/// BuildOptions with threads from $PENALTY_BENCH_THREADS (0, TBB's default, when unset).
inline scene::BuildOptions build_options() {
    scene::BuildOptions o;
    if (const char* t = std::getenv("PENALTY_BENCH_THREADS"); t != nullptr && *t != '\0') o.threads = std::atoi(t);
    return o;
}

/// Σ scalar DOFs of the states a solver integrates (not mapped, in a solver's subtree).
inline double scalar_dofs(const scene::Scene& s) {
    double n = 0;
    for (const auto& r : s.states())
        if (!r.mapped && r.in_solver_subtree && r.state != nullptr) n += double(r.state->scalar_size());
    return n;
}

/// Bytes of the heap in use now (glibc's mallinfo2: small blocks and mmapped ones).
inline double live_heap_bytes() {
    const struct mallinfo2 m = mallinfo2();
    return double(m.uordblks) + double(m.hblkhd);
}

/// The process's peak resident set so far (getrusage ru_maxrss, bytes).
inline double peak_rss_bytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return 1024.0 * double(u.ru_maxrss);
}

/// Brackets a timed step: under callgrind, collection is on only inside (no-ops natively).
struct StepProbe {
    StepProbe() {
#if PENALTY_BENCH_CALLGRIND
        CALLGRIND_TOGGLE_COLLECT;
#endif
    }
    ~StepProbe() {
#if PENALTY_BENCH_CALLGRIND
        CALLGRIND_TOGGLE_COLLECT;
#endif
    }
    StepProbe(const StepProbe&) = delete;
    StepProbe& operator=(const StepProbe&) = delete;
};

/// Turns callgrind's instrumentation on before the timed steps (no-op natively).
inline void start_instrumentation() {
#if PENALTY_BENCH_CALLGRIND
    CALLGRIND_START_INSTRUMENTATION;
#endif
}

/// Turns it off after them, so the next benchmark's build and warm-up run fast again.
inline void stop_instrumentation() {
#if PENALTY_BENCH_CALLGRIND
    CALLGRIND_STOP_INSTRUMENTATION;
#endif
}

/// Per-step sums over the timed steps of a whole-scene benchmark.
struct StepSums {
    double contacts = 0, active = 0, cg = 0, kinetic = 0, detect = 0, response = 0, solve = 0;
    long steps = 0;
    [[nodiscard]] double mean(double sum) const { return sum / double(std::max<long>(steps, 1)); }
};

/// The timed loop: each iteration one Scene::step() (manual time: its wall time alone, instrumented
/// for callgrind by StepProbe), then its contacts, CG iterations, kinetic energy and phase timings
/// added to `sums`. False (the benchmark skipped with the error) when a step throws.
inline bool run_timed_steps(benchmark::State& state, scene::Scene& scene, StepSums& sums) {
    using Clock = std::chrono::steady_clock;
    start_instrumentation();
    try {
        for (auto _ : state) {
            const auto t0 = Clock::now();
            {
                const StepProbe probe;
                scene.step();
            }
            state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
            const output::ContactSummary c = output::summarize_contacts(scene.contacts());
            sums.contacts += double(c.contacts);
            sums.active += double(c.active_contacts);
            sums.cg += scene.last_solver_stats().cg_iterations;
            sums.kinetic += scene.kinetic_energy();
            const scene::StepTimings& t = scene.last_timings();
            sums.detect += t.detection_seconds;
            sums.response += t.response_seconds;
            sums.solve += t.solve_seconds;
            ++sums.steps;
        }
    } catch (const std::exception& e) {
        stop_instrumentation();
        state.SkipWithError(("step failed: " + std::string(e.what())).c_str());
        return false;
    }
    stop_instrumentation();
    return true;
}

/// The counters both whole-scene benchmarks report: DOFs, per-step means, memory.
/// `heap_without_contacts`: the live heap after a first step without contact.
inline void report_step_sums(benchmark::State& state, const scene::Scene& scene, const StepSums& sums,
                             double heap_without_contacts) {
    const double dofs = scalar_dofs(scene), heap = live_heap_bytes();
    const double contacts = sums.mean(sums.contacts);
    state.counters["dofs"] = dofs;
    state.counters["contacts"] = contacts;
    state.counters["active"] = sums.mean(sums.active);
    state.counters["cg_its"] = sums.mean(sums.cg);
    state.counters["kinetic_j"] = sums.mean(sums.kinetic);
    state.counters["detect_ms"] = 1e3 * sums.mean(sums.detect);
    state.counters["response_ms"] = 1e3 * sums.mean(sums.response);
    state.counters["solve_ms"] = 1e3 * sums.mean(sums.solve);
    state.counters["heap_mb"] = heap / 1e6;
    state.counters["bytes_per_dof"] = heap / dofs;
    state.counters["bytes_per_contact"] = contacts > 0 ? (heap - heap_without_contacts) / contacts : 0.0;
    state.counters["peak_rss_mb"] = peak_rss_bytes() / 1e6;
}

}  // namespace penalty::bench
