#pragma once
/// @file
/// SOFA's CGLinearSolver (spec §10.3), matrix-free, on a CgSystem.

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string_view>

namespace penalty {

/// Why a CG solve stopped (SOFA's CGLinearSolver end conditions).
enum class CgEndCondition : std::uint8_t {
    none,        ///< no solve yet
    iterations,  ///< the iteration limit was reached
    tolerance,   ///< |r|/|b| <= tolerance
    threshold,   ///< |pᵀAp| <= threshold
    den_zero,    ///< pᵀAp == 0
    b_zero,      ///< |b| == 0 (x = 0, no iteration)
};

/// The name printed for an end condition: "none", "iterations", "tolerance", "threshold",
/// "den=0", "b=0" (SOFA's log words).
[[nodiscard]] std::string_view cg_end_condition_name(CgEndCondition condition);
/// Writes cg_end_condition_name(condition).
std::ostream& operator<<(std::ostream& out, CgEndCondition condition);

/// Result of one CG solve.
struct CgStats {
    int iterations = 0;  ///< iterations started (SOFA's nb_iter)
    CgEndCondition end_condition = CgEndCondition::none;
    double error = 0.0;  ///< last |r|/|b| evaluated
};

/// A linear system A·x = b for CGLinearSolver: its product, its dot product, and the two vector
/// steps of a CG iteration, which a system may run as one pass over its vectors each. An
/// override must give the defaults' bits: the same IEEE operations on the same operands, each
/// sum in the same order.
class CgSystem {
public:
    virtual ~CgSystem() = default;
    /// q = A·p.
    virtual void apply(const Eigen::VectorXd& p, Eigen::VectorXd& q) = 0;
    /// aᵀb in the system's order of summation.
    [[nodiscard]] virtual double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const = 0;
    /// The new direction and its product: p = r (first) or p = r + β·p, then q = A·p; returns pᵀq.
    virtual double direction_and_product(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                         Eigen::VectorXd& q);
    /// The update: x += α·p, r −= α·q; returns rᵀr.
    virtual double update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
                                       Eigen::VectorXd& x, Eigen::VectorXd& r);
};

/// SOFA's CGLinearSolver (GraphScattered, matrix-free), exact stopping rules: x₀ = 0, r = b; for
/// k = 1..iterations: ρ = r·r, err = √ρ/|b|; stop if err <= tolerance; p = r (k = 1) or
/// r + (ρ/ρ_prev) p; q = A p; den = p·q; stop if den == 0; stop if |den| <= threshold; x += α p,
/// r −= α q with α = ρ/den. The two "stop" tests at k = 1 are skipped (SOFA only warns) during the
/// very first solve of this instance. If |b| = 0, x = 0.
class CGLinearSolver {
public:
    using Operator = std::function<void(const Eigen::VectorXd& p, Eigen::VectorXd& q)>;
    /// Dot product of two flat vectors. SOFA sums in a fixed order (SubtreeSystem::dot); the
    /// rounding of ρ, pᵀq and |b| depends on it, so the solve uses the system's order.
    using Dot = std::function<double(const Eigen::VectorXd& a, const Eigen::VectorXd& b)>;
    int iterations = 25;
    double tolerance = 1e-5;
    double threshold = 1e-5;

    /// Validates the parameters (std::invalid_argument on iterations < 1 or negative/NaN values).
    void check() const;
    /// `dot` empty: the plain sequential sum Σ aᵢbᵢ.
    CgStats solve(const Operator& a, const Eigen::VectorXd& b, Eigen::VectorXd& x, const Dot& dot = {});
    /// The same iterations on `system`, through its fused steps (the same bits as its product and
    /// dot applied one after the other).
    CgStats solve(CgSystem& system, const Eigen::VectorXd& b, Eigen::VectorXd& x);
    [[nodiscard]] int solve_count() const { return solve_count_; }

private:
    int solve_count_ = 0;
    Eigen::VectorXd r_, p_, q_;  ///< residual, direction, A·p (kept: no allocation per solve)
};

}  // namespace penalty
