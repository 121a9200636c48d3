#include "penalty/simulation/ode_solver.hpp"

#include "penalty/core/error.hpp"
#include "penalty/simulation/direct_linear_solver.hpp"

#include <cmath>

namespace penalty {

// ---- EulerImplicitSolver ----------------------------------------------------------------------
void EulerImplicitSolver::init(Node& node) {
    cg.check();
    // The subtree's structure (mapped states, masses, mappings) is checked here, at init, so
    // that a scene the solver cannot integrate is refused before the run (not at step 0).
    (void)SubtreeSystem(node);
    if (!std::isfinite(rayleigh_stiffness) || rayleigh_stiffness < 0)
        throw_invalid_argument("EulerImplicitSolver: rayleighStiffness must be >= 0, got ", rayleigh_stiffness);
    if (!std::isfinite(rayleigh_mass) || rayleigh_mass < 0)
        throw_invalid_argument("EulerImplicitSolver: rayleighMass must be >= 0, got ", rayleigh_mass);
    if (!std::isfinite(vdamping) || vdamping < 0)
        throw_invalid_argument("EulerImplicitSolver: vdamping must be >= 0, got ", vdamping);
}

void EulerImplicitSolver::record_cg(const CgStats& stats) {
    last_cg_ = stats;
    step_cg_solves_.push_back(stats);
    step_cg_iterations_ += stats.iterations;
    step_cg_limit_reached_ = step_cg_limit_reached_ || stats.end_condition == CgEndCondition::iterations;
}

std::optional<std::size_t> EulerImplicitSolver::list_touched_states(Node& node, std::vector<const BaseState*>& out) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.append_states(out);
    return static_cast<std::size_t>(sys.size());
}

void EulerImplicitSolver::solve(Node& node, double dt) {
    SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.set_blocked_reductions(blocked_reductions);
    step_cg_iterations_ = 0;
    step_cg_solves_.clear();
    step_cg_limit_reached_ = false;
    if (newton.enabled) {
        last_solve_ = {};
        b_.resize(0);
        x_.resize(0);
        solve_newton(sys, dt);
        return;
    }
    const double h = dt;
    const double tr = trapezoidal_scheme ? 0.5 : 1.0;
    const double rs = rayleigh_stiffness;
    const double rm = rayleigh_mass;
    sys.compute_force(f_);
    sys.gather_velocity(v_);
    const SubtreeSystem::FixedReaders fixed_readers(sys);  // no contact changes until the solve ends
    // SOFA's EulerImplicitSolver::solve: b = f; b += (−rm·M + (h·tr + rs)·K)·v, each force
    // field (and mass) adding into b in turn (MappingGraphMechanicalOperations::addMBKv);
    // b = b·h (b.teq(h)).
    b_ = f_;
    if (!first_order) {
        sys.apply_mbk(v_, b_, -rm, 0.0, h * tr + rs, false, /*accumulate=*/true);
        b_ *= h;
    }
    sys.project(b_);
    // A = mf·M + bf·B + kf·K
    MbkCgSystem system(sys, first_order ? 1.0 : 1.0 + tr * h * rm, first_order ? 0.0 : -tr * h,
                       first_order ? -h * tr : -tr * h * (tr * h + rs));
    last_solve_ = {system.m(), system.b(), system.k()};
    try {
        if (direct_solver) direct_solver->solve(sys, system.m(), system.b(), system.k(), b_, x_);
        else record_cg(cg.solve(system, b_, x_));
    } catch (const NonFiniteSolveError& e) {
        // Finite forces, yet the solve overflowed (|b|², p·q): name the largest force.
        if (e.force_field() == nullptr && e.mass() == nullptr) sys.throw_naming_largest_force(e.what());
        throw;
    }
    // v_new = x (first order) or v + x, kept in v_
    if (first_order) v_ = x_;
    else v_ += x_;
    sys.scatter_velocity(v_);
    sys.add_to_positions(h, v_);
    if (vdamping != 0.0) {
        v_ *= std::exp(-h * vdamping);
        sys.scatter_velocity(v_);
    }
}

void EulerImplicitSolver::solve_newton(SubtreeSystem& sys, double dt) {
    const double h = dt;
    Eigen::VectorXd v0;
    sys.gather_velocity(v0);
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(v0.size());
    Eigen::VectorXd applied = Eigen::VectorXd::Zero(v0.size());  // h·v currently added to x_n
    double r0 = -1.0;
    last_newton_iterations_ = 0;
    last_newton_converged_ = false;
    for (int it = 0; it < newton.max_iterations; ++it) {
        // Iterate: x = x_n + h (v_n + dv) (x = x_n at the first iterate), v = v_n + dv.
        const Eigen::VectorXd v = v0 + dv;
        if (it > 0) {
            const Eigen::VectorXd target = h * v;
            sys.add_to_positions(1.0, target - applied);
            applied = target;
        }
        sys.scatter_velocity(v);
        sys.propagate_positions_and_velocities();
        if (newton.update_geometry) newton.update_geometry();
        const SubtreeSystem::FixedReaders fixed_readers(sys);  // the contacts of this iterate
        Eigen::VectorXd f;
        sys.compute_force(f);
        Eigen::VectorXd mdv;
        sys.apply_mbk(dv, mdv, 1.0, 0.0, 0.0, false);
        // −R = h f − M dv; at it = 0 add the implicit term of the linearisation at x_n.
        Eigen::VectorXd rhs = h * f - mdv;
        if (it == 0) {
            Eigen::VectorXd kv;
            sys.apply_mbk(v, kv, 0.0, 0.0, h, false);
            rhs += h * kv;
        }
        sys.project(rhs);
        const double rn = rhs.norm();
        if (r0 < 0) r0 = std::max(1.0, rn);
        last_newton_iterations_ = it + 1;
        last_newton_residual_ = rn / r0;
        if (it > 0 && rn <= newton.tolerance * r0) {
            last_newton_converged_ = true;
            break;
        }
        Eigen::VectorXd delta;
        MbkCgSystem system(sys, 1.0, -h, -h * h);
        if (direct_solver) direct_solver->solve(sys, 1.0, -h, -h * h, rhs, delta);
        else record_cg(cg.solve(system, rhs, delta));
        dv += delta;
    }
    const Eigen::VectorXd v = v0 + dv;
    sys.add_to_positions(1.0, h * v - applied);
    sys.scatter_velocity(v);
}

// ---- EulerExplicitSolver ----------------------------------------------------------------------
void EulerExplicitSolver::init(Node& node) {
    const SubtreeSystem sys(node);
    Eigen::VectorXd probe = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(sys.size()));
    Eigen::VectorXd out;
    sys.apply_inverse_mass(probe, out);  // throws naming a state without a mass
}

std::optional<std::size_t> EulerExplicitSolver::list_touched_states(Node& node, std::vector<const BaseState*>& out) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.append_states(out);
    return static_cast<std::size_t>(sys.size());
}

void EulerExplicitSolver::solve(Node& node, double dt) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.compute_force(f_);
    sys.apply_inverse_mass(f_, a_);
    sys.project(a_);
    sys.gather_velocity(v_);
    v_ += dt * a_;
    sys.scatter_velocity(v_);
    sys.add_to_positions(dt, v_);
}

}  // namespace penalty
