#pragma once
/// @file
/// The simulation: the scene graph's root and the step (DefaultAnimationLoop).

#include "penalty/core/pointer_index.hpp"
#include "penalty/simulation/node.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace penalty {

/// Most threads a Simulation (and a ContactPipeline's detection) accepts: 1024 (TBB cannot make
/// an arena above 65,536 and reserves memory per slot; no machine this runs on has more cores).
inline constexpr int kMaxThreads = 1024;

/// Fewest scalar unknowns a solver needs for Simulation::step to give it its own task: waking a
/// TBB worker costs a few µs, more than a step of CompositeCollisionPipeline's two 6-unknown rigid
/// solvers (their solve took 30 % longer on two threads), while RegularGridSpringForceField's four
/// 180-unknown grids solve 1.4× faster (docs/performance.md, "Independent solvers in parallel").
inline constexpr std::size_t kMinUnknownsPerConcurrentSolve = 96;

/// What brings contacts into the graph at the start of each step (ContactPipeline): detect()
/// finds the contacts at the positions of the end of the previous step, respond() turns them into
/// contact force fields and contact-point states in the graph.
class ContactStage {
public:
    virtual ~ContactStage() = default;
    virtual void detect() = 0;
    virtual void respond() = 0;
};

class Simulation;

/// Beyond SOFA, opt-in: runs the stages of a step in place of step()'s fixed sequence (the
/// tunnelling guard, tunnelling_guard.hpp: it may redo the solve in substeps). It calls the
/// simulation's public stages; without a driver step() runs each stage once.
class StepDriver {
public:
    virtual ~StepDriver() = default;
    /// One step of `dt` (the root node's dt): the stages of Simulation::step, ending with end_step.
    virtual void run_step(Simulation& simulation, double dt) = 0;
};

/// DefaultAnimationLoop (spec §2): owns the root node and runs the step, stage by stage
/// (src/simulation/simulation_step.cpp).
class Simulation {
public:
    Simulation();
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;
    [[nodiscard]] Node& root() { return root_; }
    /// Initialises every state, mapping, mass, force field, constraint and solver (top-down).
    void init();
    /// One step, in named stages: detect_contacts (every contact stage's detection, at the
    /// positions of the end of the previous step) → respond_to_contacts (their contact force
    /// fields and contact-point states) → solve (explicit interaction force fields of nodes
    /// without solver, then the solver subtrees) → map_back (project velocities, propagate to
    /// mapped states) → the applied external forces cleared, time += dt. With
    /// set_multi_step, SOFA's MultiStepAnimationLoop: the contact stages and integrations repeated.
    void step();
    [[nodiscard]] double time() const { return time_; }
    /// Sets the simulated time (s): a scene built again after init continues at the time it had
    /// (Scene::apply_pending_writes), SofaPython3's `root.time.value = t`.
    void set_time(double t) { time_ = t; }
    /// Threads of the solve phase (0: TBB's default, the default; 1: every action in plan order
    /// on the calling thread): solvers next to each other in the plan whose states do not meet
    /// (OdeSolver::list_touched_states) run concurrently, one task per solver, when two of them
    /// have at least kMinUnknownsPerConcurrentSolve unknowns. The results are
    /// the same bits for any count (each solve is sequential inside and reads nothing another
    /// writes), and an error is the one the first failing solver in plan order raised.
    /// std::invalid_argument outside [0, kMaxThreads].
    void set_threads(int threads);
    [[nodiscard]] int threads() const { return threads_; }
    /// The runs of solvers that step() gives a task each when it has more than one thread, from
    /// the current graph: each the solver nodes of one run, in plan order.
    [[nodiscard]] std::vector<std::vector<const Node*>> concurrent_solver_runs();
    /// The explicit force fields that step() runs as tasks when it has more than one thread:
    /// those of the runs of at least kMinExplicitFieldsPerConcurrentRun fields whose states do not
    /// meet (run_action of each writes only its own states: the same bits).
    [[nodiscard]] std::size_t concurrent_explicit_fields();
    /// The force fields step() never evaluates, from the current graph: the plain ones (not
    /// BaseForceField::sofa_interaction) of nodes with no ODE solver on their path from the root,
    /// which SOFA's SolveVisitor skips too. Depth first.
    [[nodiscard]] const std::vector<const BaseForceField*>& unevaluated_force_fields();
    /// Fewest explicit force fields in a run for tasks, and the fields a task takes.
    static constexpr std::size_t kMinExplicitFieldsPerConcurrentRun = 64;
    static constexpr std::size_t kExplicitFieldsPerTask = 16;
    /// Steps so far whose map-back plan was built on a TBB thread beside the solve plan (the
    /// graph's structure had changed and the step has several threads).
    [[nodiscard]] std::size_t concurrent_map_back_builds() const { return concurrent_map_back_builds_; }
    /// Registers a contact stage (at most once): step() runs the stages' detect() then their
    /// respond(), each in registration order. The stage unregisters itself before it dies.
    void add_contact_stage(ContactStage& stage);
    /// Unregisters `stage` (nothing if it is not registered).
    void remove_contact_stage(const ContactStage& stage);
    [[nodiscard]] const std::vector<ContactStage*>& contact_stages() const { return contact_stages_; }
    /// Sets the step's driver (nullptr: none, SOFA's step). Not owned; it unsets itself before
    /// it dies. A driver runs single steps: step() throws std::logic_error with one set on a
    /// multi-step loop.
    void set_step_driver(StepDriver* driver) { step_driver_ = driver; }
    [[nodiscard]] StepDriver* step_driver() const { return step_driver_; }
    /// SOFA's MultiStepAnimationLoop (MultiStepAnimationLoop::step): a step runs collision_steps
    /// times the contact stages, each followed by integration_steps integrations of
    /// dt / (collision_steps·integration_steps); (1, 1), the default, is DefaultAnimationLoop.
    /// SOFA sets the time of each integration from the step's start, so a step advances it by
    /// dt / collision_steps only (sofa_time, the default); false: by dt. std::invalid_argument
    /// for counts outside [1, 10⁶].
    void set_multi_step(int collision_steps, int integration_steps, bool sofa_time = true);
    [[nodiscard]] int collision_steps() const { return collision_steps_; }
    [[nodiscard]] int integration_steps() const { return integration_steps_; }

