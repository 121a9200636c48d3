#include "penalty/mechanics/mass.hpp"

#include "sofa_vector_ops.hpp"

#include "penalty/mechanics/ordered_scatter.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace penalty {

namespace {
constexpr std::size_t kUniformMassDofsPerTask = 4096;  // add_mdx on threads (a large state)

void check_mass(double m, const char* parameter) {
    if (!std::isfinite(m) || m <= 0.0)
        throw_invalid_argument("UniformMass: ", parameter, " must be finite and > 0, got ", m);
}
}  // namespace

template <class DT>
void UniformMass<DT>::set_vertex_mass(double m) {
    check_mass(m, "vertexMass");
    vertex_mass_ = m;
}

template <class DT>
void UniformMass<DT>::set_total_mass(double m) {
    check_mass(m, "totalMass");
    total_mass_ = m;
}

template <class DT>
void UniformMass<DT>::set_inertia(const Mat3& inertia) {
    if (!inertia.allFinite() || !inertia.isApprox(inertia.transpose(), 1e-12) ||
        Eigen::SelfAdjointEigenSolver<Mat3>(inertia).eigenvalues().minCoeff() <= 0.0) {
        throw_invalid_argument("UniformMass: inertiaMatrix must be symmetric positive definite");
    }
    inertia_ = inertia;
}

template <class DT>
void UniformMass<DT>::init() {
    if (total_mass_) {
        if (state_->num_dofs() == 0) throw_invalid_argument("UniformMass: totalMass given for a state with no DOF");
        mass_ = *total_mass_ / static_cast<double>(state_->num_dofs());
    } else if (vertex_mass_) {
        mass_ = *vertex_mass_;
    } else {
        throw_invalid_argument("UniformMass: neither vertexMass nor totalMass is set");
    }
}

template <>
void UniformMass<Vec3Types>::add_gravity_force(const Vec3& g) {
    const double m = lagging_weight_mass_.value_or(mass_);
    for (auto& f : state_->force) f += m * g;
}
template <>
void UniformMass<Rigid3Types>::add_gravity_force(const Vec3& g) {
    const double m = lagging_weight_mass_.value_or(mass_);
    for (auto& f : state_->force) f.linear += m * g;
}

template <>
void UniformMass<Vec3Types>::add_mdx(double factor) {
    lagging_weight_mass_.reset();  // SOFA's update callback has run (set_lagging_weight_mass)
    // df += dx·(m·factor), the scale computed once (the same double for every DOF)
    // (each DOF its own: on TBB's threads for a large state, the same bits)
    const double scale = mass_ * factor;
    Vec3* df = state_->df.data();
    const Vec3* dx = state_->dx.data();
    detail::for_each_range(state_->df.size(), kUniformMassDofsPerTask, [=](std::size_t first, std::size_t end) {
        // (locals: a store through df could otherwise alias the closure's copies, read again each time)
        Vec3* const out = df;
        const Vec3* const in = dx;
        const double s = scale;
        for (std::size_t i = first; i < end; ++i) out[i] += in[i] * s;
    });
}
template <>
void UniformMass<Rigid3Types>::add_mdx(double factor) {
    lagging_weight_mass_.reset();  // SOFA's update callback has run (set_lagging_weight_mass)
    // UniformMass::addMDx with SOFA's RigidMass: m *= factor (when factor != 1) scales the mass
    // and the inertia-mass matrix J·m, then df += (dx_lin·m, (J·m)·dx_ang), each row summed left
    // to right (RigidMass's operator*(Deriv, RigidMass))
    double m = mass_;
    Mat3 j = inertia_ * mass_;  // RigidMass::recalc: inertiaMassMatrix = inertiaMatrix * mass
    if (factor != 1.0) {
        m *= factor;
        j *= factor;
    }
    for (std::size_t i = 0; i < state_->df.size(); ++i) {
        state_->df[i].linear += state_->dx[i].linear * m;
        state_->df[i].angular += sofa_vec::times(j, state_->dx[i].angular);
    }
}

