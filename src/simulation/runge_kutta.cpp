#include "penalty/simulation/runge_kutta.hpp"

namespace penalty {

void SubtreePositions::save(const SubtreeSystem& system) {
    vec3_.resize(system.independent_states().size());
    rigid_.resize(system.independent_states().size());
    for (std::size_t i = 0; i < system.independent_states().size(); ++i) {
        const BaseState* s = system.independent_states()[i];
        PENALTY_DEMAND(s != nullptr);
        const std::string_view name = s->state_name();
        if (const auto* v = dynamic_cast<const Vec3Object*>(s)) vec3_[i] = v->position;
        else if (const auto* r = dynamic_cast<const Rigid3Object*>(s)) rigid_[i] = r->position;
        else throw_invalid_argument("Runge-Kutta: state '", name, "' is neither Vec3d nor Rigid3d");
    }
}

void SubtreePositions::restore(const SubtreeSystem& system) const {
    for (std::size_t i = 0; i < system.independent_states().size(); ++i) {
        BaseState* s = system.independent_states()[i];
        if (auto* v = dynamic_cast<Vec3Object*>(s)) v->position = vec3_[i];
        else if (auto* r = dynamic_cast<Rigid3Object*>(s)) r->position = rigid_[i];
    }
}

void RungeKuttaSolver::init(Node& node) {
    const SubtreeSystem sys(node);
    Eigen::VectorXd probe = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(sys.size()));
    Eigen::VectorXd out;
    sys.apply_inverse_mass(probe, out);  // throws naming a state without an invertible mass
}

std::optional<std::size_t> RungeKuttaSolver::list_touched_states(Node& node, std::vector<const BaseState*>& out) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.append_states(out);
    return static_cast<std::size_t>(sys.size());
}

// MechanicalOperations::computeAcc: projectPositionAndVelocity, propagate, computeForce,
// accFromF, projectResponse.
void RungeKuttaSolver::acceleration(const SubtreeSystem& system, Eigen::VectorXd& v, Eigen::VectorXd& a) {
    system.scatter_velocity(v);
    if (!system.constraints().empty()) {
        for (BaseProjectiveConstraint* c : system.constraints()) c->project_velocity();
        system.gather_velocity(v);  // SOFA projects the stage's velocity vector in place
    }
    system.propagate_positions_and_velocities();
    system.compute_force(f_);
    system.apply_inverse_mass(f_, a);
    system.project(a);
}

void RungeKutta2Solver::solve(Node& node, double dt) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    const double half = dt / 2.;
    start_.save(sys);
    sys.gather_velocity(v0_);
    acceleration(sys, v0_, a_);
    // newX = pos + vel·dt/2, newV = vel + acc·dt/2
    sys.add_to_positions(half, v0_);
    v_mid_ = v0_ + a_ * half;
    acceleration(sys, v_mid_, a_);
    // pos = pos + newV·dt, vel = vel + acc·dt
    start_.restore(sys);
    sys.add_to_positions(dt, v_mid_);
    sys.scatter_velocity(v0_ + a_ * dt);
}

void RungeKutta4Solver::solve(Node& node, double dt) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    const double by2 = dt / 2.0;
    const double by3 = dt / 3.0;
    const double by6 = dt / 6.0;
    start_.save(sys);
    sys.gather_velocity(v0_);
    kv_[0] = v0_;
    acceleration(sys, kv_[0], ka_[0]);
    // stage s: x = pos + k(s−1)v·f, k(s)v = vel + k(s−1)a·f with f = dt/2, dt/2, dt
    const double factors[3] = {by2, by2, dt};
    for (std::size_t s = 1; s < 4; ++s) {
        start_.restore(sys);
        sys.add_to_positions(factors[s - 1], kv_[s - 1]);
        kv_[s] = v0_ + ka_[s - 1] * factors[s - 1];
        acceleration(sys, kv_[s], ka_[s]);
    }
    // pos = pos + k1v·dt/6 + k2v·dt/3 + k3v·dt/3 + k4v·dt/6 (vOp after vOp), vel likewise
    start_.restore(sys);
    const double weights[4] = {by6, by3, by3, by6};
    Eigen::VectorXd v = v0_;
    for (std::size_t s = 0; s < 4; ++s) {
        sys.add_to_positions(weights[s], kv_[s]);
        v += ka_[s] * weights[s];
    }
    sys.scatter_velocity(v);
}

}  // namespace penalty
