// Simulation's solve plan: the step's solve actions in depth-first order, the runs of solvers
// that may run concurrently, and the concurrent solve of such a run.
#include "penalty/core/error.hpp"
#include "penalty/core/first_error.hpp"
#include "penalty/simulation/ode_solver.hpp"
#include "simulation_internal.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace penalty {

using detail::for_each_node;

void Simulation::plan_node(Node& node) {
    // The first node with an ODE solver on a path integrates its whole subtree; at a node without
    // solver, each interaction force field (SOFA's BaseInteractionForceField) is explicit, then
    // the children (SOFA's SolveVisitor::processNodeTopDown visits only the node's
    // interactionForceField list there: a plain ForceField at such a node acts on a state no
    // solver integrates and is never evaluated).
    if (node.ode_solver() != nullptr) {
        plan_.push_back({&node, nullptr, {}});
        return;
    }
    node.for_each_force_field([this](BaseForceField& ff) {
        if (ff.sofa_interaction()) plan_.push_back({nullptr, &ff, ff.states()});
        else unevaluated_.push_back(&ff);
    });
    for (const auto& child : node.children()) plan_node(*child);
}

const std::vector<Simulation::SolveAction>& Simulation::solve_plan() {
    if (plan_version_ != root_.structure_version()) {
        plan_.clear();
        unevaluated_.clear();
        plan_node(root_);
        applied_states_.clear();
        applied_index_.clear();
        const auto add = [&](BaseState* s) {
            if (s != nullptr && applied_index_.emplace(s, applied_states_.size()).second) applied_states_.push_back(s);
        };
        for (const SolveAction& a : plan_) {
            if (a.solver_node != nullptr) for_each_node(*a.solver_node, [&](Node& n) { add(n.state()); });
            for (BaseState* s : a.states) add(s);
        }
        for_each_node(root_, [&](Node& n) {
            if (n.mapping()) add(n.state());
        });
        for_each_node(root_, [&](Node& n) {
            if (n.state() != nullptr) n.state()->set_static(!applied_index_.contains(n.state()));
        });
        for (std::size_t i = 0; i < plan_.size(); i = plan_[i].run_end) {
            if (plan_[i].solver_node != nullptr) {
                find_run(i);
            } else {
                find_explicit_run(i);
            }
        }
        plan_version_ = root_.structure_version();
    }
    return plan_;
}

void Simulation::run_action(const SolveAction& action, double dt) {
    if (action.solver_node != nullptr) {
        action.solver_node->ode_solver()->solve(*action.solver_node, dt);
        return;
    }
    // Explicit: forces from the start-of-step x, v, added as external forces for the step.
    // As SOFA's SolveVisitor::fwdInteractionForceField (addForce into externalForce): each
    // contribution is added to the external force in turn, ((e + c1) + c2), not e + (c1 + c2).
    for (BaseState* s : action.states) s->force_flat() = s->external_force_flat();
    action.explicit_field->accumulate_force();
    for (BaseState* s : action.states) {
        s->external_force_flat() = s->force_flat();
        s->force_flat().setZero();
    }
}

const std::vector<const BaseForceField*>& Simulation::unevaluated_force_fields() {
    solve_plan();
    return unevaluated_;
}

void Simulation::find_run(std::size_t begin) {
    // Solvers whose touched states do not meet commute: none reads what another writes (a
    // solver's subtree states, and the scratch force and dx of the outside states it reads).
    std::vector<const BaseState*> run_states, solver_states;  // sorted
    std::size_t end = begin;
    int large = 0;  // solvers with kMinUnknownsPerConcurrentSolve unknowns or more
    for (; end < plan_.size() && plan_[end].solver_node != nullptr; ++end) {
        solver_states.clear();
        const std::optional<std::size_t> unknowns =
            plan_[end].solver_node->ode_solver()->list_touched_states(*plan_[end].solver_node, solver_states);
        if (!unknowns || plan_[end].solver_node->ode_solver()->runs_in_plan_order()) break;
        std::sort(solver_states.begin(), solver_states.end());
        bool meet = false;
        for (auto a = run_states.begin(), b = solver_states.begin();
             !meet && a != run_states.end() && b != solver_states.end();) {
            if (*a < *b) {
                ++a;
            } else if (*b < *a) {
                ++b;
            } else {
                meet = true;
            }
        }
        if (meet) break;
        if (*unknowns >= kMinUnknownsPerConcurrentSolve) ++large;
        const auto middle = run_states.insert(run_states.end(), solver_states.begin(), solver_states.end());
        std::inplace_merge(run_states.begin(), middle, run_states.end());
    }
    plan_[begin].run_end = std::max(end, begin + 1);
    plan_[begin].run_worth_tasks = large >= 2;
}

