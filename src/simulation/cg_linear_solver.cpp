#include "penalty/simulation/cg_linear_solver.hpp"

#include "flat_vector_ops.hpp"
#include "penalty/core/error.hpp"
#include "penalty/simulation/solve_error.hpp"

#include <cmath>
#include <ostream>

namespace penalty {

// ---- CG ---------------------------------------------------------------------------------------
std::string_view cg_end_condition_name(CgEndCondition condition) {
    switch (condition) {
        case CgEndCondition::none:
            return "none";
        case CgEndCondition::iterations:
            return "iterations";
        case CgEndCondition::tolerance:
            return "tolerance";
        case CgEndCondition::threshold:
            return "threshold";
        case CgEndCondition::den_zero:
            return "den=0";
        case CgEndCondition::b_zero:
            return "b=0";
    }
    return "unknown";
}

std::ostream& operator<<(std::ostream& out, CgEndCondition condition) {
    return out << cg_end_condition_name(condition);
}

void CGLinearSolver::check() const {
    if (iterations < 1) throw_invalid_argument("CGLinearSolver: iterations must be >= 1, got ", iterations);
    if (!std::isfinite(tolerance) || tolerance < 0)
        throw_invalid_argument("CGLinearSolver: tolerance must be >= 0, got ", tolerance);
    if (!std::isfinite(threshold) || threshold < 0)
        throw_invalid_argument("CGLinearSolver: threshold must be >= 0, got ", threshold);
}

namespace {
using detail::sequential_dot;

/// CgSystem over an operator and a dot product: the steps one after the other.
class FunctionCgSystem final : public CgSystem {
public:
    FunctionCgSystem(const CGLinearSolver::Operator& a, const CGLinearSolver::Dot& dot) : a_(a), dot_(dot) {}
    void apply(const Eigen::VectorXd& p, Eigen::VectorXd& q) override { a_(p, q); }
    [[nodiscard]] double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const override {
        return dot_ ? dot_(a, b) : sequential_dot(a, b);
    }

private:
    const CGLinearSolver::Operator& a_;
    const CGLinearSolver::Dot& dot_;
};

}  // namespace

double CgSystem::direction_and_product(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                       Eigen::VectorXd& q) {
    if (first) p = r;
    else p = r + beta * p;
    apply(p, q);
    return dot(p, q);
}

double CgSystem::update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
                                     Eigen::VectorXd& x, Eigen::VectorXd& r) {
    x += alpha * p;
    r -= alpha * q;
    return dot(r, r);
}

CgStats CGLinearSolver::solve(const Operator& a, const Eigen::VectorXd& b, Eigen::VectorXd& x, const Dot& dot_product) {
    FunctionCgSystem system(a, dot_product);
    return solve(system, b, x);
}

CgStats CGLinearSolver::solve(CgSystem& system, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    check();
    CgStats stats;
    const bool first_solve = solve_count_ == 0;
    ++solve_count_;
    x.setZero(b.size());
    const double norm_b = std::sqrt(system.dot(b, b));  // SOFA: MultiVec::norm() = sqrt(v_dot(b, b))
    if (!std::isfinite(norm_b))
        throw NonFiniteSolveError("CGLinearSolver: the right-hand side is not finite (|b| overflows)", nullptr, nullptr,
                                  nullptr);
    if (norm_b == 0.0) {
        stats.end_condition = CgEndCondition::b_zero;
        return stats;
    }
    Eigen::VectorXd& r = r_;
    Eigen::VectorXd& p = p_;
    Eigen::VectorXd& q = q_;
    r = b;
    p.resize(b.size());
    q.resize(b.size());
    // ρ = r·r of the iteration to come: computed here for the first, by the update of r after
    // (update_and_residual, which also computes it once after the last iteration, unused).
    double rho = system.dot(r, r);
    double rho_prev = 0.0;
    stats.end_condition = CgEndCondition::iterations;
    for (int k = 1; k <= iterations; ++k) {
        stats.iterations = k;
        const double err = std::sqrt(rho) / norm_b;
        stats.error = err;
        if (err <= tolerance && !(k == 1 && first_solve)) {
            stats.end_condition = CgEndCondition::tolerance;
            break;
        }
        // p = r (k = 1) or r + (ρ/ρ_prev)·p; q = A·p; den = p·q
        const double den = system.direction_and_product(r, k == 1 ? 0.0 : rho / rho_prev, k == 1, p, q);
        if (den == 0.0) {
            stats.end_condition = CgEndCondition::den_zero;
            break;
        }
        if (std::abs(den) <= threshold && !(k == 1 && first_solve)) {
            stats.end_condition = CgEndCondition::threshold;
            break;
        }
        const double alpha = rho / den;
        rho_prev = rho;
        rho = system.update_and_residual(alpha, p, q, x, r);  // x += α·p, r −= α·q
    }
    if (!x.allFinite())
        throw NonFiniteSolveError(
            "CGLinearSolver: the solution is not finite (singular or indefinite system, or an overflow)", nullptr,
            nullptr, nullptr);
    return stats;
}

}  // namespace penalty
