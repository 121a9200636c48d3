#include "penalty/mechanics/projective_constraints.hpp"

#include "sofa_vector_ops.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

using sofa_vec::dot3;

void check_constraint_indices(const char* component, std::span<const Index> indices, std::size_t dofs) {
    for (Index i : indices)
        if (i < 0 || static_cast<std::size_t>(i) >= dofs)
            throw_invalid_argument(component, ": index ", i, " out of range (", dofs, " DOFs)");
}

namespace {

/// v·(1/|v|) per component (type::Vec::operator*=(1/norm)), |v| = √(v·v).
Vec3 scaled_by_inverse_norm(const Vec3& v) {
    const double inverse = 1 / std::sqrt(dot3(v, v));
    return {v[0] * inverse, v[1] * inverse, v[2] * inverse};
}

/// Row r of P·u as SOFA's sparse product sums it: P(r,0)u₀ + P(r,1)u₁ + P(r,2)u₂.
Vec3 block_times(const Mat3& p, const Vec3& u) { return sofa_vec::times(p, u); }

}  // namespace

// ---- Line, Plane, Direction -------------------------------------------------------------------
// LineProjectiveConstraint::updateJacobian (PlaneProjectiveConstraint::reinit,
// DirectionProjectiveConstraint::reinit): the block of each constrained point on the diagonal of
// a jacobian filled from the sorted indices, identity elsewhere.
void BlockProjectionConstraint::init() {
    check_constraint_indices(component_, indices_, state_->num_dofs());
    make_block();
    std::vector<Index> sorted = indices_;
    std::sort(sorted.begin(), sorted.end());
    projected_.clear();
    std::size_t next = 0;
    for (std::size_t i = 0; i < state_->num_dofs(); ++i)
        if (next < sorted.size() && static_cast<Index>(i) == sorted[next]) {
            projected_.push_back(static_cast<Index>(i));
            ++next;  // a repeated index never matches again: the points after it stay identity
        }
}

void BlockProjectionConstraint::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    const std::span<Vec3> u = as_derivs<Vec3Types>(v);
    for (Index i : projected_)  // (a point past the end: a projection kept over a topological change)
        if (static_cast<std::size_t>(i) < u.size())
            u[static_cast<std::size_t>(i)] = block_times(block_, u[static_cast<std::size_t>(i)]);
}

void BlockProjectionConstraint::project_velocity() { project_response(Vec3Object::flat(state_->velocity)); }

void LineProjectiveConstraint::make_block() {
    n_ = direction_;
    if (std::sqrt(dot3(n_, n_)) == 0) n_[0] = 1;
    else n_ = scaled_by_inverse_norm(n_);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) block_(r, c) = n_[r] * n_[c];
}

// LineProjectiveConstraint::projectPosition: x ← o + n ((x − o)·n).
void LineProjectiveConstraint::project_position() {
    for (Index i : indices_) {
        Vec3& x = state_->position[static_cast<std::size_t>(i)];
        const double along = dot3(x - origin_, n_);
        x = Vec3(origin_[0] + n_[0] * along, origin_[1] + n_[1] * along, origin_[2] + n_[2] * along);
    }
}

void PlaneProjectiveConstraint::make_block() {
    n_ = normal_;
    if (std::sqrt(dot3(n_, n_)) == 0) n_[1] = 0;  // SOFA's "arbitrary normal" leaves it zero
    else n_ = scaled_by_inverse_norm(n_);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) block_(r, c) = r == c ? 1 - n_[r] * n_[c] : -n_[r] * n_[c];
}

// PlaneProjectiveConstraint::projectPosition: x ← x − n ((x − o)·n).
void PlaneProjectiveConstraint::project_position() {
    for (Index i : indices_) {
        Vec3& x = state_->position[static_cast<std::size_t>(i)];
        const double off = dot3(x - origin_, n_);
        x = Vec3(x[0] - n_[0] * off, x[1] - n_[1] * off, x[2] - n_[2] * off);
    }
}

