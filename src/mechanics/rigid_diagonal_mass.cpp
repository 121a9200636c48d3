#include "penalty/mechanics/rigid_diagonal_mass.hpp"

#include "penalty/core/error.hpp"
#include "sofa_vector_ops.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

RigidDiagonalMass::RigidDiagonalMass(Rigid3Object& state, std::vector<FrameMass> masses)
    : state_(&state), masses_(std::move(masses)) {
    for (std::size_t i = 0; i < masses_.size(); ++i) {
        const FrameMass& m = masses_[i];
        if (!std::isfinite(m.mass) || m.mass <= 0.0)
            throw_invalid_argument("DiagonalMass: the mass of frame ", i, " must be finite and > 0, got ", m.mass);
        if (!m.inertia.allFinite() || !m.inertia.isApprox(m.inertia.transpose(), 1e-12) ||
            !(m.inertia.determinant() > 0.0))
            throw_invalid_argument("DiagonalMass: the inertia matrix of frame ", i,
                                   " must be symmetric and invertible");
        inertia_mass_.push_back(m.inertia * m.mass);  // RigidMass::recalc
    }
}

std::size_t RigidDiagonalMass::count() const { return std::min(masses_.size(), state_->num_dofs()); }

void RigidDiagonalMass::add_gravity_force(const Vec3& g) {
    // DiagonalMass::addForce: f += theGravity·m, theGravity = (g, 0): no torque
    for (std::size_t i = 0; i < count(); ++i) state_->force[i].linear += g * masses_[i].mass;
}

void RigidDiagonalMass::add_mdx(double factor) {
    // DiagonalMass::addMDx: res += dx·m (factor 1), else res += (dx·m)·factor
    const std::size_t n = std::min(count(), state_->dx.size());
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 linear = state_->dx[i].linear * masses_[i].mass;
        Vec3 angular = sofa_vec::times(inertia_mass_[i], state_->dx[i].angular);
        if (factor != 1.0) {
            linear = linear * factor;
            angular = angular * factor;
        }
        state_->df[i].linear += linear;
        state_->df[i].angular += angular;
    }
}

void RigidDiagonalMass::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in,
                                      Eigen::Ref<Eigen::VectorXd> out) const {
    // DiagonalMass::accFromF: a = f / m (linear), (J·m)⁻¹·f (angular); no mass: 0
    out.setZero();
    for (std::size_t i = 0; i < count(); ++i) {
        const auto o = Eigen::Index(6 * i);
        out.segment<3>(o) = in.segment<3>(o) / masses_[i].mass;
        out.segment<3>(o + 3) = inertia_mass_[i].inverse() * in.segment<3>(o + 3);
    }
}

void RigidDiagonalMass::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    for (std::size_t i = 0; i < count(); ++i) {
        const Index o = offset + 6 * Index(i);
        for (Index a = 0; a < 3; ++a) t.emplace_back(o + a, o + a, factor * masses_[i].mass);
        for (Index a = 0; a < 3; ++a)
            for (Index b = 0; b < 3; ++b) t.emplace_back(o + 3 + a, o + 3 + b, factor * inertia_mass_[i](a, b));
    }
}

double RigidDiagonalMass::kinetic_energy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < count(); ++i) {
        const RigidDeriv& v = state_->velocity[i];
        e += masses_[i].mass * v.linear.squaredNorm() + v.angular.dot(inertia_mass_[i] * v.angular);
    }
    return 0.5 * e;
}

double RigidDiagonalMass::gravity_potential_energy(const Vec3& g) const {
    double e = 0.0;
    for (std::size_t i = 0; i < count(); ++i) e -= masses_[i].mass * g.dot(state_->position[i].center);
    return e;
}

double RigidDiagonalMass::total_mass() const {
    double m = 0.0;
    for (std::size_t i = 0; i < count(); ++i) m += masses_[i].mass;
    return m;
}

}  // namespace penalty
