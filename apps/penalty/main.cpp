// `penalty`: command-line entry point.
//   penalty run [SCENE] [options]   run a SOFA scene headless (built-in scene when none is given)
//   penalty info SCENE              builds the scene: what each component becomes, the contact pairs
//   penalty demo                    the force field alone on worked numbers
//   penalty view DIR                serves the browser viewer written by `penalty run --view DIR`
// Exit codes: 0 success; 1 invalid scene or input file; 2 command-line error; 3 the simulation
// diverged (NaN/inf); 4 the states differ from the SOFA reference (--reference); 5 other errors
// (output files, ...).
#include "demo.hpp"
#include "view_server.hpp"

#include "penalty/collision/intersection.hpp"
#include "penalty/io/error.hpp"
#include "penalty/io/overrides.hpp"
#include "penalty/output/format.hpp"
#include "penalty/output/output_file.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/output/viewer_writer.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/contact_advice.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/solver.hpp"

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string_view>

namespace {

enum ExitCode : int { kOk = 0, kBadInput = 1, kUsage = 2, kDiverged = 3, kReferenceMismatch = 4, kOther = 5 };

// ---- argument limits (docs/reliability.md) -------------------------------------------------------
/// Most steps one run may ask for: 10⁹ (a 1 µs step would take 17 minutes; beyond that a typo).
constexpr std::int64_t kMaxSteps = 1'000'000'000;
// Threads: 1 … penalty::kMaxThreads (simulation/solver.hpp); time step: scene::kMinTimeStep …
// scene::kMaxTimeStep (scene/scene.hpp). Each limit is stated once, there.

/// A validator for a whole number in [lo, hi]: the text must be an integer (no sign games, no
/// exponent), and a value out of range is named with the range, never a 309-digit bound.
CLI::Validator integer_in(std::int64_t lo, std::int64_t hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            std::int64_t value = 0;
            const char* first = text.data();
            const char* last = text.data() + text.size();
            if (first != last && *first == '+') ++first;
            const auto [ptr, ec] = std::from_chars(first, last, value);
            if (ec == std::errc::result_out_of_range)
                return "'" + text + "' is out of range (" + std::to_string(lo) + " to " + std::to_string(hi) + ")";
            if (ec != std::errc() || ptr != last || first == last) return "'" + text + "' is not a whole number";
            if (value < lo || value > hi)
                return std::to_string(value) + " is out of range (" + std::to_string(lo) + " to " + std::to_string(hi) +
                       ")";
            return {};
        },
        "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

/// A validator for a finite number in (lo, hi] (lo_open) or [lo, hi]; nan and inf are refused.
CLI::Validator number_in(double lo, double hi, bool lo_open) {
    return CLI::Validator(
        [lo, hi, lo_open](std::string& text) -> std::string {
            double value = 0.0;
            const char* first = text.data();
            const char* last = text.data() + text.size();
            if (first != last && *first == '+') ++first;
            const auto [ptr, ec] = std::from_chars(first, last, value);
            if (ec != std::errc() || ptr != last || first == last) return "'" + text + "' is not a number";
            if (!std::isfinite(value)) return "'" + text + "' is not a finite number";
            const bool low = lo_open ? !(value > lo) : !(value >= lo);
            if (low || value > hi) {
                char range[96];
                std::snprintf(range, sizeof range, "%s%g, %g]", lo_open ? "(" : "[", lo, hi);
                return "'" + text + "' is out of range " + range;
            }
            return {};
        },
        "NUMBER");
}

/// The build options' defaults, set once in scene::BuildOptions.
const penalty::scene::BuildOptions kBuildDefaults{};

struct RunArguments {
    std::string scene;
    std::int64_t steps = -1;
    double dt = 0.0;
    int threads = kBuildDefaults.threads;
    std::vector<std::string> data_dirs;
    std::string vtk, states, stats, reference;
    std::string compare_trajectory;                     ///< --compare-trajectory DIR
    double trajectory_threshold = 1e-12;                ///< --trajectory-threshold
    std::int64_t debug_step = -1;                       ///< --debug-step K
    std::string debug_file = "penalty-debug-step.txt";  ///< --debug-file FILE
    std::vector<std::string> quirk_fixes;               ///< --fix-sofa-quirk NAME (repeatable), --fix-sofa-quirks all
    std::vector<std::string> overrides;                 ///< --set PATH.attribute=value (repeatable)
    std::int64_t vtk_every = 1, export_every = 1;
    double divergence_factor = 100.0;
    bool export_mapped = false;
    bool exhaustive = kBuildDefaults.exhaustive_detection;
    bool sofa_head_orders = kBuildDefaults.sofa_head_orders;
    bool quiet = false;
    std::string summary_json;  // --summary-json FILE
    std::string view;          // --view DIR: the browser viewer (docs/viewer.md)
    std::int64_t view_every = 1;
    bool no_serve = false;
    int port = 0;               // 0: a free port
    std::string no_tunnelling;  // --no-tunnelling MODE (docs/no-tunnelling.md); "": the scene's
    std::string reduction = kBuildDefaults.blocked_reductions
                                ? "blocked"
                                : "sofa";  // --reduction sofa|blocked (docs/performance.md, "Blocked reductions")
};

/// A command-line value that is well-formed but not accepted (exit code 2).
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Writes `text` into `path` (`--summary-json FILE`); std::runtime_error naming it when it cannot.
void write_text_file(const std::filesystem::path& path, const std::string& text) {
    penalty::output::write_output_file(path, text);
}

std::string quirk_names() {
    std::string out = "known: all";
    for (const penalty::SofaQuirkInfo& q : penalty::sofa_quirk_table()) out += ", " + std::string(q.name);
    return out;
}

/// A fresh folder under the system's temporary directory, removed with its files at the end.
struct TemporaryDirectory {
    std::filesystem::path path;
    TemporaryDirectory() {
        const std::filesystem::path base = std::filesystem::temp_directory_path();
        for (int attempt = 0;; ++attempt) {
            path = base / ("penalty-states-" + std::to_string(::getpid()) + "-" + std::to_string(attempt));
            if (std::filesystem::create_directory(path)) return;
        }
    }
    ~TemporaryDirectory() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    TemporaryDirectory(const TemporaryDirectory&) = delete;
    TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
};

/// One progress line on a terminal (stderr), redrawn at most 10 times per second.
class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : enabled_(enabled) {}
    void operator()(std::int64_t done, std::int64_t total, const penalty::scene::RunSummary& s) {
        if (!enabled_) return;
        const auto now = std::chrono::steady_clock::now();
        if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        const int width = 30;
        const int filled = total > 0 ? int(double(width) * double(done) / double(total)) : width;
        std::fprintf(
            stderr, "\r[%s%s] %3d%%  step %lld/%lld  t = %.4g s  %.0f steps/s ",
            std::string(std::size_t(filled), '#').c_str(), std::string(std::size_t(width - filled), '.').c_str(),
            total > 0 ? int(100 * done / total) : 100, static_cast<long long>(done), static_cast<long long>(total),
            s.simulated_time,
            s.detection_seconds + s.response_seconds + s.solve_seconds > 0
                ? double(done) / (s.detection_seconds + s.response_seconds + s.solve_seconds + s.output_seconds)
                : 0.0);
        if (done == total) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }

private:
    bool enabled_;
    std::chrono::steady_clock::time_point last_{};
};

