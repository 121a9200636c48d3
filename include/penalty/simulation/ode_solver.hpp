#pragma once
/// @file
/// ODE solvers (spec §10.2): SOFA's EulerImplicitSolver and EulerExplicitSolver over a SubtreeSystem.

#include "penalty/core/fidelity.hpp"
#include "penalty/simulation/cg_linear_solver.hpp"
#include "penalty/simulation/subtree_system.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace penalty {

class DirectLinearSolver;  // direct_linear_solver.hpp

/// An ODE solver integrates the subtree of the node that owns it over one time step.
class OdeSolver {
public:
    virtual ~OdeSolver() = default;
    virtual void init(Node& /*node*/) {}
    virtual void solve(Node& node, double dt) = 0;
    /// Appends to `out` every state solve(node, dt) reads or writes (its subtree's states and the
    /// outside ones its force fields and mappings use, SubtreeSystem::append_states) and
    /// returns the number of scalar unknowns of its system (a measure of its work); nullopt when
    /// the solver cannot tell. Simulation::step runs solvers next to each other in the plan
    /// whose lists do not meet concurrently: each then gives the bits it gives alone.
    [[nodiscard]] virtual std::optional<std::size_t> list_touched_states(Node& /*node*/,
                                                                         std::vector<const BaseState*>& /*out*/) {
        return std::nullopt;
    }
    /// True while the solve does more than touch its listed states and must run alone, in plan
    /// order (EulerImplicitSolver: Newton, whose geometry update runs the detection between
    /// iterates). Read at every step, so it may change without a graph change.
    [[nodiscard]] virtual bool runs_in_plan_order() const { return false; }
    /// Sum the forces of computeForce, of the right-hand side's addMBKv and of the CG's products
    /// in the order of SOFA HEAD's MappingGraph (MappingGraphMechanicalOperations: force fields
    /// by component group, then the mappings' Jᵀ in reversed breadth-first order) instead of the
    /// visitors' order (on by default, kFidelityDefaults: docs/sofa-compatibility.md, "SOFA HEAD's
    /// orders").
    bool sofa_mapping_graph_order = kFidelityDefaults.sofa_head_orders;
    /// Apply the contact fields of many small contact-point states in one pass over flat arrays
    /// (SubtreeSystem's fused contact block). The same bits either way; off: every product
    /// through the objects (tests compare the two).
    bool fuse_contact_products = true;
    /// Beyond SOFA (off: SOFA's chains): the CG's dot products in fixed blocks on TBB's threads,
    /// the same bits at any thread count (SubtreeSystem::set_blocked_reductions).
    bool blocked_reductions = false;
};

/// Beyond SOFA (opt-in): Newton iterations on the backward-Euler residual
/// R(Δv) = M Δv − h f(x_n + h (v_n + Δv), v_n + Δv), each iteration re-running `update_geometry`
/// (e.g. contact detection) at the current iterate before the forces are evaluated.
struct NewtonOptions {
    bool enabled = false;
    int max_iterations = 10;
    double tolerance = 1e-10;               ///< on |R| / max(1, |R₀|)
    std::function<void()> update_geometry;  ///< called at each iterate (positions already updated)
};

/// SOFA's EulerImplicitSolver (spec §10.2). With h = dt, tr = ½ (trapezoidal) or 1:
///   b = h (f + (h·tr + rs) K v − rm M v)  (firstOrder: b = f), projected;
///   A = (1 + tr h rm) M − tr h B − tr h (tr h + rs) K  (firstOrder: M − h tr K);
///   A Δv = b by CG; v ← v + Δv (firstOrder: v ← Δv); x ← x + h v; v ← v·exp(−h·vdamping).
class EulerImplicitSolver final : public OdeSolver {
public:
    double rayleigh_stiffness = 0.0;
    double rayleigh_mass = 0.0;
    double vdamping = 0.0;
    bool first_order = false;
    bool trapezoidal_scheme = false;
    CGLinearSolver cg;
    /// A direct linear solver (SparseLDLSolver, ...) used instead of `cg` when set.
    std::shared_ptr<DirectLinearSolver> direct_solver;
    NewtonOptions newton;