void DirectionProjectiveConstraint::make_block() {
    n_ = direction_;
    if (std::sqrt(dot3(n_, n_)) == 0) n_[1] = 0;
    else n_ = scaled_by_inverse_norm(n_);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) block_(r, c) = n_[r] * n_[c];
    if (following_topology_) return;  // m_origin is not a topology data: kept as at init
    origins_.clear();
    for (Index i : indices_) origins_.push_back(state_->position[static_cast<std::size_t>(i)]);
}

// DirectionProjectiveConstraint::projectPosition: x_k ← o_k + n ((x_k − o_k)·n).
void DirectionProjectiveConstraint::project_position() {
    for (std::size_t k = 0; k < indices_.size(); ++k) {
        Vec3& x = state_->position[static_cast<std::size_t>(indices_[k])];
        const Vec3& o = origins_[k];
        const double along = dot3(x - o, n_);
        x = Vec3(o[0] + n_[0] * along, o[1] + n_[1] * along, o[2] + n_[2] * along);
    }
}

// ---- Point ------------------------------------------------------------------------------------
void PointProjectiveConstraint::init() {
    check_constraint_indices("PointProjectiveConstraint", indices_, state_->num_dofs());
}

void PointProjectiveConstraint::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    const std::span<Vec3> u = as_derivs<Vec3Types>(v);
    if (fix_all_) std::fill(u.begin(), u.end(), Vec3::Zero());
    else
        for (Index i : indices_) u[static_cast<std::size_t>(i)] = Vec3::Zero();
}

void PointProjectiveConstraint::project_velocity() { project_response(Vec3Object::flat(state_->velocity)); }

void PointProjectiveConstraint::project_position() {
    if (fix_all_) std::fill(state_->position.begin(), state_->position.end(), point_);
    else
        for (Index i : indices_) state_->position[static_cast<std::size_t>(i)] = point_;
}

// PointProjectiveConstraint::applyConstraint(ZeroDirichletCondition*): the listed indices only,
// fixAll or not.
bool PointProjectiveConstraint::list_discarded_rows(std::vector<Index>& rows) const {
    for (Index i : indices_)
        for (Index c = 0; c < 3; ++c) rows.push_back(3 * i + c);
    return true;
}

// ---- PartialFixed -----------------------------------------------------------------------------
void PartialFixedProjectiveConstraint::init() {
    check_constraint_indices("PartialFixedProjectiveConstraint", indices_, state_->num_dofs());
    if (fixed_.size() != static_cast<std::size_t>(state_->deriv_size()))
        throw_invalid_argument("PartialFixedProjectiveConstraint: fixedDirections needs ", state_->deriv_size(),
                               " flags, got ", fixed_.size());
}

namespace {
void clear_fixed_components(Eigen::Ref<Eigen::VectorXd> v, Index dof, int width, const std::vector<bool>& fixed) {
    for (int c = 0; c < width; ++c)
        if (fixed[static_cast<std::size_t>(c)]) v[dof * width + c] = 0.0;
}
}  // namespace

void PartialFixedProjectiveConstraint::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    const int width = state_->deriv_size();
    if (fix_all_) {
        for (Index i = 0; i < static_cast<Index>(v.size() / width); ++i) clear_fixed_components(v, i, width, fixed_);
    } else {
        for (Index i : follow(indices_)) clear_fixed_components(v, i, width, fixed_);
    }
}

void PartialFixedProjectiveConstraint::project_velocity() {
    if (project_velocity_) project_response(state_->velocity_flat());
}

bool PartialFixedProjectiveConstraint::list_discarded_rows(std::vector<Index>& rows) const {
    const int width = state_->deriv_size();
    const auto append = [&](Index i) {
        for (int c = 0; c < width; ++c)
            if (fixed_[static_cast<std::size_t>(c)]) rows.push_back(i * width + c);
    };
    if (fix_all_)
        for (Index i = 0; i < static_cast<Index>(state_->num_dofs()); ++i) append(i);
    else
        for (Index i : follow(indices_)) append(i);
    return true;
}

}  // namespace penalty