int run_command(const RunArguments& a) {
    namespace sc = penalty::scene;
    sc::BuildOptions build;
    for (const auto& d : a.data_dirs) build.data_dirs.emplace_back(d);
    if (a.dt > 0) build.dt = a.dt;
    build.threads = a.threads;
    build.exhaustive_detection = a.exhaustive;
    build.sofa_head_orders = a.sofa_head_orders;
    if (!a.no_tunnelling.empty()) build.no_tunnelling = penalty::parse_tunnelling_mode(a.no_tunnelling);
    build.blocked_reductions = a.reduction == "blocked";
    // A malformed --set is a usage error (exit 2); a path or attribute the scene lacks is an
    // invalid input (exit 1, from the builder).
    for (const std::string& o : a.overrides) {
        try {
            (void)penalty::io::parse_override(o);
        } catch (const penalty::io::OverrideSyntaxError& e) {
            throw UsageError(e.what());
        }
    }
    build.overrides = a.overrides;
    for (const std::string& name : a.quirk_fixes)
        if (!penalty::enable_sofa_quirk_fix(build.sofa_quirk_fixes, name))
            throw UsageError("--fix-sofa-quirk: unknown SOFA quirk '" + name + "' (" + quirk_names() + ")");
    std::optional<tbb::global_control> threads;
    if (a.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(a.threads));

    const bool builtin = a.scene.empty();
    std::unique_ptr<sc::Scene> scene =
        builtin ? sc::build_scene(penalty::io::parse_scene_string(sc::default_scene_xml(), "<built-in scene>"), build)
                : sc::load_scene(a.scene, build);
    std::cout << "penalty run: "
              << (builtin ? std::string("built-in scene (soft cube and rigid ball on a floor)") : a.scene) << "\n";
    std::cout << scene->states().size() << " states, " << scene->collision_models().size() << " collision models, "
              << scene->pipelines().size() << " collision pipeline(s)\n";
    for (const std::string& w : scene->warnings()) std::cout << "note: " << w << "\n";

    // --compare-trajectory without --export-states: the states go to a temporary folder.
    std::optional<TemporaryDirectory> temporary_states;
    std::string states_directory = a.states;
    if (!a.compare_trajectory.empty() && states_directory.empty()) {
        temporary_states.emplace();
        states_directory = temporary_states->path.string();
    }

    sc::RunOptions run;
    run.steps = a.steps >= 0 ? a.steps : (builtin ? 400 : 100);
    if (!a.vtk.empty()) run.vtk_directory = a.vtk;
    run.vtk_every = a.vtk_every;
    if (!states_directory.empty()) run.states_directory = states_directory;
    run.export_mapped = a.export_mapped;
    run.export_every = a.export_every;
    if (!a.stats.empty()) run.stats_file = a.stats;
    run.divergence_factor = a.divergence_factor;
    if (!a.view.empty()) run.view_directory = a.view;
    run.view_every = a.view_every;
    run.view_title = builtin ? std::string("built-in scene") : std::filesystem::path(a.scene).filename().string();
    if (a.debug_step >= 0) {
        if (a.debug_step >= run.steps)
            throw UsageError("--debug-step " + std::to_string(a.debug_step) + " is not below --steps " +
                             std::to_string(run.steps));
        run.debug_step = a.debug_step;
        run.debug_file = a.debug_file;
    }
    ProgressBar bar(!a.quiet && isatty(STDERR_FILENO) != 0);
    const sc::RunSummary summary = sc::run_scene(*scene, run, std::ref(bar));
    std::cout << sc::format_summary(summary);
    if (!a.states.empty())
        std::cout << "states: " << summary.state_files.size() << " files in " << a.states
                  << (summary.steps == 0 ? " (0 steps: the initial state only)" : "") << "\n";
    if (!a.vtk.empty()) std::cout << "vtk: series in " << a.vtk << " (open the .pvd files in ParaView)\n";
    if (!a.stats.empty()) std::cout << "stats: " << a.stats << "\n";
    if (!a.view.empty()) std::cout << "view: browser viewer in " << a.view << " (penalty view " << a.view << ")\n";
    if (a.debug_step >= 0) std::cout << "debug: step " << a.debug_step << " in " << a.debug_file << "\n";
    if (!a.summary_json.empty()) {
        write_text_file(a.summary_json, sc::summary_json(summary));
        std::cout << "summary: " << a.summary_json << "\n";
    }

    if (!a.reference.empty()) {
        if (builtin) throw std::invalid_argument("--reference needs a scene file");
        const auto refs = sc::reference_files(a.reference, a.scene, summary.state_files);
        const penalty::output::RegressionResult r =
            penalty::output::compare_with_reference(refs, summary.state_files, summary.values_per_dof);
        for (const auto& m : r.messages) std::cout << "reference: " << m << "\n";
        for (std::size_t i = 0; i < r.per_state_error.size(); ++i)
            std::cout << "reference: " << refs[i].filename().string() << ": error " << r.per_state_error[i] << "\n";
        std::cout << "reference: mean error " << r.mean_error
                  << " (SOFA's criterion: <= 1e-4): " << (r.passed() ? "PASS" : "FAIL") << "\n";
        if (!r.passed()) return kReferenceMismatch;
    }
    if (!a.compare_trajectory.empty()) {
        if (builtin) throw std::invalid_argument("--compare-trajectory needs a scene file");
        const penalty::output::TrajectoryComparison c = penalty::output::compare_trajectories(
            a.compare_trajectory, summary.state_files, summary.values_per_dof, a.trajectory_threshold);
        std::cout << penalty::output::format_trajectory_comparison(c);
        if (!c.passed()) return kReferenceMismatch;
    }
    if (!a.view.empty() && !a.no_serve) penalty::apps::serve_directory(a.view, a.port, std::cout);
    return kOk;
}

