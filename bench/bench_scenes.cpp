// Whole scenes (issue 7): steps per second of every SOFA scene of the shared folder
// (<shared>/sofa/scenes/*.scn) and of every project scene (scenes/*.scn), with the phase split of
// Scene::last_timings() and the number of contacts per step; and the BVH narrow phase against
// SOFA's exhaustive pair loop (BuildOptions::exhaustive_detection) on the heaviest shared scenes.
//
// Scenes are globbed when the executable starts (new project scenes are picked up without a
// rebuild). The shared folder is $PENALTY_SHARED_DIR, or <source>/../shared; when it has no
// sofa/scenes folder, the shared benchmarks are reported as skipped with an error.
//
// Method. A scene is built once (load_scene, data dirs: the scene's folder, then <shared>/sofa),
// then kWarmupSteps steps are run untimed. A benchmark iteration is kStepsPerIteration steps; only
// Scene::step() is timed (manual time), the contact count after each step is not. The scene is
// never rebuilt: successive iterations continue the same trajectory. Threads of the narrow phase
// and of independent solvers: TBB's default (BuildOptions::threads = 0).
//
// Counters (per step, over the timed steps of the reported run):
//   steps_per_s               timed steps / Σ step wall time
//   detect_ms, response_ms, solve_ms   mean of Scene::last_timings()
//   contacts                  mean Σ contact force-field sizes after the step
//   dofs                      Σ scalar DOFs of the simulated states: unmapped, in a solver's subtree
//                             (3 per Vec3 point, 6 per rigid frame; static obstacles not counted)
//   elements                  Σ sizes of the collision models
// BVH vs exhaustive: both builds of the same scene run in one benchmark, alternating one
// iteration each; counters bvh_detect_ms, exh_detect_ms, detect_ratio (exhaustive / BVH),
// bvh_step_ms, exh_step_ms, step_ratio, and contacts_equal (1 when both builds had the same
// contact count after every timed step, as they must).
#include "penalty/output/stats_csv.hpp"
#include "penalty/scene/scene.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace penalty::scene {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kWarmupSteps = 20;
constexpr int kStepsPerIteration = 50;
constexpr int kIterations = 4;         // 200 timed steps per scene
constexpr int kCompareIterations = 2;  // per build: 100 timed steps each

fs::path source_dir() { return fs::path(__FILE__).parent_path().parent_path(); }

fs::path shared_dir() {
    if (const char* env = std::getenv("PENALTY_SHARED_DIR"); env != nullptr && *env != '\0') return fs::path(env);
    return source_dir() / ".." / "shared";
}

fs::path shared_scene_dir() { return shared_dir() / "sofa" / "scenes"; }

std::vector<fs::path> glob_scenes(const fs::path& dir) {
    std::vector<fs::path> out;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return out;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.is_regular_file() && e.path().extension() == ".scn") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

struct Loaded {
    std::unique_ptr<Scene> scene;
    std::string error;  // build or warm-up failure
};

/// Builds (once per path and detection mode) and warms up a scene.
Loaded& loaded(const fs::path& file, bool exhaustive) {
    static std::map<std::pair<std::string, bool>, Loaded> cache;
    auto [it, inserted] = cache.try_emplace({file.string(), exhaustive});
    if (!inserted) return it->second;
    try {
        BuildOptions options;
        options.data_dirs = {shared_dir() / "sofa"};
        options.exhaustive_detection = exhaustive;
        it->second.scene = load_scene(file, options);
        for (int k = 0; k < kWarmupSteps; ++k) it->second.scene->step();
    } catch (const std::exception& e) {
        it->second.error = e.what();
        it->second.scene.reset();
    }
    return it->second;
}

double scalar_dofs(const Scene& s) {
    double n = 0;
    for (const auto& r : s.states())
        if (!r.mapped && r.in_solver_subtree && r.state != nullptr) n += double(r.state->scalar_size());
    return n;
}

double collision_elements(const Scene& s) {
    double n = 0;
    for (const auto& m : s.collision_models()) n += double(m.model->size());
    return n;
}

std::size_t contact_count(const Scene& s) {
    const auto records = s.contacts();
    return output::summarize_contacts(records).contacts;
}

/// Running sums over timed steps.
struct Totals {
    double wall = 0, detect = 0, response = 0, solve = 0, contacts = 0;
    long steps = 0;
};

/// Runs `n` steps, timing Scene::step() only; returns the wall time; appends contact counts.
double run_steps(Scene& s, int n, Totals& t, std::vector<std::size_t>* counts = nullptr) {
    double wall = 0;
    for (int k = 0; k < n; ++k) {
        const auto t0 = Clock::now();
        s.step();
        wall += std::chrono::duration<double>(Clock::now() - t0).count();
        const StepTimings& tm = s.last_timings();
        t.detect += tm.detection_seconds;
        t.response += tm.response_seconds;
        t.solve += tm.solve_seconds;
        const std::size_t c = contact_count(s);
        t.contacts += double(c);
        if (counts != nullptr) counts->push_back(c);
    }
    t.wall += wall;
    t.steps += n;
    return wall;
}

