#pragma once
// What the whole-scene benchmarks (bench_scaling.cpp, bench_large_scenes.cpp) measure besides
// time: the scene's DOFs, its memory (live heap bytes, peak RSS), the .scn files on request, the
// thread count from the environment, and the instruction counts of the timed steps alone under
// callgrind.
//
// Environment:
//   PENALTY_SCALING_SCENES=DIR   write each generated scene as DIR/<name>.scn (for `penalty run`)
//   PENALTY_BENCH_THREADS=N      BuildOptions::threads (default 0: TBB's default); 1 for callgrind
//
// Callgrind: `valgrind --tool=callgrind --instr-atstart=no --collect-atstart=no BENCH ...` runs
// the build and the warm-up uninstrumented (a few times slower than natively, not fifty), and
// collects the timed Scene::step() calls only (StepProbe): Ir per step = total Ir / steps.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"

#include <malloc.h>
#include <sys/resource.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define PENALTY_BENCH_CALLGRIND 1
#else
#define PENALTY_BENCH_CALLGRIND 0
#endif

namespace penalty::bench {

/// Writes `xml` as $PENALTY_SCALING_SCENES/<name>.scn when that variable is set.
inline void write_scene_if_asked(const std::string& name, const std::string& xml) {
    const char* dir = std::getenv("PENALTY_SCALING_SCENES");
    if (dir == nullptr || *dir == '\0') return;
    std::filesystem::create_directories(dir);
    std::ofstream(std::filesystem::path(dir) / (name + ".scn")) << xml;
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

}  // namespace penalty::bench
