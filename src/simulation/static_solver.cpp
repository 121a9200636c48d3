#include "penalty/simulation/static_solver.hpp"

#include <cmath>

namespace penalty {

void NewtonRaphsonParameters::check() const {
    if (max_iterations < 0)
        throw_invalid_argument("NewtonRaphsonSolver: maxNbIterationsNewton must be >= 0, got ", max_iterations);
    if (max_line_search_iterations < 0)
        throw_invalid_argument("NewtonRaphsonSolver: maxNbIterationsLineSearch must be >= 0, got ",
                               max_line_search_iterations);
    const std::pair<const char*, double> thresholds[] = {
        {"relativeSuccessiveStoppingThreshold", relative_successive},
        {"relativeInitialStoppingThreshold", relative_initial},
        {"absoluteResidualStoppingThreshold", absolute_residual},
        {"relativeEstimateDifferenceThreshold", relative_estimate_difference},
        {"absoluteEstimateDifferenceThreshold", absolute_estimate_difference},
    };
    for (const auto& [name, value] : thresholds)
        if (!std::isfinite(value) || value < 0)
            throw_invalid_argument("NewtonRaphsonSolver: ", name, " must be finite and >= 0, got ", value);
    if (!std::isfinite(line_search_coefficient) || line_search_coefficient <= 0 || line_search_coefficient > 1)
        throw_invalid_argument("NewtonRaphsonSolver: lineSearchCoefficient must be in (0, 1], got ",
                               line_search_coefficient);
}

std::string_view newton_status_name(NewtonStatus status) {
    switch (status) {
        case NewtonStatus::undefined:
            return "Undefined";
        case NewtonStatus::running:
            return "Running";
        case NewtonStatus::converged_equilibrium:
            return "ConvergedEquilibrium";
        case NewtonStatus::diverged_line_search:
            return "DivergedLineSearch";
        case NewtonStatus::diverged_max_iterations:
            return "DivergedMaxIterations";
        case NewtonStatus::converged_residual_successive_ratio:
            return "ConvergedResidualSuccessiveRatio";
        case NewtonStatus::converged_residual_initial_ratio:
            return "ConvergedResidualInitialRatio";
        case NewtonStatus::converged_absolute_residual:
            return "ConvergedAbsoluteResidual";
        case NewtonStatus::converged_relative_estimate_difference:
            return "ConvergedRelativeEstimateDifference";
        case NewtonStatus::converged_absolute_estimate_difference:
            return "ConvergedAbsoluteEstimateDifference";
    }
    return "?";
}

double squared_positions_norm(const SubtreeSystem& system) {
    double total = 0.0;
    for (BaseState* s : system.independent_states()) {
        double r = 0.0;
        if (const auto* v = dynamic_cast<const Vec3Object*>(s)) {
            for (const Vec3& x : v->position) r += x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        } else if (const auto* rigid = dynamic_cast<const Rigid3Object*>(s)) {
            for (const RigidFrame& x : rigid->position) {
                const Quat& q = x.orientation;
                r += x.center[0] * x.center[0] + x.center[1] * x.center[1] + x.center[2] * x.center[2] + q.x() * q.x() +
                     q.y() * q.y() + q.z() * q.z() + q.w() * q.w();
            }
        }
        total += r;
    }
    return total;
}

void StaticSolver::init(Node& node) {
    newton.check();
    linear.cg.check();
    (void)SubtreeSystem(node);
}

std::optional<std::size_t> StaticSolver::list_touched_states(Node& node, std::vector<const BaseState*>& out) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.append_states(out);
    return static_cast<std::size_t>(sys.size());
}

// StaticSolver::solve with NewtonRaphsonSolver::solve (StaticResidualFunction's steps).
void StaticSolver::solve(Node& node, double /*dt*/) {
    SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    squared_residuals_.clear();
    linear_solves_.clear();
    iterations_ = 0;
    status_ = NewtonStatus::running;
    // evaluateCurrentGuess: f = P·f(x); squaredNormLastEvaluation: f·f
    const auto evaluate = [&] {
        sys.compute_force(f_);
        sys.project(f_);
        return sys.dot(f_, f_);
    };
    double squared_residual = evaluate();
    squared_residuals_.push_back(squared_residual);
    const double absolute = newton.absolute_residual;
    if (absolute > 0 && squared_residual <= absolute * absolute) {
        status_ = NewtonStatus::converged_equilibrium;
        return;
    }
    const double first_squared_residual = squared_residual;
    const auto squared = [](double t) { return t * t; };
    const int line_search_iterations = std::max(newton.max_line_search_iterations, 1);
    bool converged = false;
    for (; iterations_ < newton.max_iterations; ++iterations_) {
        const double previous_squared_residual = squared_residual;
        const double squared_previous_x = newton.relative_estimate_difference > 0 ? squared_positions_norm(sys) : 0.0;
        // computeGradientFromCurrentGuess, solveLinearEquation: (−K)·dx = r
        {
            const SubtreeSystem::FixedReaders fixed_readers(sys);  // the contacts do not change in a solve
            linear_solves_.push_back(linear.solve(sys, 0.0, 0.0, -1.0, f_, dx_));
        }
        // lineSearchIteration: x += (α − α_prev)·dx, propagated; r evaluated
        double alpha = 1.0;
        double previous_alpha = 0.0;
        bool success = false;
        for (int ls = 0; ls < line_search_iterations; ++ls) {
            sys.add_to_positions(alpha - previous_alpha, dx_);
            sys.propagate_positions_and_velocities();
            squared_residual = evaluate();
            if (squared_residual < previous_squared_residual) {
                success = true;
                break;
            }
            previous_alpha = alpha;
            alpha *= newton.line_search_coefficient;
        }
        if (!success) {
            status_ = NewtonStatus::diverged_line_search;
            if (line_search_iterations > 1) {
                sys.add_to_positions(1.0 - previous_alpha, dx_);
                sys.propagate_positions_and_velocities();
                squared_residual = evaluate();
            }
        }
        squared_residuals_.push_back(squared_residual);
        const auto converged_on = [&](NewtonStatus s) {
            status_ = s;
            converged = true;
        };
        if (newton.relative_successive > 0 &&
            squared_residual < squared(newton.relative_successive) * previous_squared_residual) {
            converged_on(NewtonStatus::converged_residual_successive_ratio);
            break;
        }
        if (newton.relative_initial > 0 &&
            squared_residual < squared(newton.relative_initial) * first_squared_residual) {
            converged_on(NewtonStatus::converged_residual_initial_ratio);
            break;
        }
        if (absolute > 0 && squared_residual < squared(absolute)) {
            converged_on(NewtonStatus::converged_absolute_residual);
            break;
        }
        if (newton.relative_estimate_difference > 0 || newton.absolute_estimate_difference > 0) {
            const double squared_dx = sys.dot(dx_, dx_);
            if (newton.relative_estimate_difference > 0 && squared_previous_x > 0 &&
                squared_dx < squared_previous_x * squared(newton.relative_estimate_difference)) {
                converged_on(NewtonStatus::converged_relative_estimate_difference);
                break;
            }
            if (newton.absolute_estimate_difference > 0 && squared_dx < squared(newton.absolute_estimate_difference)) {
                converged_on(NewtonStatus::converged_absolute_estimate_difference);
                break;
            }
        }
    }
    if (converged) ++iterations_;  // SOFA's count stops at the converged iteration's index
    else status_ = NewtonStatus::diverged_max_iterations;
}

}  // namespace penalty
