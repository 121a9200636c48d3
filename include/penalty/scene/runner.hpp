#pragma once
/// @file
/// Runs a built scene for a number of steps with the outputs of `penalty run` (SOFA regression
/// states, VTK series, per-step CSV), a progress line and a summary.
///
/// Order within step k (k = 0 … steps−1), as SOFA's DefaultAnimationLoop with WriteState:
///   1. outputs of the state at time t_k = k·dt (state files when k is kept, VTK pieces);
///   2. the step (collision with the positions at t_k, then the solvers);
///   3. divergence check of every state that can move (a NaN/inf position, or a DOF that jumped
///      beyond DivergenceBound, stops the run with an error naming the state, the DOF and the
///      step; RunOptions::states_change_between_steps), statistics row.
/// A non-finite value inside the solve (NonFiniteSolveError) is a divergence naming the step, the
/// state and the force field or mass; at the first step, from a known component, it is invalid
/// input naming that component (a parameter too large).
/// After the last step, the VTK series and the viewer get the final state at t = steps·dt.

#include "penalty/scene/scene.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace penalty::scene {

struct RunOptions {
    std::int64_t steps = 100;
    std::optional<std::filesystem::path> vtk_directory;     ///< `--vtk DIR`
    std::int64_t vtk_every = 1;                             ///< `--vtk-every M`
    std::optional<std::filesystem::path> states_directory;  ///< `--export-states DIR`
    bool export_mapped = false;                             ///< `--export-mapped`
    std::int64_t export_every = 1;                    ///< `--export-every M`: steps k with k % M == 0, and the last
    std::optional<std::filesystem::path> stats_file;  ///< `--stats FILE.csv`
    /// `--divergence-factor F`: the run has diverged when a step moves a DOF by more than F times
    /// the initial scene size (DivergenceBound); 0 turns the check off.
    double divergence_factor = 100.0;
    std::optional<std::filesystem::path> view_directory;  ///< `--view DIR`: the browser viewer (viewer.hpp)
    std::int64_t view_every = 1;                          ///< `--view-every M`: frames k with k % M == 0, and the end
    std::string view_title;                               ///< the viewer page's title (the scene's name)
    /// `--debug-step K --debug-file FILE`: after step K, write what it did (write_step_debug).
    std::optional<std::int64_t> debug_step;
    std::filesystem::path debug_file = "penalty-debug-step.txt";
    /// Whether the progress callback may change the states between steps (SofaPython3
    /// controllers). Then every state is checked after every step (step 3 above). Otherwise a
    /// state that no step moves, one outside every ODE solver's subtree and not the output of a
    /// mapping (a static obstacle: StateRecord::mapped and in_solver_subtree both false), is
    /// checked after the first step only: a static floor of 10⁵ points costs nothing per step.
    bool states_change_between_steps = false;
};

/// The divergence criterion of run_scene, besides non-finite values. L is the diagonal of the
/// bounding box of every state's positions at the start of the run (rigid frames: their centres;
/// for a box of zero size, max(1, |c|) with c its centre). A step that moves some DOF by more than
/// F·L is a divergence (exit 3). A simulation that resolves its contacts moves a body by a small
/// fraction of the scene per step (contact detection needs less than the alarm distance); F = 100
/// catches a body ejected by an unstable explicit step or dropped through the floor by a huge dt
/// at the step it happens, and never a long, legitimate free fall (its step length grows as g·t·dt).
/// Second rule, energy: with E = kinetic + potential energy (gravity, springs, FEM, contacts) and
/// E_ref = kinetic₀ + |stored₀| + Σ m·|g|·h (the energy of dropping every moving body through the
/// scene's height h: Scene::gravity_energy_scale), a step after which E − E₀ > 10·F·E_ref, or
/// after which E grew in that one step by more than F times E_ref plus the kinetic and stored
/// energy the scene held before it, is a divergence (from the second step
/// on: the force fields report their stored energy once the first step has evaluated them):
/// energy created from nothing, as by an unstable explicit contact that throws a ball out with
/// 10⁵ times its energy while each step stays short. A static obstacle's mass (it cannot fall)
/// is not part of E_ref. A scene with E_ref = 0 (at rest, no gravity, nothing stored) has no
/// energy rule.
class DivergenceBound {
public:
    /// Records L and the positions of the scene's states; factor 0 turns the check off.
    DivergenceBound(const Scene& scene, double factor);
    /// Compares with the positions of the previous call (or of construction), then records the
    /// current ones. Throws output::NonFiniteValueError naming the step, the state, the DOF and
    /// the distance moved. `static_states`: false skips the states no step moves (outside every
    /// solver's subtree and not mapped; see RunOptions::states_change_between_steps).
    void check(const Scene& scene, std::int64_t step, double time, bool static_states = true);
    [[nodiscard]] double scene_size() const { return size_; }

private:
    /// Calls f(record, dof, position) for every DOF of every state (rigid frames: centres).
    template <class F>
    static void for_each_position(const Scene& scene, F&& f);
    double factor_;
    double size_ = 0.0;
    std::vector<Vec3> previous_;  ///< every DOF's position after the last checked step
    /// The energy rules (docs/reliability.md): E − E₀ > 10·F·E_ref, or, in one step,
    /// E − E_previous > F·(E_ref + kinetic_previous + |stored_previous|).
    void check_energy(const Scene& scene, std::int64_t step, double time);
    double initial_energy_ = 0.0;       ///< E₀ (J)
    double energy_scale_ = 0.0;         ///< E_ref (J)
    double previous_energy_ = 0.0;      ///< E after the last checked step (J)
    double previous_content_ = 0.0;     ///< kinetic + |stored| energy after the last checked step (J)
    bool stored_energy_known_ = false;  ///< the force fields' energy at the start is read at the first check
};