/// `penalty view DIR`: refreshes the page files of a viewer directory and serves it.
int view_command(const std::string& directory, int port, bool no_serve) {
    // the server serves only regular files that are not links (view_server.cpp): a run.json that
    // is a link would pass a check that follows it and then be refused, so it is refused here
    const std::filesystem::file_status run_json =
        std::filesystem::symlink_status(std::filesystem::path(directory) / "run.json");
    if (std::filesystem::is_symlink(run_json))
        throw std::invalid_argument("'" + directory + "/run.json' is a symbolic link: penalty view serves no link");
    if (!std::filesystem::is_regular_file(run_json))
        throw std::invalid_argument("'" + directory +
                                    "' has no run.json: not a viewer directory (write one with "
                                    "`penalty run SCENE --view " +
                                    directory + "`)");
    penalty::output::write_viewer_page(directory);
    if (no_serve) {
        std::cout << "penalty view: page files written in " << directory << "\n";
        return kOk;
    }
    penalty::apps::serve_directory(directory, port, std::cout);
    return kOk;
}

int info_command(const std::string& scene_path, const std::vector<std::string>& data_dirs,
                 const std::vector<std::string>& quirk_fixes, bool contact_advice, double impact_speed,
                 bool all_pairs) {
    penalty::scene::BuildOptions build;
    for (const auto& d : data_dirs) build.data_dirs.emplace_back(d);
    for (const std::string& name : quirk_fixes)
        if (!penalty::enable_sofa_quirk_fix(build.sofa_quirk_fixes, name))
            throw UsageError("--fix-sofa-quirk: unknown SOFA quirk '" + name + "' (" + quirk_names() + ")");
    const std::unique_ptr<penalty::scene::Scene> scene = penalty::scene::load_scene(scene_path, build);
    if (contact_advice) {
        std::cout << penalty::scene::contact_advice(
            *scene, impact_speed > 0 ? std::optional<double>(impact_speed) : std::nullopt);
        return kOk;
    }
    std::cout << penalty::scene::describe_scene(
        *scene, all_pairs ? std::numeric_limits<std::size_t>::max() : penalty::scene::kDescribedPairLines);
    std::cout << "SOFA quirk fixes (--fix-sofa-quirk NAME, or fixSofaQuirks=\"NAME ...\" on an intersection method):\n";
    for (const penalty::SofaQuirkInfo& q : penalty::sofa_quirk_table())
        std::cout << "  " << q.name << (build.sofa_quirk_fixes.*q.member ? " [on for every pipeline]" : "") << ": "
                  << q.description << "\n";
    return kOk;
}

