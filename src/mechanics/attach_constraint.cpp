#include "penalty/mechanics/attach_constraint.hpp"

#include "penalty/mechanics/projective_constraints.hpp"
#include "sofa_vector_ops.hpp"

#include <cmath>

namespace penalty {

template <class DataTypes>
AttachProjectiveConstraint<DataTypes>::AttachProjectiveConstraint(MechanicalObject<DataTypes>& object1,
                                                                  MechanicalObject<DataTypes>& object2,
                                                                  AttachParameters p)
    : object1_(&object1), object2_(&object2), p_(std::move(p)) {}

template <class DataTypes>
void AttachProjectiveConstraint<DataTypes>::init() {
    check_constraint_indices("AttachProjectiveConstraint (indices1)", p_.indices1, object1_->num_dofs());
    check_constraint_indices("AttachProjectiveConstraint (indices2)", p_.indices2, object2_->num_dofs());
    if (p_.two_way && object1_ != object2_)
        throw_invalid_argument(
            "AttachProjectiveConstraint: twoWay needs object1 and object2 to be the same state in penalty");
    if (!p_.constraint_factor.empty() && p_.constraint_factor.size() < pairs())
        throw_invalid_argument("AttachProjectiveConstraint: constraintFactor has ", p_.constraint_factor.size(),
                               " values for ", pairs(), " pairs");
    released_.assign(p_.indices2.size(), 0);
}

template <class DataTypes>
std::size_t AttachProjectiveConstraint<DataTypes>::pairs_past_end() const {
    std::size_t n = 0;
    for (std::size_t k = 0; k < pairs(); ++k) n += in_range(k) ? 0 : 1;
    return n;
}

namespace {

double sofa_distance(const Vec3& a, const Vec3& b) {
    const Vec3 d = a - b;
    return std::sqrt(sofa_vec::dot3(d, d));
}

}  // namespace

// AttachProjectiveConstraint::projectPosition, doProjectPosition per pair.
template <>
void AttachProjectiveConstraint<Vec3Types>::project_position() {
    for (std::size_t k = 0; k < pairs(); ++k) {
        if (!in_range(k)) continue;
        const Vec3 x1 = object1_->position[static_cast<std::size_t>(p_.indices1[k])];
        Vec3& x2 = object2_->position[static_cast<std::size_t>(p_.indices2[k])];
        if (p_.min_distance != -1 && sofa_distance(x2, x1) > p_.min_distance) {
            released_[k] = 1;
            continue;
        }
        released_[k] = 0;
        const Vec3 corr = (x2 - x1) * (0.5 * p_.position_factor * factor(k));
        x2 -= corr;
    }
}

template <>
void AttachProjectiveConstraint<Rigid3Types>::project_position() {
    for (std::size_t k = 0; k < pairs(); ++k) {
        if (!in_range(k)) continue;
        const RigidFrame x1 = object1_->position[static_cast<std::size_t>(p_.indices1[k])];
        RigidFrame& x2 = object2_->position[static_cast<std::size_t>(p_.indices2[k])];
        if (p_.min_distance != -1.0 && sofa_distance(x2.center, x1.center) > p_.min_distance) {
            released_[k] = 1;
            continue;
        }
        released_[k] = 0;
        x2.center = x1.center;
        if (!p_.free_rotations) x2.orientation = x1.orientation;
    }
}

template <>
void AttachProjectiveConstraint<Vec3Types>::project_velocity() {
    for (std::size_t k = 0; k < pairs(); ++k) {
        if (released_[k] || !in_range(k)) continue;
        Vec3& v1 = object1_->velocity[static_cast<std::size_t>(p_.indices1[k])];
        Vec3& v2 = object2_->velocity[static_cast<std::size_t>(p_.indices2[k])];
        const Vec3 corr = (v2 - v1) * (0.5 * p_.velocity_factor * factor(k));
        v1 += corr;
        v2 -= corr;
    }
}

template <>
void AttachProjectiveConstraint<Rigid3Types>::project_velocity() {
    for (std::size_t k = 0; k < pairs(); ++k) {
        if (released_[k] || !in_range(k)) continue;
        const RigidDeriv& v1 = object1_->velocity[static_cast<std::size_t>(p_.indices1[k])];
        RigidDeriv& v2 = object2_->velocity[static_cast<std::size_t>(p_.indices2[k])];
        v2.linear = v1.linear;
        if (!p_.free_rotations) v2.angular = v1.angular;
    }
}

template <>
void AttachProjectiveConstraint<Vec3Types>::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    const std::span<Vec3> r = as_derivs<Vec3Types>(v);  // object2's (the same state as object1 with twoWay)
    for (std::size_t k = 0; k < pairs(); ++k) {
        if (released_[k] || !in_range(k)) continue;
        Vec3& r2 = r[static_cast<std::size_t>(p_.indices2[k])];
        if (!p_.two_way) {
            r2 = Vec3::Zero();
            continue;
        }
        Vec3& r1 = r[static_cast<std::size_t>(p_.indices1[k])];
        const Vec3 corr = (((r2 - r1) * 0.5) * p_.response_factor) * factor(k);
        r1 += corr;
        r2 -= corr;
    }
}

template <>
void AttachProjectiveConstraint<Rigid3Types>::project_response(Eigen::Ref<Eigen::VectorXd> v) const {
    const std::span<RigidDeriv> r = as_derivs<Rigid3Types>(v);
    for (std::size_t k = 0; k < pairs(); ++k) {
        if (released_[k] || !in_range(k)) continue;
        RigidDeriv& r2 = r[static_cast<std::size_t>(p_.indices2[k])];
        if (!p_.two_way) {
            if (!p_.free_rotations) r2 = RigidDeriv{};
            else r2.linear = Vec3::Zero();
            continue;
        }
        RigidDeriv& r1 = r[static_cast<std::size_t>(p_.indices1[k])];
        r1.linear += r2.linear;
        r2.linear = r1.linear;
        if (!p_.free_rotations) {
            r1.angular += r2.angular;
            r2.angular = r1.angular;
        }
    }
}

// AttachProjectiveConstraint::applyConstraint(ZeroDirichletCondition*): one-way only; every index
// of indices2 (not only the paired ones).
template <class DataTypes>
bool AttachProjectiveConstraint<DataTypes>::list_discarded_rows(std::vector<Index>& rows) const {
    if (p_.two_way) return true;  // no rows: SOFA discards none
    const Index width = DataTypes::kDerivSize;
    const Index constrained = (width == 6 && p_.free_rotations) ? 3 : width;
    for (Index i : p_.indices2)
        if (std::size_t(i) < object2_->num_dofs())  // past the end after a topological change: nothing
            for (Index c = 0; c < constrained; ++c) rows.push_back(width * i + c);
    return true;
}

template class AttachProjectiveConstraint<Vec3Types>;
template class AttachProjectiveConstraint<Rigid3Types>;

}  // namespace penalty
