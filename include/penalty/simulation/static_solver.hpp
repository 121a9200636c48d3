#pragma once
/// @file
/// SOFA's StaticSolver with its NewtonRaphsonSolver: each step moves the positions toward the
/// equilibrium f(x) = 0 by Newton iterations on the residual r(x) = P·f(x), with a backtracking
/// line search; velocities are left as they are.

#include "penalty/simulation/direct_linear_solver.hpp"
#include "penalty/simulation/solver.hpp"

#include <string_view>
#include <vector>

namespace penalty {

/// SOFA's NewtonRaphsonSolver data (its defaults). A threshold of 0 turns its criterion off.
struct NewtonRaphsonParameters {
    int max_iterations = 1;                     ///< maxNbIterationsNewton
    double relative_successive = 1e-5;          ///< relativeSuccessiveStoppingThreshold: |r_k| < t·|r_{k−1}|
    double relative_initial = 1e-5;             ///< relativeInitialStoppingThreshold: |r_k| < t·|r_0|
    double absolute_residual = 1e-5;            ///< absoluteResidualStoppingThreshold: |r_k| < t (N)
    double relative_estimate_difference = 0.0;  ///< relativeEstimateDifferenceThreshold: |dx| < t·|x|
    double absolute_estimate_difference = 0.0;  ///< absoluteEstimateDifferenceThreshold: |dx| < t (m)
    int max_line_search_iterations = 1;         ///< maxNbIterationsLineSearch (at least 1 is run)
    double line_search_coefficient = 0.5;       ///< lineSearchCoefficient: α ← c·α
    /// std::invalid_argument naming the first bad value (negative or non-finite thresholds,
    /// iteration counts below 0, a coefficient outside (0, 1]).
    void check() const;
};

/// SOFA's NewtonStatus.
enum class NewtonStatus : std::uint8_t {
    undefined,
    running,
    converged_equilibrium,
    diverged_line_search,
    diverged_max_iterations,
    converged_residual_successive_ratio,
    converged_residual_initial_ratio,
    converged_absolute_residual,
    converged_relative_estimate_difference,
    converged_absolute_estimate_difference,
};
/// SOFA's name of a status ("ConvergedEquilibrium", ...).
[[nodiscard]] std::string_view newton_status_name(NewtonStatus status);

/// StaticSolver::solve → NewtonRaphsonSolver::solve with StaticResidualFunction:
///   r = P·f(x) (computeForce, projectResponse), |r|² summed as SOFA's v_dot;
///   stop at once if |r| ≤ absolute_residual (ConvergedEquilibrium); else per Newton iteration:
///   A = −K (m = 0, b = 0, k = −1, projected), A·dx = r by the linear solver;
///   line search α = 1, c, c², ...: x ← x + (α − α_prev)·dx, propagated through the mappings,
///   r evaluated, accepted when |r|² < |r_prev|² (after max_line_search_iterations failures with
///   more than one allowed, back to α = 1);
///   then the criteria in SOFA's order: relative successive, relative initial, absolute, and
///   (when set) relative and absolute estimate difference on |dx|.
class StaticSolver final : public OdeSolver {
public:
    NewtonRaphsonParameters newton;
    LinearSolverChoice linear;

    void init(Node& node) override;
    void solve(Node& node, double dt) override;
    [[nodiscard]] std::optional<std::size_t> list_touched_states(Node& node,
                                                                 std::vector<const BaseState*>& out) override;

    /// The last solve: its status, Newton iterations, squared residual norms (initial then one per
    /// iteration, SOFA's residualGraph) and linear solves' CG statistics.
    [[nodiscard]] NewtonStatus status() const { return status_; }
    [[nodiscard]] int iterations() const { return iterations_; }
    [[nodiscard]] const std::vector<double>& squared_residuals() const { return squared_residuals_; }
    [[nodiscard]] const std::vector<CgStats>& linear_solves() const { return linear_solves_; }

private:
    SubtreeSystemCache system_;
    Eigen::VectorXd f_, dx_;
    NewtonStatus status_ = NewtonStatus::undefined;
    int iterations_ = 0;
    std::vector<double> squared_residuals_;
    std::vector<CgStats> linear_solves_;
};

/// Σ x·x over the independent states' positions (Vec3: 3 numbers, Rigid3: centre and quaternion's
/// 7), SOFA's MultiVecCoord dot (the relative estimate-difference criterion's |x|²).
[[nodiscard]] double squared_positions_norm(const SubtreeSystem& system);

}  // namespace penalty