/// `penalty run|info scene.py ...` and `penalty sweep ...`: a SofaPython3 script, or a sweep, runs in the Python module
/// (same options, output and exit codes), through Debian's interpreter: `python3 -m penalty <same arguments>`. Returns
/// only if the script cannot be handed over.
int run_python_scene(int argc, char** argv) {
#ifdef PENALTY_PYTHON_EXECUTABLE
    namespace fs = std::filesystem;
    std::string path;
    for (const char* dir : {PENALTY_PYTHON_BUILD_PATH, PENALTY_PYTHON_INSTALL_PATH}) {
        std::error_code ec;
        if (fs::exists(fs::path(dir) / "penalty" / "__init__.py", ec))
            path += (path.empty() ? "" : ":") + std::string(dir);
    }
    if (const char* old = std::getenv("PYTHONPATH"); old != nullptr && *old != '\0')
        path += (path.empty() ? "" : ":") + std::string(old);
    setenv("PYTHONPATH", path.c_str(), 1);
    // A pip-installed `penalty` (python/penalty/_cli.py) names its own interpreter.
    const char* python = std::getenv("PENALTY_PYTHON");
    if (python == nullptr || *python == '\0') python = PENALTY_PYTHON_EXECUTABLE;
    std::vector<char*> args{const_cast<char*>(python), const_cast<char*>("-m"), const_cast<char*>("penalty")};
    for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
    args.push_back(nullptr);
    execv(python, args.data());
    std::cerr << "penalty: error: cannot start " << python << " for the Python scene: " << std::strerror(errno) << "\n";
    return kOther;
#else
    (void)argc;
    (void)argv;
    std::cerr << "penalty: error: SofaPython3 scenes (.py) and `penalty sweep` need the Python module, which this "
                 "build does not include "
                 "(PENALTY_BUILD_PYTHON: it needs pybind11-dev, python3-dev and python3-numpy, and is off under the "
                 "sanitizers); use a release build or python3 -m penalty\n";
    return kBadInput;
#endif
}