    void init(Node& node) override;
    void solve(Node& node, double dt) override;
    [[nodiscard]] std::optional<std::size_t> list_touched_states(Node& node,
                                                                 std::vector<const BaseState*>& out) override;
    [[nodiscard]] bool runs_in_plan_order() const override { return newton.enabled; }
    [[nodiscard]] const CgStats& last_cg_stats() const { return last_cg_; }
    /// Every linear solve of the last solve() in order (one, or one per Newton iterate).
    [[nodiscard]] const std::vector<CgStats>& last_step_cg_solves() const { return step_cg_solves_; }
    /// CG iterations of the last solve() in all (one linear solve, or one per Newton iterate).
    [[nodiscard]] int last_step_cg_iterations() const { return step_cg_iterations_; }
    /// True if a linear solve of the last solve() stopped on its iteration limit.
    [[nodiscard]] bool last_step_cg_limit_reached() const { return step_cg_limit_reached_; }
    /// Newton (newton.enabled): residual evaluations of the last solve (iterates 0..n−1; the
    /// last one either met the tolerance or was followed by the max_iterations-th update).
    [[nodiscard]] int last_newton_iterations() const { return last_newton_iterations_; }
    /// |R| / max(1, |R₀|) at the last evaluated iterate of the last solve.
    [[nodiscard]] double last_newton_residual() const { return last_newton_residual_; }
    /// True if the last solve stopped on the tolerance (false: max_iterations reached).
    [[nodiscard]] bool last_newton_converged() const { return last_newton_converged_; }
    /// The cached system of the solver's subtree (builds() counts its rebuilds).
    [[nodiscard]] const SubtreeSystemCache& system_cache() const { return system_; }
    /// The last linear solve A·x = b of solve() (SOFA's linear system: A = m·M + b·B + k·K
    /// projected, its rhs and solution), for SofaPython3's linear system views; empty vectors and
    /// factors 0 before the first step and after a Newton step (its iterates' systems are not kept).
    struct LinearSolveRecord {
        double m = 0.0, b = 0.0, k = 0.0;
    };
    [[nodiscard]] const LinearSolveRecord& last_linear_solve() const { return last_solve_; }
    [[nodiscard]] const Eigen::VectorXd& last_rhs() const { return b_; }
    [[nodiscard]] const Eigen::VectorXd& last_solution() const { return x_; }

private:
    void solve_newton(SubtreeSystem& system, double dt);
    LinearSolveRecord last_solve_;
    SubtreeSystemCache system_;
    Eigen::VectorXd f_, v_, b_, x_;  ///< force, velocity, right-hand side, CG solution (kept)
    CgStats last_cg_;
    void record_cg(const CgStats& stats);
    int step_cg_iterations_ = 0;
    std::vector<CgStats> step_cg_solves_;
    bool step_cg_limit_reached_ = false;
    int last_newton_iterations_ = 0;
    double last_newton_residual_ = 0.0;
    bool last_newton_converged_ = false;
};

/// SOFA's EulerExplicitSolver, symplectic: a = M⁻¹ f (projected), v ← v + h a, x ← x + h v.
class EulerExplicitSolver final : public OdeSolver {
public:
    /// Checks that every independent state of the subtree has a mass (a = M⁻¹ f needs one);
    /// std::invalid_argument naming the state otherwise.
    void init(Node& node) override;
    void solve(Node& node, double dt) override;
    [[nodiscard]] std::optional<std::size_t> list_touched_states(Node& node,
                                                                 std::vector<const BaseState*>& out) override;

private:
    SubtreeSystemCache system_;
    Eigen::VectorXd f_, a_, v_;  ///< force, acceleration, velocity (kept)
};

}  // namespace penalty
