// SpringForceField<Rigid3>: see include/penalty/mechanics/rigid_spring_force_field.hpp. The
// arithmetic follows SpringForceField::computeSpringForce / computeSpringDForce term by term.
#include "penalty/mechanics/rigid_spring_force_field.hpp"

#include "penalty/core/error.hpp"
#include "sofa_vector_ops.hpp"

#include <cmath>

namespace penalty {

RigidSpringForceField::RigidSpringForceField(Rigid3Object& state1, Rigid3Object& state2, std::vector<Spring> springs)
    : s1_(&state1), s2_(&state2), springs_(std::move(springs)) {}

ForceFieldStates RigidSpringForceField::states() const {
    if (s1_ == s2_) return ForceFieldStates(s1_);
    return {s1_, s2_};
}

void RigidSpringForceField::init() {
    for (std::size_t k = 0; k < springs_.size(); ++k) {
        const Spring& s = springs_[k];
        if (s.a < 0 || static_cast<std::size_t>(s.a) >= s1_->num_dofs() || s.b < 0 ||
            static_cast<std::size_t>(s.b) >= s2_->num_dofs())
            throw_invalid_argument("SpringForceField: spring ", k, " joins frames ", s.a, " and ", s.b,
                                   ", out of range (", s1_->num_dofs(), " and ", s2_->num_dofs(), " frames)");
        if (!(s.ks >= 0) || !(s.kd >= 0) || !(s.rest_length >= 0) || !std::isfinite(s.ks) || !std::isfinite(s.kd) ||
            !std::isfinite(s.rest_length))
            throw_invalid_argument("SpringForceField: spring ", k,
                                   ": stiffness, damping and length must be finite and >= 0");
    }
    dfdx_.assign(springs_.size(), Mat3::Zero());
}

void RigidSpringForceField::accumulate_force() {
    energy_ = 0.0;
    dfdx_.resize(springs_.size());
    for (std::size_t i = 0; i < springs_.size(); ++i) {
        const Spring& s = springs_[i];
        const auto a = static_cast<std::size_t>(s.a), b = static_cast<std::size_t>(s.b);
        Vec3 u = s2_->position[b].center - s1_->position[a].center;
        const double d = std::sqrt(sofa_vec::dot3(u, u));
        if (!(d > 1.0e-9)) {
            dfdx_[i].setZero();
            continue;
        }
        const double inverse_length = 1.0 / d;
        u = sofa_vec::scaled(u, inverse_length);
        const double elongation = d - s.rest_length;
        energy_ += elongation * elongation * s.ks / 2;
        const Vec3 relative_velocity = s2_->velocity[b].linear - s1_->velocity[a].linear;
        const double elongation_velocity = sofa_vec::dot3(u, relative_velocity);
        const double force_intensity = s.ks * elongation + s.kd * elongation_velocity;
        const Vec3 force = sofa_vec::scaled(u, force_intensity);
        const double tgt = force_intensity * inverse_length;
        Mat3& m = dfdx_[i];
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) m(j, k) = (s.ks - tgt) * u[j] * u[k];
            m(j, j) += tgt;
        }
        s1_->force[a].linear += force;
        s2_->force[b].linear += -force;
    }
}

void RigidSpringForceField::accumulate_dforce(double k_factor, double /*b_factor*/) {
    for (std::size_t i = 0; i < springs_.size(); ++i) {
        const Spring& s = springs_[i];
        const auto a = static_cast<std::size_t>(s.a), b = static_cast<std::size_t>(s.b);
        const Vec3 d = s2_->dx[b].linear - s1_->dx[a].linear;
        const Vec3 dforce = sofa_vec::scaled(sofa_vec::times(dfdx_[i], d), k_factor);
        s1_->df[a].linear += dforce;
        s2_->df[b].linear -= dforce;
    }
}

void RigidSpringForceField::add_stiffness(TripletList& t, const StateOffsets& offsets, double factor) const {
    // addKToMatrix: −k on the (a, a) and (b, b) linear blocks, +k on (a, b) and (b, a), k = m·factor
    const Index o1 = offsets(s1_), o2 = offsets(s2_);
    for (std::size_t e = 0; e < springs_.size() && e < dfdx_.size(); ++e) {
        const Spring& s = springs_[e];
        const Index p1 = o1 + 6 * s.a, p2 = o2 + 6 * s.b;
        for (Index i = 0; i < 3; ++i)
            for (Index j = 0; j < 3; ++j) {
                const double k = dfdx_[e](i, j) * factor;
                t.emplace_back(p1 + i, p1 + j, -k);
                t.emplace_back(p1 + i, p2 + j, k);
                t.emplace_back(p2 + i, p1 + j, k);
                t.emplace_back(p2 + i, p2 + j, -k);
            }
    }
}

}  // namespace penalty