template <>
void UniformMass<Vec3Types>::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in,
                                           Eigen::Ref<Eigen::VectorXd> out) const {
    lagging_weight_mass_.reset();  // SOFA's update callback has run (set_lagging_weight_mass)
    out = in / mass_;
}
template <>
void UniformMass<Rigid3Types>::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in,
                                             Eigen::Ref<Eigen::VectorXd> out) const {
    lagging_weight_mass_.reset();  // SOFA's update callback has run (set_lagging_weight_mass)
    const Mat3 jinv = (inertia_ * mass_).inverse();
    for (Eigen::Index i = 0; i < in.size() / 6; ++i) {
        out.segment<3>(6 * i) = in.segment<3>(6 * i) / mass_;
        out.segment<3>(6 * i + 3) = jinv * in.segment<3>(6 * i + 3);
    }
}

template <>
void UniformMass<Vec3Types>::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    lagging_weight_mass_.reset();  // SOFA's update callback has run (set_lagging_weight_mass)
    for (Index i = 0; i < static_cast<Index>(3 * state_->num_dofs()); ++i)
        t.emplace_back(offset + i, offset + i, factor * mass_);
}
template <>
void UniformMass<Rigid3Types>::add_mass_triplets(TripletList& t, Index offset, double factor) const {
    lagging_weight_mass_.reset();  // SOFA's update callback has run (set_lagging_weight_mass)
    for (Index i = 0; i < static_cast<Index>(state_->num_dofs()); ++i) {
        const Index o = offset + 6 * i;
        for (Index a = 0; a < 3; ++a) t.emplace_back(o + a, o + a, factor * mass_);
        for (Index a = 0; a < 3; ++a)
            for (Index b = 0; b < 3; ++b) t.emplace_back(o + 3 + a, o + 3 + b, factor * mass_ * inertia_(a, b));
    }
}

template <>
double UniformMass<Vec3Types>::kinetic_energy() const {
    double e = 0.0;
    for (const auto& v : state_->velocity) e += v.squaredNorm();
    return 0.5 * mass_ * e;
}
template <>
double UniformMass<Rigid3Types>::kinetic_energy() const {
    double e = 0.0;
    for (const auto& v : state_->velocity)
        e += mass_ * v.linear.squaredNorm() + mass_ * v.angular.dot(inertia_ * v.angular);
    return 0.5 * e;
}

template <>
double UniformMass<Vec3Types>::gravity_potential_energy(const Vec3& g) const {
    double e = 0.0;
    for (const auto& x : state_->position) e -= mass_ * g.dot(x);
    return e;
}
template <>
double UniformMass<Rigid3Types>::gravity_potential_energy(const Vec3& g) const {
    double e = 0.0;
    for (const auto& x : state_->position) e -= mass_ * g.dot(x.center);
    return e;
}

template class UniformMass<Vec3Types>;
template class UniformMass<Rigid3Types>;

void FixedProjectiveConstraint::init() {
    for (const Index i : indices_) {
        if (i < 0 || static_cast<std::size_t>(i) >= state_->num_dofs()) {
            throw_invalid_argument("FixedProjectiveConstraint: index ", i, " out of range for state '",
                                   state_->state_name(), "' of ", state_->num_dofs(), " DOFs");
        }
    }
}

const std::vector<Index>& FixedProjectiveConstraint::read_indices() const { return follow(indices_); }

void FixedProjectiveConstraint::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    if (fix_all_) {
        v.setZero();
        return;
    }
    const Index d = state_->deriv_size();
    for (const Index i : read_indices()) v.segment(d * i, d).setZero();
}

bool FixedProjectiveConstraint::list_discarded_rows(std::vector<Index>& rows) const {
    const Index d = state_->deriv_size();
    if (fix_all_) {
        for (Index r = 0; r < Index(state_->scalar_size()); ++r) rows.push_back(r);
        return true;
    }
    for (const Index i : read_indices())
        for (Index c = 0; c < d; ++c) rows.push_back(d * i + c);
    return true;
}

void FixedProjectiveConstraint::project_velocity() {
    if (!project_velocity_) return;  // FixedProjectiveConstraint::projectVelocity: d_projectVelocity
    FlatVector v = state_->velocity_flat();
    project_response(v);
}

}  // namespace penalty