/// True for `penalty run|info ... scene.py ...`: the positional scene argument ends in ".py"
/// (option values, e.g. `--stats out.py`, are skipped).
bool is_python_scene_command(int argc, char** argv) {
    if (argc < 3 || (std::strcmp(argv[1], "run") != 0 && std::strcmp(argv[1], "info") != 0)) return false;
    for (int i = 2; i < argc; ++i) {
        const std::string_view a = argv[i];
        if (a.starts_with("-")) {
            const bool flag = a == "--export-mapped" || a == "--exhaustive" || a == "--sofa-head-orders" ||
                              a == "--no-sofa-head-orders" || a == "--quiet" || a == "--contact-advice" ||
                              a.find('=') != a.npos;
            if (!flag) ++i;  // its value
            continue;
        }
        return a.size() > 3 && a.ends_with(".py");
    }
    return false;
}

/// Levenshtein distance between two option names (for "did you mean").
std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

/// The first argument of subcommand `sub` (argv[2...]) that looks like an option and is none of
/// its options, as an error naming it and the nearest option. CLI11 alone would take the next
/// argument for the scene file (`penalty run --stpes 10`: "scene: File does not exist: 10").
/// Numbers (`--steps -3`) and everything after `--` are values, never options.
std::optional<std::string> unknown_option(CLI::App& sub, int argc, char** argv) {
    for (int i = 2; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--") return std::nullopt;
        if (arg.size() < 2 || arg[0] != '-') continue;
        char* end = nullptr;
        (void)std::strtod(argv[i], &end);
        if (end != nullptr && *end == '\0') continue;  // a negative number: a value
        const std::string name(arg.substr(0, arg.find('=')));
        if (sub.get_option_no_throw(name) != nullptr) continue;
        std::string nearest;
        std::size_t best = 3;  // suggest within two edits
        for (const CLI::Option* option : sub.get_options())
            for (const std::string& known : option->get_lnames())
                if (const std::size_t d = edit_distance(name, "--" + known); d < best) {
                    best = d;
                    nearest = "--" + known;
                }
        return "penalty " + sub.get_name() + ": unknown option '" + name + "'" +
               (nearest.empty() ? std::string() : " (did you mean '" + nearest + "'?)");
    }
    return std::nullopt;
}