void BM_Scene(benchmark::State& state, const fs::path& file, bool shared) {
    if (shared && !fs::is_directory(shared_scene_dir())) {
        state.SkipWithError(("shared folder absent: " + shared_scene_dir().string()).c_str());
        for (auto _ : state) {
        }
        return;
    }
    Loaded& l = loaded(file, false);
    if (!l.scene) {
        state.SkipWithError(("build or warm-up failed: " + l.error).c_str());
        for (auto _ : state) {
        }
        return;
    }
    Scene& s = *l.scene;
    Totals t;
    try {
        for (auto _ : state) state.SetIterationTime(run_steps(s, kStepsPerIteration, t));
    } catch (const std::exception& e) {
        state.SkipWithError(("step failed: " + std::string(e.what())).c_str());
        return;
    }
    const double n = double(std::max<long>(t.steps, 1));
    state.counters["steps_per_s"] = t.wall > 0 ? double(t.steps) / t.wall : 0.0;
    state.counters["detect_ms"] = 1e3 * t.detect / n;
    state.counters["response_ms"] = 1e3 * t.response / n;
    state.counters["solve_ms"] = 1e3 * t.solve / n;
    state.counters["contacts"] = t.contacts / n;
    state.counters["dofs"] = scalar_dofs(s);
    state.counters["elements"] = collision_elements(s);
}

void BM_BvhVsExhaustive(benchmark::State& state, const fs::path& file) {
    if (!fs::is_directory(shared_scene_dir()) || !fs::exists(file)) {
        state.SkipWithError(("shared scene absent: " + file.string()).c_str());
        for (auto _ : state) {
        }
        return;
    }
    // Fresh builds for both modes, so that both start from the same state (BM_Scene's build of
    // the scene has moved on).
    std::unique_ptr<Scene> bvh, exh;
    try {
        BuildOptions ob;
        ob.data_dirs = {shared_dir() / "sofa"};
        BuildOptions oe = ob;
        oe.exhaustive_detection = true;
        bvh = load_scene(file, ob);
        exh = load_scene(file, oe);
        for (int k = 0; k < kWarmupSteps; ++k) {
            bvh->step();
            exh->step();
        }
    } catch (const std::exception& e) {
        state.SkipWithError(("build or warm-up failed: " + std::string(e.what())).c_str());
        for (auto _ : state) {
        }
        return;
    }
    Totals tb, te;
    std::vector<std::size_t> cb, ce;
    try {
        for (auto _ : state) {
            const double wb = run_steps(*bvh, kStepsPerIteration, tb, &cb);
            const double we = run_steps(*exh, kStepsPerIteration, te, &ce);
            state.SetIterationTime(wb + we);
        }
    } catch (const std::exception& e) {
        state.SkipWithError(("step failed: " + std::string(e.what())).c_str());
        return;
    }
    const double nb = double(std::max<long>(tb.steps, 1)), ne = double(std::max<long>(te.steps, 1));
    const double db = 1e3 * tb.detect / nb, de = 1e3 * te.detect / ne;
    const double sb = 1e3 * tb.wall / nb, se = 1e3 * te.wall / ne;
    state.counters["bvh_detect_ms"] = db;
    state.counters["exh_detect_ms"] = de;
    state.counters["detect_ratio"] = db > 0 ? de / db : 0.0;
    state.counters["bvh_step_ms"] = sb;
    state.counters["exh_step_ms"] = se;
    state.counters["step_ratio"] = sb > 0 ? se / sb : 0.0;
    state.counters["contacts"] = tb.contacts / nb;
    state.counters["contacts_equal"] = cb == ce ? 1.0 : 0.0;
    state.counters["elements"] = collision_elements(*bvh);
}

/// Registers the benchmarks when the executable starts (before benchmark's main).
const bool registered = [] {
    const fs::path shared = shared_scene_dir();
    const std::vector<fs::path> shared_scenes = glob_scenes(shared);
    if (shared_scenes.empty()) {
        benchmark::RegisterBenchmark("BM_Scene/shared/(absent)",
                                     [](benchmark::State& st) { BM_Scene(st, fs::path(), true); })
            ->UseManualTime()
            ->Iterations(1);
    }
    for (const fs::path& f : shared_scenes) {
        benchmark::RegisterBenchmark(("BM_Scene/shared/" + f.stem().string()).c_str(),
                                     [f](benchmark::State& st) { BM_Scene(st, f, true); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(kIterations);
    }
    for (const fs::path& f : glob_scenes(source_dir() / "scenes")) {
        benchmark::RegisterBenchmark(("BM_Scene/project/" + f.stem().string()).c_str(),
                                     [f](benchmark::State& st) { BM_Scene(st, f, false); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(kIterations);
    }
    for (const char* name : {"collisionMultiple", "Gravity", "MeshSpringForceField"}) {
        const fs::path f = shared / (std::string(name) + ".scn");
        benchmark::RegisterBenchmark((std::string("BM_BvhVsExhaustive/") + name).c_str(),
                                     [f](benchmark::State& st) { BM_BvhVsExhaustive(st, f); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(kCompareIterations);
    }
    return true;
}();

}  // namespace
}  // namespace penalty::scene
