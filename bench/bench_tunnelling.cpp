// The tunnelling guard's cost and effect (issue 53, docs/no-tunnelling.md): each case is built
// four times, one per mode (off, warn, substep, stiffen), and the four scenes are stepped in turn
// within each benchmark iteration, so that the ratios to the unguarded step come from one run on
// the same machine state.
//
// Cases (tests/support/penalty_test/tunnelling_scenes.hpp, cubes_in_bowl.hpp):
//   Bowl/k:1 … 8     bench_scaling's cubes in a bowl: 300 steps untimed (the pile settles; the
//                    crossings are counted from the start), then 2000/k³ steps (10 … 200) timed
//   Ball/v:10,30,50  a ball thrown onto a single-layer sheet: 100 steps, all timed
//   BallOnCloth/v:50 the same onto a pinned spring cloth
//   Band             an elastic band around two pegs, pulled: 160 steps
//   DrapedSheet      a thin FEM sheet dropped on a sphere and pulled: 80 steps
//
// Manual time: the unguarded (off) step. Counters (per timed step unless said):
//   off_ms, warn_ms, substep_ms, stiffen_ms   wall time of Scene::step() of each mode
//   warn_ratio, substep_ratio, stiffen_ratio  each over off_ms (one run: the same machine state)
//   crossings_off       crossings of the unguarded motion over the whole run (warn's count:
//                       warn is the unguarded step bit for bit)
//   crossings_substep, crossings_stiffen      crossings left by the guard over the whole run (0 wanted)
//   prevented_substep, prevented_stiffen      crossings found and undone over the whole run
//   sunk_off, sunk_substep, sunk_stiffen      bowl: cube nodes beyond R + C from its centre at the end
// $PENALTY_TUNNELLING_SCENES=DIR also writes the cases' scenes into DIR.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/cubes_in_bowl.hpp"
#include "penalty_test/tunnelling_scenes.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