void Simulation::find_explicit_run(std::size_t begin) {
    // Explicit force fields next to each other in the plan whose states do not meet commute: each
    // writes only the force and external force of its own states (run_action) and reads nothing
    // another writes. A pile's contacts with a static obstacle are hundreds of such fields at
    // the root (SOFA's interaction force fields above every solver, §2.1).
    PointerIndex<BaseState>& met = explicit_run_states_;
    std::vector<const BaseState*>& read = explicit_field_states_;
    met.clear();
    std::size_t end = begin;
    for (; end < plan_.size() && plan_[end].solver_node == nullptr; ++end) {
        read.clear();
        for (BaseState* s : plan_[end].states) read.push_back(s);
        plan_[end].explicit_field->list_read_states(read);
        const bool meets = std::any_of(read.begin(), read.end(), [&](const BaseState* s) { return met.contains(s); });
        if (meets) break;
        for (const BaseState* s : read) met.emplace(s, 0);
    }
    plan_[begin].run_end = std::max(end, begin + 1);
    plan_[begin].run_worth_tasks = plan_[begin].run_end - begin >= kMinExplicitFieldsPerConcurrentRun;
}

bool Simulation::run_concurrently(const std::vector<SolveAction>& plan, std::size_t begin) const {
    if (!plan[begin].run_worth_tasks) return false;
    if (plan[begin].solver_node == nullptr) return true;  // explicit force fields
    for (std::size_t k = begin; k < plan[begin].run_end; ++k)
        if (plan[k].solver_node->ode_solver()->runs_in_plan_order()) return false;  // Newton turned on since
    return true;
}

std::vector<std::vector<const Node*>> Simulation::concurrent_solver_runs() {
    std::vector<std::vector<const Node*>> runs;
    const std::vector<SolveAction>& plan = solve_plan();
    for (std::size_t i = 0; i < plan.size(); i = plan[i].run_end) {
        if (plan[i].solver_node == nullptr || !run_concurrently(plan, i)) continue;
        runs.emplace_back();
        for (std::size_t k = i; k < plan[i].run_end; ++k) runs.back().push_back(plan[k].solver_node);
    }
    return runs;
}

std::size_t Simulation::concurrent_explicit_fields() {
    std::size_t fields = 0;
    const std::vector<SolveAction>& plan = solve_plan();
    for (std::size_t i = 0; i < plan.size(); i = plan[i].run_end)
        if (plan[i].solver_node == nullptr && run_concurrently(plan, i)) fields += plan[i].run_end - i;
    return fields;
}

void Simulation::solve_concurrently(const std::vector<SolveAction>& plan, std::size_t begin, std::size_t end,
                                    double dt) {
    if (!arena_) arena_ = std::make_unique<ThreadArena>(threads_);
    FirstErrorInOrder failure;
    arena_->arena.execute([&] {
        // a task per solver; explicit force fields (a few contacts each) by groups
        const std::size_t grain = plan[begin].solver_node != nullptr ? 1 : kExplicitFieldsPerTask;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              // (every action runs: they are independent)
                              for (std::size_t i = r.begin(); i != r.end(); ++i)
                                  failure.run(i, [&] { run_action(plan[i], dt); });
                          });
    });
    // The error of the first failing solver in plan order, as a sequential run would raise it.
    failure.rethrow_if_any();
}

}  // namespace penalty
