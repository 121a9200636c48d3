#pragma once
/// @file
/// SOFA's AttachProjectiveConstraint (Vec3d, Rigid3d): DOF indices2[k] of object2 follows DOF
/// indices1[k] of object1 (pairs up to the shorter list). Per pair, as SOFA's doProject* methods:
///   Vec3d position:  x2 ← x2 − (x2 − x1)·½·positionFactor·c_k (x1 is not written: SOFA corrects a
///                    copy of it, so x2 goes half way each projection);
///   Vec3d velocity:  corr = (v2 − v1)·½·velocityFactor·c_k; v1 += corr, v2 −= corr (both);
///   Vec3d response:  one-way: r2 = 0; twoWay: corr = (r2 − r1)·½·responseFactor·c_k, r1 += corr,
///                    r2 −= corr;
///   Rigid3d:         x2 = x1 (centre; orientation too unless freeRotations), v2 = v1 (likewise),
///                    response one-way r2 = 0 (linear part only with freeRotations), twoWay
///                    r1 += r2, r2 = r1 (the factors are not read);
/// c_k = constraintFactor[k] (1 when empty). With minDistance ≠ −1 a pair farther apart than it at
/// a position projection is released (left alone) until a later projection finds it closer.
/// An assembled system discards the rows of indices2 (one-way only): 3 per Vec3d DOF; 6, or 3
/// with freeRotations, per Rigid3d DOF.
///
/// penalty projects a solver's vectors one state at a time (SubtreeSystem::project): object1 and
/// object2 must be the same state when twoWay is set.
///
/// Topological changes: SOFA's indices1 and indices2 get no topology handler (init creates none):
/// they keep their values, each naming the point now at its index. A pair whose index is past its
/// state's end after a change (SOFA HEAD reads and writes past the state's vectors) acts on nothing.

#include "penalty/mechanics/force_field.hpp"

#include <vector>

namespace penalty {

struct AttachParameters {
    std::vector<Index> indices1, indices2;
    bool two_way = false;
    bool free_rotations = false;
    double min_distance = -1;  ///< −1: never released
    double position_factor = 1, velocity_factor = 1, response_factor = 1;
    std::vector<double> constraint_factor;  ///< per pair, or empty (all 1)
};

template <class DataTypes>
class AttachProjectiveConstraint final : public BaseProjectiveConstraint {
public:
    AttachProjectiveConstraint(MechanicalObject<DataTypes>& object1, MechanicalObject<DataTypes>& object2,
                               AttachParameters p);
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override;
    void project_position() override;
    [[nodiscard]] bool projects_positions() const override { return true; }
    [[nodiscard]] bool list_discarded_rows(std::vector<Index>& rows) const override;
    /// object2, whose responses it projects (object1 too when it is the same state).
    [[nodiscard]] BaseState* state() const override { return object2_; }
    [[nodiscard]] std::size_t pairs() const { return std::min(p_.indices1.size(), p_.indices2.size()); }
    [[nodiscard]] bool released(std::size_t pair) const { return released_[pair] != 0; }
    [[nodiscard]] BaseState* object1() const { return object1_; }
    /// Pairs with an index past its state's end (after a topological change), which act on nothing.
    [[nodiscard]] std::size_t pairs_past_end() const;

private:
    /// Both indices of pair k within their states.
    [[nodiscard]] bool in_range(std::size_t k) const {
        return std::size_t(p_.indices1[k]) < object1_->num_dofs() && std::size_t(p_.indices2[k]) < object2_->num_dofs();
    }
    [[nodiscard]] double factor(std::size_t pair) const {
        return p_.constraint_factor.empty() ? 1.0 : p_.constraint_factor[pair];
    }
    MechanicalObject<DataTypes>* object1_;
    MechanicalObject<DataTypes>* object2_;
    AttachParameters p_;
    std::vector<char> released_;  ///< SOFA's constraintReleased, per pair
};

template <>
void AttachProjectiveConstraint<Vec3Types>::project_position();
template <>
void AttachProjectiveConstraint<Rigid3Types>::project_position();
template <>
void AttachProjectiveConstraint<Vec3Types>::project_velocity();
template <>
void AttachProjectiveConstraint<Rigid3Types>::project_velocity();
template <>
void AttachProjectiveConstraint<Vec3Types>::project_response(Eigen::Ref<Eigen::VectorXd>) const;
template <>
void AttachProjectiveConstraint<Rigid3Types>::project_response(Eigen::Ref<Eigen::VectorXd>) const;
extern template class AttachProjectiveConstraint<Vec3Types>;
extern template class AttachProjectiveConstraint<Rigid3Types>;

}  // namespace penalty
