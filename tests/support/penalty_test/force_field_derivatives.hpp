#pragma once
/// @file
/// The derivative check of a force field acting on one Vec3 state, by central finite differences
/// of the state's positions (h = 1e-6): `add_dforce` (k_factor 1) and the assembled stiffness
/// triplets equal K = ∂f/∂x (SOFA's sign: negative semi-definite for springs), and f = −∂E/∂x.
/// Header-only; include it only from suites that link penalty::mechanics.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty_test/finite_difference.hpp"

#include <gtest/gtest.h>
#include <Eigen/Core>

#include <algorithm>
#include <optional>

namespace penalty::test {

/// Relative tolerances of the checks (|a − b|∞ ≤ tol·max(|a|∞, |b|∞), see near_relative).
struct DerivativeTolerances {
    double dforce_vs_fd;         ///< add_dforce columns vs the FD Jacobian of the force
    double assembled_vs_dforce;  ///< add_stiffness triplets vs add_dforce
    /// f vs −FD(E); none: E is not the potential of f (corotational FEM), not checked.
    std::optional<double> force_vs_energy;
};

/// What the check measured at x0, for checks of the caller's own (symmetry, a stress-free motion,
/// a non-vacuous |K|).
struct ForceFieldDerivatives {
    Eigen::VectorXd force;     ///< f(x0), flat (3 per DOF)
    Eigen::MatrixXd k_fd;      ///< ∂f/∂x by central differences
    Eigen::MatrixXd k_dforce;  ///< column j: add_dforce(dx = e_j, k_factor 1, b_factor 0)
};

/// Checks (EXPECT_*) the derivatives of `ff` on its state `s` at the current positions x0 with the
/// tolerances `tol`; on return the state is back at x0 with f(x0) in `force` (field linearised at x0).
inline ForceFieldDerivatives check_force_field_derivatives(BaseForceField& ff, Vec3Object& s,
                                                           const DerivativeTolerances& tol) {
    const auto n = static_cast<Eigen::Index>(3 * s.num_dofs());
    Eigen::VectorXd x0(n);
    for (std::size_t i = 0; i < s.num_dofs(); ++i) x0.segment<3>(3 * static_cast<Eigen::Index>(i)) = s.position[i];
    auto force = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        for (std::size_t i = 0; i < s.num_dofs(); ++i) s.position[i] = x.segment<3>(3 * static_cast<Eigen::Index>(i));
        std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
        ff.accumulate_force();
        return Vec3Object::flat(s.force);
    };
    ForceFieldDerivatives d;
    d.k_fd = finite_jacobian(x0, force, 1e-6);
    d.force = force(x0);  // linearise at x0
    d.k_dforce.resize(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {
        std::fill(s.dx.begin(), s.dx.end(), Vec3::Zero());
        std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
        Vec3Object::flat(s.dx)[j] = 1.0;
        ff.accumulate_dforce(1.0, 0.0);
        d.k_dforce.col(j) = Vec3Object::flat(s.df);
    }
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, 1.0);
    SparseMatrix k_sparse(n, n);
    k_sparse.setFromTriplets(t.begin(), t.end());
    const Eigen::MatrixXd k_assembled(k_sparse);
    EXPECT_TRUE(near_relative(d.k_dforce, d.k_fd, tol.dforce_vs_fd))
        << "add_dforce vs FD: max diff " << (d.k_dforce - d.k_fd).cwiseAbs().maxCoeff();
    EXPECT_TRUE(near_relative(k_assembled, d.k_dforce, tol.assembled_vs_dforce)) << "assembled vs add_dforce";
    if (tol.force_vs_energy) {
        auto energy = [&](const Eigen::VectorXd& x) {
            force(x);
            return ff.potential_energy();
        };
        const Eigen::VectorXd grad = finite_gradient(x0, energy, 1e-6);
        EXPECT_TRUE(near_relative(Eigen::VectorXd(-grad), d.force, *tol.force_vs_energy)) << "f = -dE/dx";
        force(x0);
    }
    return d;
}

}  // namespace penalty::test