namespace penalty::scene {
namespace {

namespace bowl = penalty::test::cubes_in_bowl;
namespace tun = penalty::test::tunnelling;
using Clock = std::chrono::steady_clock;

constexpr std::array<TunnellingMode, 4> kModes = {TunnellingMode::off, TunnellingMode::warn, TunnellingMode::substep,
                                                  TunnellingMode::stiffen};

struct Case {
    std::string name;
    std::string xml;
    int untimed_steps = 0;
    int timed_steps = 100;
    int bowl_k = 0;  ///< > 0: a bowl (the sunk counters)
};

void write_scene_if_asked(const Case& c) {
    const char* dir = std::getenv("PENALTY_TUNNELLING_SCENES");
    if (dir == nullptr || *dir == '\0') return;
    std::filesystem::create_directories(dir);
    std::string file = c.name;
    std::replace(file.begin(), file.end(), '/', '_');
    std::replace(file.begin(), file.end(), ':', '_');
    std::ofstream(std::filesystem::path(dir) / (file + ".scn")) << c.xml;
}

/// Cube nodes farther than R + C from the bowl's centre (bench_scaling's `sunk`).
int sunk(const Scene& scene, int k) {
    bowl::Setup s;
    s.k = k;
    const auto c = bowl::bowl_centre(s);
    int n = 0;
    for (const auto& r : scene.states()) {
        if (!r.in_solver_subtree) continue;
        for (const Vec3& x : dynamic_cast<const Vec3Object&>(*r.state).position)
            if ((x - Vec3(c[0], c[1], c[2])).norm() > bowl::bowl_radius(s) + s.contact_distance) ++n;
    }
    return n;
}

struct ModeRun {
    std::unique_ptr<Scene> scene;
    double seconds = 0.0;  ///< timed steps
    std::size_t crossings = 0, prevented = 0;
    void step(bool timed) {
        const auto t0 = Clock::now();
        scene->step();
        if (timed) seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        if (const TunnellingReport* r = scene->tunnelling_report()) {
            crossings += r->crossings.size();
            prevented += r->prevented;
        }
    }
};

void BM_Tunnelling(benchmark::State& state, const Case& c) {
    std::array<ModeRun, kModes.size()> runs;
    try {
        write_scene_if_asked(c);
        for (std::size_t m = 0; m < kModes.size(); ++m) {
            BuildOptions o;
            o.no_tunnelling = kModes[m];
            runs[m].scene = build_scene(io::parse_scene_string(c.xml, c.name + ".scn"), o);
        }
        for (int i = 0; i < c.untimed_steps; ++i)
            for (ModeRun& r : runs) r.step(false);
    } catch (const std::exception& e) {
        state.SkipWithError(("build or warm-up failed: " + std::string(e.what())).c_str());
        for (auto _ : state) {
        }
        return;
    }
    long steps = 0;
    try {
        for (auto _ : state) {
            for (std::size_t m = 0; m < runs.size(); ++m) {
                const double before = runs[m].seconds;
                runs[m].step(true);
                if (m == 0) state.SetIterationTime(runs[m].seconds - before);
            }
            ++steps;
        }
    } catch (const std::exception& e) {
        state.SkipWithError(("step failed: " + std::string(e.what())).c_str());
        return;
    }
    const double n = double(std::max<long>(steps, 1));
    const double off = runs[0].seconds / n;
    const char* names[] = {"off", "warn", "substep", "stiffen"};
    for (std::size_t m = 0; m < runs.size(); ++m) {
        state.counters[std::string(names[m]) + "_ms"] = 1e3 * runs[m].seconds / n;
        if (m > 0) state.counters[std::string(names[m]) + "_ratio"] = off > 0 ? runs[m].seconds / n / off : 0.0;
    }
    state.counters["crossings_off"] = double(runs[1].crossings);
    state.counters["crossings_substep"] = double(runs[2].crossings);
    state.counters["crossings_stiffen"] = double(runs[3].crossings);
    state.counters["prevented_substep"] = double(runs[2].prevented);
    state.counters["prevented_stiffen"] = double(runs[3].prevented);
    if (c.bowl_k > 0) {
        state.counters["sunk_off"] = sunk(*runs[0].scene, c.bowl_k);
        state.counters["sunk_substep"] = sunk(*runs[2].scene, c.bowl_k);
        state.counters["sunk_stiffen"] = sunk(*runs[3].scene, c.bowl_k);
    }
}

std::vector<Case> cases() {
    std::vector<Case> out;
    for (double v : {10.0, 30.0, 50.0}) {
        tun::BallOnSheet b;
        b.speed = v;
        out.push_back({"Ball/v:" + std::to_string(int(v)), tun::ball_on_sheet_xml(b), 0, 100, 0});
    }
    tun::BallOnSheet cloth;
    cloth.speed = 50.0;
    cloth.deformable_sheet = true;
    out.push_back({"BallOnCloth/v:50", tun::ball_on_sheet_xml(cloth), 0, 60, 0});
    out.push_back({"Band", tun::band_on_pegs_xml(tun::BandOnPegs{}), 0, 160, 0});
    out.push_back({"DrapedSheet", tun::draped_sheet_xml(tun::DrapedSheet{}), 0, 80, 0});
    for (int k = 1; k <= 8; ++k) {
        bowl::Setup s;
        s.k = k;
        out.push_back(
            {"Bowl/k:" + std::to_string(k), bowl::scene_xml(s), 300, std::clamp(2000 / (k * k * k), 10, 200), k});
    }
    return out;
}

[[maybe_unused]] const bool registered = [] {
    static const std::vector<Case> all = cases();
    for (const Case& c : all)
        benchmark::RegisterBenchmark(("BM_Tunnelling/" + c.name).c_str(), BM_Tunnelling, c)
            ->Iterations(c.timed_steps)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
    return true;
}();

}  // namespace
}  // namespace penalty::scene
