// Simulation::step, stage by stage: detect → respond → solve → map back → end of step. The data
// between the stages is the graph's states (positions and velocities at the end of the previous
// step, contact force fields and contact-point states after the response, forces and velocities
// after the solve).
#include "penalty/simulation/ode_solver.hpp"
#include "simulation_internal.hpp"

#include <tbb/global_control.h>
#include <tbb/task_group.h>

#include <optional>
#include <stdexcept>

namespace penalty {

using detail::for_each_node;

void Simulation::step() {
    if (!initialized_) init();
    const double dt = root_.dt();
    if (step_driver_ != nullptr) {
        if (collision_steps_ != 1 || integration_steps_ != 1)
            throw std::logic_error(
                "Simulation::step: a step driver (the tunnelling guard) runs single steps, not a "
                "MultiStepAnimationLoop's");
        step_driver_->run_step(*this, dt);
        return;
    }
    if (collision_steps_ == 1 && integration_steps_ == 1) {
        detect_contacts();
        respond_to_contacts();
        integrate(dt);
        time_ += dt;
        return;
    }
    // MultiStepAnimationLoop::step: stepDt = dt / (ncollis·ninteg); the time after the
    // integration i of each collision step is start + (i + 1)·stepDt.
    const double start = time_;
    const double step_dt = dt / (collision_steps_ * integration_steps_);
    for (int c = 0; c < collision_steps_; ++c) {
        detect_contacts();
        respond_to_contacts();
        for (int i = 0; i < integration_steps_; ++i) {
            integrate(step_dt);
            time_ = start + (i + 1) * step_dt;
        }
    }
    if (!sofa_multi_step_time_) time_ = start + dt;
}

void Simulation::integrate(double dt) {
    solve(dt);
    map_back();
    clear_applied_external_forces();
}

void Simulation::detect_contacts() {
    // at the positions and velocities of the end of the previous step; a detection writes only
    // its collision models (SOFA's Triangle–Triangle normals), which no other stage's reads
    for (ContactStage* stage : contact_stages_) stage->detect();
}

void Simulation::respond_to_contacts() {
    // contact force fields and contact-point states into the graph (its structure version moves
    // when a pair comes or goes, which rebuilds the solve plan and the solvers' systems)
    for (ContactStage* stage : contact_stages_) stage->respond();
}

void Simulation::solve(double dt) {
    // set_threads(n > 0): the solve's tasks (concurrent solvers, a product's chains) in an arena of
    // n threads; 0: TBB's default arena
    if (threads_ > 0) {
        if (!arena_) arena_ = std::make_unique<ThreadArena>(threads_);
        arena_->arena.execute([&] { solve_in_arena(dt); });
        return;
    }
    solve_in_arena(dt);
}

void Simulation::solve_in_arena(double dt) {
    const bool concurrent = threads_ != 1 &&
                            tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) > 1 &&
                            (arena_ ? arena_->arena.max_concurrency() : tbb::this_task_arena::max_concurrency()) > 1;
    // When the graph's structure changed, map_back's plan (which reads the structure only) is
    // built on a TBB thread while this one builds the solve plan and the solvers' systems, if
    // the last plan had waves worth tasks (a pile's contact points: a small scene's task would
    // cost more than its build).
    std::optional<tbb::task_group> map_back_build;
    if (concurrent && arena_ && !arena_->map_back_plan.current(root_) &&
        arena_->map_back_plan.steps() >= detail::kMinStepsForConcurrentMapBack) {
        ++concurrent_map_back_builds_;
        map_back_build.emplace();
        map_back_build->run([this] { arena_->map_back_plan.update(root_); });
    }
    const std::vector<SolveAction>* planned = nullptr;
    try {
        planned = &solve_plan();
    } catch (...) {
        if (map_back_build) map_back_build->wait();
        throw;
    }
    if (map_back_build) map_back_build->wait();
    const std::vector<SolveAction>& plan = *planned;
    for (std::size_t i = 0; i < plan.size(); i = plan[i].run_end) {
        if (concurrent && run_concurrently(plan, i)) {
            solve_concurrently(plan, i, plan[i].run_end, dt);
        } else {
            for (std::size_t k = i; k < plan[i].run_end; ++k) run_action(plan[k], dt);
        }
    }
}

void Simulation::map_back() {
    // SOFA's MechanicalProjectPositionAndVelocityVisitor and the propagation of positions and
    // velocities, node by node depth first; with more than one thread, independent mappings at
    // once (map_back_plan.hpp: the same bits)
    const bool one_thread =
        threads_ == 1 || tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) < 2;
    if (one_thread) {
        for_each_node(root_, [](Node& n) {
            for (const auto& c : n.constraints()) {
                c->project_position();
                c->project_velocity();
            }
            if (n.mapping()) {
                n.mapping()->apply_position();
                n.mapping()->apply_velocity();
            }
        });
        return;
    }
    if (!arena_) arena_ = std::make_unique<ThreadArena>(threads_);
    ThreadArena& a = *arena_;
    a.arena.execute([&] {
        a.map_back_plan.update(root_);
        a.map_back_plan.run(a.arena.max_concurrency() > 1);
    });
}

void Simulation::clear_applied_external_forces() {
    for (BaseState* s : applied_states_) s->external_force_flat().setZero();
}

void Simulation::end_step(double dt) {
    clear_applied_external_forces();
    time_ += dt;
}

}  // namespace penalty
