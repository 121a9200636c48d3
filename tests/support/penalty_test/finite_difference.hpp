#pragma once
/// @file
/// Central finite differences for derivative tests (gradient of a scalar, Jacobian of a vector
/// function) and a relative comparison that refuses vacuous passes (all-zero operands).

#include <Eigen/Core>

#include <algorithm>
#include <functional>

namespace penalty::test {

/// d f / d x by central differences, step h per coordinate: (f(x + h e_i) - f(x - h e_i)) / 2h.
inline Eigen::VectorXd finite_gradient(const Eigen::VectorXd& x, const std::function<double(const Eigen::VectorXd&)>& f,
                                       double h = 1e-6) {
    Eigen::VectorXd grad(x.size());
    Eigen::VectorXd xp = x;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
        xp[i] = x[i] + h;
        const double fp = f(xp);
        xp[i] = x[i] - h;
        const double fm = f(xp);
        xp[i] = x[i];
        grad[i] = (fp - fm) / (2.0 * h);
    }
    return grad;
}

/// d F / d x (rows: outputs, columns: inputs) by central differences.
inline Eigen::MatrixXd finite_jacobian(const Eigen::VectorXd& x,
                                       const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                       double h = 1e-6) {
    const Eigen::VectorXd f0 = f(x);
    Eigen::MatrixXd jac(f0.size(), x.size());
    Eigen::VectorXd xp = x;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
        xp[i] = x[i] + h;
        const Eigen::VectorXd fp = f(xp);
        xp[i] = x[i] - h;
        const Eigen::VectorXd fm = f(xp);
        xp[i] = x[i];
        jac.col(i) = (fp - fm) / (2.0 * h);
    }
    return jac;
}

/// |a − b|∞ <= tol · max(|a|∞, |b|∞): relative to the larger operand at every scale (a
/// derivative of size 1e-6 is checked to tol·1e-6, not to tol). Refuses vacuous passes: two
/// all-zero operands (nothing was checked), different sizes, and non-finite values fail.
template <class A, class B>
bool near_relative(const A& a, const B& b, double tol) {
    if (a.size() != b.size() || a.size() == 0) return false;
    if (!a.allFinite() || !b.allFinite()) return false;
    const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
    if (scale == 0.0) return false;
    return (a - b).cwiseAbs().maxCoeff() <= tol * scale;
}

}  // namespace penalty::test
