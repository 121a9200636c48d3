#pragma once
/// @file
/// SOFA's explicit Runge-Kutta solvers, RungeKutta2Solver (midpoint) and RungeKutta4Solver
/// (classical), on a solver subtree: each stage's acceleration a = P·M⁻¹·f(x, v)
/// (MechanicalOperations::computeAcc: positions and velocities set, propagated through the
/// mappings, forces computed, M⁻¹ applied, projected).

#include "penalty/simulation/solver.hpp"

#include <vector>

namespace penalty {

/// The positions of a subtree's independent states, kept to be put back (Vec3d, Rigid3d).
class SubtreePositions {
public:
    /// Copies the current positions of `system`'s independent states.
    void save(const SubtreeSystem& system);
    /// Puts the saved positions back.
    void restore(const SubtreeSystem& system) const;

private:
    std::vector<std::vector<Vec3>> vec3_;
    std::vector<std::vector<RigidFrame>> rigid_;
};

/// The common part of the Runge-Kutta solvers: the subtree's system and computeAcc.
class RungeKuttaSolver : public OdeSolver {
public:
    /// Checks that every independent state has an invertible mass (SOFA's accFromF), naming it.
    void init(Node& node) override;
    [[nodiscard]] std::optional<std::size_t> list_touched_states(Node& node,
                                                                 std::vector<const BaseState*>& out) override;

protected:
    /// a = P·M⁻¹·f(x, v) with the positions x already in the states: v is scattered, projected
    /// in place (projectVelocity), both are propagated through the mappings, then the forces.
    void acceleration(const SubtreeSystem& system, Eigen::VectorXd& v, Eigen::VectorXd& a);
    SubtreeSystemCache system_;
    SubtreePositions start_;
    Eigen::VectorXd f_;
};

/// RungeKutta2Solver::solve (h = dt): a₁ = a(x, v); x' = x + v·h/2, v' = v + a₁·h/2;
/// a₂ = a(x', v'); x ← x + v'·h, v ← v + a₂·h.
class RungeKutta2Solver final : public RungeKuttaSolver {
public:
    void solve(Node& node, double dt) override;

private:
    Eigen::VectorXd v0_, v_mid_, a_;
};

/// RungeKutta4Solver::solve (h = dt): k1 = (v, a(x, v)); k2 = (v + a₁h/2, a(x + k1v·h/2, ·));
/// k3 = (v + a₂h/2, a(x + k2v·h/2, ·)); k4 = (v + a₃h, a(x + k3v·h, ·));
/// x ← ((((x + k1v·h/6) + k2v·h/3) + k3v·h/3) + k4v·h/6), v likewise with the a's, summed in that
/// order (SOFA's v_multiop). Global error O(h⁴).
class RungeKutta4Solver final : public RungeKuttaSolver {
public:
    void solve(Node& node, double dt) override;

private:
    Eigen::VectorXd v0_;
    std::array<Eigen::VectorXd, 4> kv_;
    std::array<Eigen::VectorXd, 4> ka_;
};

}  // namespace penalty