/// Totals of a run.
struct RunSummary {
    std::int64_t steps = 0;
    double dt = 0.0;                 ///< s
    double simulated_time = 0.0;     ///< s
    double wall_seconds = 0.0;       ///< whole loop, outputs included
    double detection_seconds = 0.0;  ///< Σ over steps
    double response_seconds = 0.0;
    double solve_seconds = 0.0;
    double output_seconds = 0.0;
    double mean_contacts = 0.0;  ///< contacts per step (after the step's collision)
    std::size_t max_contacts = 0;
    double max_penetration = 0.0;     ///< m, over the run
    double kinetic_energy = 0.0;      ///< J, at the end
    double contact_energy = 0.0;      ///< J, stored in the contact springs at the end
    double dissipated_energy = 0.0;   ///< J, by contact damping/friction (cumulative, live pairs)
    bool cg = false;                  ///< the scene has an implicit solver
    double mean_cg_iterations = 0.0;  ///< per step, all implicit solvers
    int max_cg_iterations = 0;
    std::int64_t cg_limit_steps = 0;      ///< steps where a linear solve hit its iteration limit
    bool newton = false;                  ///< a solver runs Newton iterations
    double mean_newton_iterations = 0.0;  ///< per step
    int max_newton_iterations = 0;
    std::int64_t newton_unconverged_steps = 0;  ///< steps where Newton stopped on newtonIterations
    /// The tunnelling guard (beyond SOFA, docs/no-tunnelling.md), when the scene has one.
    struct Tunnelling {
        std::string mode;                 ///< "" without a guard
        std::int64_t crossings = 0;       ///< kept in the accepted motion, over the run
        std::int64_t crossing_steps = 0;  ///< steps with a kept crossing
        std::int64_t prevented = 0;       ///< found by undone solves
        std::int64_t undone_solves = 0;
        std::int64_t extra_solves = 0;  ///< Σ (solves − 1): the steps' substeps
        int deepest_halving = 0;        ///< the shortest solve was dt / 2^this
        double max_depth = 0.0;         ///< m, of the kept crossings
        std::string first_crossing;     ///< "step k: Crossing::describe()" of the first kept one
        std::int64_t stiffened_contacts = 0;
        double max_stiffening = 1.0;
        double stiffening_energy = 0.0;  ///< J, cumulative
        double guard_seconds = 0.0;      ///< Σ over steps
    } tunnelling;
    std::vector<std::filesystem::path> state_files;  ///< the files written by --export-states
    std::vector<int> values_per_dof;                 ///< per state file (3 Vec3, 7 Rigid3)
};

/// Called after each step with (steps done, steps total, summary so far) — the progress bar.
using ProgressCallback = std::function<void(std::int64_t, std::int64_t, const RunSummary&)>;

/// Runs `options.steps` steps. Throws std::runtime_error on divergence or I/O failure and
/// std::invalid_argument for invalid options (steps < 0, every < 1).
RunSummary run_scene(Scene& scene, const RunOptions& options, const ProgressCallback& progress = {});

/// The debug export of one step (`penalty run --debug-step K`), written right after step k
/// (which started at time t_start and detected contacts with the positions at t_start). Plain
/// text, one record per line, numbers with 17 significant digits, sections:
///   # header: scene, step, t_start, dt
///   contacts: per live contact pair "pair <model 1>-<model 2> (<n> contacts)", then per contact
///     "contact <i> elements <e1> <e2> point1 <x y z> point2 <x y z> normal <x y z> distance <d>
///      penetration <pen> stiffness <ks> force <f_n>" (points: the contact points at the end of the
///     step's collision, i.e. mapped from the positions at t_start; penetration and force from the
///     last force evaluation of the step)
///   solves: per implicit solver "solve <node path> linear solve <j>: iterations <n> end <cond>
///     residual <|r|/|b|>"
///   forces: per state (every MechanicalObject of the scene, depth first) its force vector as the
///     step's solver computed it at t_start, "force <state> <dof> <fx fy fz>" (Rigid3: 6 values).
[[nodiscard]] std::string step_debug_text(const Scene& scene, std::int64_t step, double t_start);

/// The summary as printed at the end of `penalty run` (several lines).
[[nodiscard]] std::string format_summary(const RunSummary& summary);
/// Its tunnelling guard's lines (docs/no-tunnelling.md).
[[nodiscard]] std::string format_tunnelling_summary(const RunSummary& summary);

/// The summary as a JSON object (`penalty run --summary-json FILE`; Python's Scene.run returns it
/// as a dict): every field of RunSummary under its name (state_files as strings, non-finite
/// numbers as null; values_per_dof left out), and "text", format_summary's text.
[[nodiscard]] std::string summary_json(const RunSummary& summary);

/// SOFA's reference file names for the exported states of a scene: for state file
/// `<k>_<name>_mstate.txt` of scene `S.scn`, `<reference_dir>/S.scn.reference_<k>_<name>_mstate.txt`.
[[nodiscard]] std::vector<std::filesystem::path> reference_files(const std::filesystem::path& reference_dir,
                                                                 const std::filesystem::path& scene_file,
                                                                 const std::vector<std::filesystem::path>& state_files);

}  // namespace penalty::scene