    // ---- the stages of step() (simulation_step.cpp), public for a StepDriver -------------------
    void detect_contacts();
    void respond_to_contacts();
    void solve(double dt);
    void map_back();
    void clear_applied_external_forces();
    /// The end of a single step: the applied external forces cleared, the time advanced by dt.
    void end_step(double dt);
    /// One integration of dt (no contact stage, no time change): solve, map_back, the applied
    /// external forces cleared.
    void integrate(double dt);

private:
    void solve_in_arena(double dt);  ///< solve()'s body, in the simulation's arena when it has one
    std::vector<ContactStage*> contact_stages_;
    StepDriver* step_driver_ = nullptr;
    /// One entry of a step's solve phase, in depth-first order: a solver node (integrates its
    /// subtree) or an explicit force field with its states.
    struct SolveAction {
        Node* solver_node = nullptr;
        BaseForceField* explicit_field = nullptr;
        ForceFieldStates states;  ///< of explicit_field
        /// The action after this one's run: a run is the solver actions (or the explicit force
        /// fields) from this one whose touched states do not meet (one action when this one
        /// cannot run with others), found with the plan; set on the first action of each run.
        std::size_t run_end = 0;
        /// two solvers of the run have kMinUnknownsPerConcurrentSolve unknowns, or the run has
        /// kMinExplicitFieldsPerConcurrentRun explicit force fields
        bool run_worth_tasks = false;
    };
    /// plan[begin] starts a run worth tasks and none of its solvers runs_in_plan_order now.
    [[nodiscard]] bool run_concurrently(const std::vector<SolveAction>& plan, std::size_t begin) const;
    /// The solve phase's actions and their runs, rebuilt when the graph's structure changes
    /// (which is also all that changes the states a solver touches).
    const std::vector<SolveAction>& solve_plan();
    void plan_node(Node& node);
    /// Simulation::init's projection of positions and velocities (simulation.cpp).
    static void project_initial_state(Node& node, bool moved_above);
    void run_action(const SolveAction& action, double dt);
    /// Sets plan_[begin].run_end and run_worth_tasks.
    void find_run(std::size_t begin);
    /// The same for an explicit force field: the explicit fields from it whose states (and read
    /// states) do not meet, worth tasks from kMinExplicitFieldsPerConcurrentRun fields.
    void find_explicit_run(std::size_t begin);
    /// plan[begin, end): solver actions whose touched states do not meet, concurrently.
    void solve_concurrently(const std::vector<SolveAction>& plan, std::size_t begin, std::size_t end, double dt);
    struct ThreadArena;
    Node root_;
    int threads_ = 0;
    std::unique_ptr<ThreadArena> arena_;  ///< made at the first concurrent solve
    std::vector<SolveAction> plan_;
    std::vector<const BaseForceField*> unevaluated_;  ///< made with plan_ (unevaluated_force_fields)
    std::size_t concurrent_map_back_builds_ = 0;
    PointerIndex<BaseState> explicit_run_states_;          ///< find_explicit_run's scratch
    std::vector<const BaseState*> explicit_field_states_;  ///< find_explicit_run's scratch
    /// The states whose external force a step applies, cleared after each step (found with the
    /// plan): those of a solver's subtree, the outputs of mappings and the states of explicit
    /// force fields. The others (static obstacles) are never applied nor cleared: a floor of
    /// 10⁵ points costs no pass over its memory per step.
    std::vector<BaseState*> applied_states_;
    PointerIndex<BaseState> applied_index_;  ///< solve_plan's scratch: the states of applied_states_
    std::optional<std::uint64_t> plan_version_;
    double time_ = 0.0;
    bool initialized_ = false;
    int collision_steps_ = 1;
    int integration_steps_ = 1;
    bool sofa_multi_step_time_ = true;
};

}  // namespace penalty
