#pragma once
/// @file
/// Finite differences on Rigid3d states: a displacement δ of frame i is (δc, δθ), the centre
/// moved by δc and the orientation turned by the world rotation vector δθ (q ← exp(δθ)·q), the
/// convention of RigidDeriv's angular part. Header-only; include it only from suites that link
/// penalty::mechanics.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty_test/finite_difference.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <vector>

namespace penalty::test {

/// The frames displaced by δ (6 per frame).
inline std::vector<RigidFrame> displaced_frames(const std::vector<RigidFrame>& x0, const Eigen::VectorXd& delta) {
    std::vector<RigidFrame> x = x0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const auto o = static_cast<Eigen::Index>(6 * i);
        x[i].center += delta.segment<3>(o);
        const Vec3 w = delta.segment<3>(o + 3);
        const double angle = w.norm();
        if (angle > 0) x[i].orientation = (Quat(Eigen::AngleAxisd(angle, w / angle)) * x[i].orientation).normalized();
    }
    return x;
}

/// f(x0 + δ) of `ff` on state `s` (force cleared first), flat 6 per frame; leaves s at x0 + δ.
inline Eigen::VectorXd rigid_force_at(BaseForceField& ff, Rigid3Object& s, const std::vector<RigidFrame>& x0,
                                      const Eigen::VectorXd& delta) {
    s.position = displaced_frames(x0, delta);
    std::fill(s.force.begin(), s.force.end(), RigidDeriv{});
    ff.accumulate_force();
    return Rigid3Object::flat(s.force);
}

/// ∂f/∂δ at x0 by central differences (6n × 6n).
inline Eigen::MatrixXd rigid_force_jacobian(BaseForceField& ff, Rigid3Object& s, double h = 1e-6) {
    const std::vector<RigidFrame> x0 = s.position;
    const auto n = static_cast<Eigen::Index>(6 * x0.size());
    const Eigen::MatrixXd k = finite_jacobian(
        Eigen::VectorXd::Zero(n), [&](const Eigen::VectorXd& d) { return rigid_force_at(ff, s, x0, d); }, h);
    rigid_force_at(ff, s, x0, Eigen::VectorXd::Zero(n));  // back at x0, linearised there
    return k;
}

/// Column j: add_dforce(dx = e_j, k_factor 1) at the last accumulate_force.
inline Eigen::MatrixXd rigid_dforce_matrix(BaseForceField& ff, Rigid3Object& s) {
    const auto n = static_cast<Eigen::Index>(6 * s.num_dofs());
    Eigen::MatrixXd k(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {
        std::fill(s.dx.begin(), s.dx.end(), RigidDeriv{});
        std::fill(s.df.begin(), s.df.end(), RigidDeriv{});
        Rigid3Object::flat(s.dx)[j] = 1.0;
        ff.accumulate_dforce(1.0, 0.0);
        k.col(j) = Rigid3Object::flat(s.df);
    }
    return k;
}

/// The assembled stiffness (factor 1, offset 0).
inline Eigen::MatrixXd assembled_stiffness(const BaseForceField& ff, Index size) {
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, 1.0);
    SparseMatrix k(size, size);
    k.setFromTriplets(t.begin(), t.end());
    return Eigen::MatrixXd(k);
}

}  // namespace penalty::test