/// The `run` subcommand and its options, bound to `args`.
CLI::App* add_run_command(CLI::App& app, RunArguments& args) {
    CLI::App* run = app.add_subcommand("run", "Run a SOFA scene headless (the built-in scene when none is given)");
    run->add_option("scene", args.scene, "SOFA .scn file (or SofaPython3 .py script, run by the Python module)")
        ->check(CLI::ExistingFile);
    run->add_option("--steps", args.steps, "Number of time steps (default 100; 400 for the built-in scene)")
        ->check(integer_in(0, kMaxSteps));
    run->add_option("--dt", args.dt, "Time step (s), overrides the scene's")
        ->check(number_in(penalty::scene::kMinTimeStep, penalty::scene::kMaxTimeStep, false));
    run->add_option("--threads", args.threads,
                    "Threads for the detection, the contacts' response and independent solvers (default: all cores)")
        ->check(integer_in(1, penalty::kMaxThreads));
    run->add_option("--set", args.overrides,
                    "Override an attribute before the scene is built: PATH.attribute=value, e.g. "
                    "/Floor/FloorTri1.contactStiffness=200 or /.dt=0.005 (repeatable; docs/sweeps.md)");
    run->add_option("--data-dir", args.data_dirs, "Folder searched for mesh and included files (repeatable)")
        ->check(CLI::ExistingDirectory);
    run->add_option("--vtk", args.vtk, "Write a ParaView time series (.pvd + .vtu/.vtp) into DIR");
    run->add_option("--vtk-every", args.vtk_every, "Write one VTK step in M")->check(integer_in(1, kMaxSteps));
    run->add_option("--export-states", args.states, "Write SOFA regression state files into DIR");
    run->add_flag("--export-mapped", args.export_mapped, "Also export mapped states");
    run->add_option("--export-every", args.export_every, "Export one step in M, plus the last")
        ->check(integer_in(1, kMaxSteps));
    run->add_option(
           "--divergence-factor", args.divergence_factor,
           "Diverged when a step moves a DOF by more than F times the initial scene size (default 100; 0: off)")
        ->check(number_in(0.0, 1e100, false));
    run->add_option("--stats", args.stats, "Write per-step statistics to FILE.csv");
    run->add_option("--summary-json", args.summary_json,
                    "Write the run's summary to FILE as JSON (the numbers printed at the end; Python's Scene.run "
                    "returns the same)");
    run->add_option("--reference", args.reference,
                    "Compare the exported states with SOFA's reference files in DIR (needs --export-states)");
    run->add_option("--compare-trajectory", args.compare_trajectory,
                    "Compare every exported step with SOFA's state files (<k>_<name>_mstate.txt[.gz]) in DIR: SOFA's "
                    "criterion, first step above --trajectory-threshold per state; exit code 4 on a mismatch")
        ->check(CLI::ExistingDirectory);
    run->add_option("--trajectory-threshold", args.trajectory_threshold,
                    "Largest |x - x_SOFA| per value accepted by --compare-trajectory (default 1e-12)")
        ->check(CLI::NonNegativeNumber);
    run->add_option("--debug-step", args.debug_step,
                    "After step K (0 = the first), write its contacts, linear solves and forces (--debug-file)")
        ->check(CLI::NonNegativeNumber);
    run->add_option("--debug-file", args.debug_file, "File of --debug-step (default penalty-debug-step.txt)");
    run->add_option("--fix-sofa-quirk", args.quirk_fixes,
                    "Fix a SOFA bug: in every intersection method, or in reading MechanicalObjects (repeatable; 'all' "
                    "for every one; names: penalty info)");
    run->add_option("--fix-sofa-quirks", args.quirk_fixes, "Same as --fix-sofa-quirk (e.g. --fix-sofa-quirks all)");
    run->add_flag("--exhaustive", args.exhaustive, "Detect with SOFA's exhaustive pair loop instead of the BVH");
    run->add_flag("--sofa-head-orders,!--no-sofa-head-orders", args.sofa_head_orders,
                  "Sum forces through SOFA HEAD's MappingGraph and order contacts by its stable-id maps "
                  "(default; --no-sofa-head-orders: the visitors' order and contacts in scene order)");
    run->add_flag("--quiet", args.quiet, "No progress bar");
    run->add_option(
           "--no-tunnelling", args.no_tunnelling,
           "Tunnelling guard (beyond SOFA, docs/no-tunnelling.md): off, warn (report the crossings), substep "
           "(redo a crossing step in halves) or stiffen (stiffen deep contacts); default: the scene's noTunnelling")
        ->check(CLI::IsMember({"off", "warn", "substep", "stiffen"}));
    run->add_option(
           "--reduction", args.reduction,
           "The CG's dot products: sofa (SOFA's single chain, the default) or blocked (beyond SOFA: fixed blocks "
           "of 4096 DOFs summed on several threads, the same bits at any --threads; docs/performance.md)")
        ->check(CLI::IsMember({"sofa", "blocked"}));
    auto* view_option = run->add_option("--view", args.view,
                                        "Write the browser viewer into DIR and serve it on 127.0.0.1 after the run");
    run->add_option("--view-every", args.view_every, "Keep one viewer frame in M (and the last)")
        ->check(CLI::PositiveNumber)
        ->needs(view_option);
    run->add_flag("--no-serve", args.no_serve, "With --view: only write the files")->needs(view_option);
    run->add_option("--port", args.port, "With --view: the port to serve on (default: a free one)")
        ->check(CLI::Range(0, 65535))
        ->needs(view_option);
    return run;
}

}  // namespace

int main(int argc, char** argv) {
    // `penalty sweep ...`: parameter sweeps on Dask run in the Python module (docs/sweeps.md).
    if (is_python_scene_command(argc, argv) || (argc >= 2 && std::strcmp(argv[1], "sweep") == 0))
        return run_python_scene(argc, argv);
    CLI::App app{"penalty: fast, validated penalty-based contact for deformable and rigid bodies"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("penalty ") + PENALTY_VERSION);

    RunArguments args;
    CLI::App* run = add_run_command(app, args);

    std::string view_dir;
    int view_port = 0;
    bool view_no_serve = false;
    auto* view = app.add_subcommand(
        "view", "Serve the browser viewer of a run (written by penalty run --view DIR) on 127.0.0.1");
    view->add_option("dir", view_dir, "Viewer directory")->required()->check(CLI::ExistingDirectory);
    view->add_option("--port", view_port, "Port (default: a free one)")->check(CLI::Range(0, 65535));
    view->add_flag("--no-serve", view_no_serve, "Only refresh the page files");

    std::string info_scene;
    std::vector<std::string> info_data_dirs;
    auto* info = app.add_subcommand(
        "info",
        "Build a scene without running it: what each component becomes, and which model pairs make contacts where");
    info->add_option("scene", info_scene, "SOFA .scn file")->check(CLI::ExistingFile);
    bool info_all_components = false;
    std::string info_component;
    info->add_flag("--components", info_all_components,
                   "List every supported component type with the attributes it reads (kind, unit, check, default)");
    info->add_option("--component", info_component, "The same for one component type (e.g. UniformMass)");
    info->add_option("--data-dir", info_data_dirs, "Folder searched for mesh and included files (repeatable)")
        ->check(CLI::ExistingDirectory);
    std::vector<std::string> info_quirk_fixes;
    info->add_option("--fix-sofa-quirk,--fix-sofa-quirks", info_quirk_fixes,
                     "As for run: SOFA bugs fixed (repeatable; 'all')");
    bool info_contact_advice = false;
    double info_impact_speed = 0.0;
    info->add_flag("--contact-advice", info_contact_advice,
                   "The largest time step and smallest contact stiffness at which the scene's bodies cannot tunnel "
                   "(docs/no-tunnelling.md)");
    info->add_option("--impact-speed", info_impact_speed,
                     "With --contact-advice: the impact speed (m/s; default: estimated)")
        ->check(number_in(0.0, 1e6, true));
    bool info_all_pairs = false;
    info->add_flag("--all-pairs", info_all_pairs,
                   "A line for every model pair (default: the first 200 of a pipeline, the others counted by kind)");

    // Listed for --help only: `penalty sweep ...` is handed to the Python module before parsing.
    app.add_subcommand("sweep",
                       "Parameter sweep on Dask: one run per override set (python3 -m penalty sweep --help; "
                       "docs/sweeps.md)")
        ->allow_extras();
    auto* demo = app.add_subcommand("demo", "Built-in demonstration of the penalty force field alone");
    penalty::apps::DemoOptions options;
    demo->add_option("--stiffness", options.stiffness, "Contact stiffness ks (N/m)")->check(number_in(0.0, 1e12, true));
    demo->add_option("--damping", options.damping, "Normal damping c (N·s/m) of the drop")
        ->check(number_in(0.0, 1e12, false));
    demo->add_option("--friction", options.friction, "Friction coefficient mu (static = dynamic) of the drop")
        ->check(number_in(0.0, 100.0, false));

    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        if (argc >= 2 && sub->get_name() == argv[1] && sub->get_name() != "sweep")
            if (const std::optional<std::string> problem = unknown_option(*sub, argc, argv)) {
                std::cerr << "penalty: error: " << *problem << "\n"
                          << "Run 'penalty " << sub->get_name() << " --help' for the options.\n";
                return kUsage;
            }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line with the tool's prefix (CLI11's own printer has none), then where to look.
        std::cerr << "penalty: error: " << e.what() << "\n"
                  << "Run 'penalty --help' or 'penalty run --help' for the options.\n";
        return kUsage;
    }
    try {
        if (*run) {
            if (!args.reference.empty() && args.states.empty()) {
                std::cerr << "penalty: error: --reference needs --export-states DIR\n";
                return kUsage;
            }
            return run_command(args);
        }
        if (*info && (info_all_components || !info_component.empty())) {
            std::cout << penalty::scene::describe_components(info_component);
            return kOk;
        }
        if (*info && info_scene.empty()) throw UsageError("info: a scene file, or --components, or --component TYPE");
        if (*info)
            return info_command(info_scene, info_data_dirs, info_quirk_fixes, info_contact_advice, info_impact_speed,
                                info_all_pairs);
        if (*view) return view_command(view_dir, view_port, view_no_serve);
        return penalty::apps::run_demo(options, std::cout);
    } catch (const UsageError& e) {
        std::cerr << "penalty: error: " << e.what() << "\n";
        return kUsage;
    } catch (const penalty::io::LoadError& e) {
        std::cerr << "penalty: error: " << e.what() << "\n";
        return kBadInput;
    } catch (const penalty::output::NonFiniteValueError& e) {
        std::cerr << "penalty: error: " << e.what() << "\n";
        return kDiverged;
    } catch (const penalty::NonFiniteSolveError& e) {
        std::cerr << "penalty: error: simulation diverged: " << e.what() << "\n";
        return kDiverged;
    } catch (const std::invalid_argument& e) {
        std::cerr << "penalty: error: " << e.what() << "\n";
        return kBadInput;
    } catch (const std::exception& e) {
        std::cerr << "penalty: error: " << e.what() << "\n";
        return kOther;
    }
}
