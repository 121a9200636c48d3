#pragma once
/// @file
/// SpringForceField<Rigid3> (SOFA's SpringForceField.cpp instantiates SpringForceField for Rigid3):
/// the springs of penalty::SpringForceField between the CENTRES of Rigid3d frames. For a spring
/// (a, b) with centres c_a, c_b: u = c_b − c_a, d = |u|, û = u/d, F = ks (d − L) + kd (v_b − v_a)·û
/// (linear velocities), force +F û on a's linear part, −F û on b's (no torque: SOFA's
/// computeSpringForce uses DataTypes::getCPos / getDPos / setDPos); springs with d <= 1e-9 give
/// nothing. Stiffness on the linear blocks, linearised at add_force:
///   m = (ks − F/d) ûûᵀ + (F/d) I,  df_a = m·(dx_b − dx_a)·k, df_b = −df_a (SOFA's sign).
/// Damping is explicit only (SOFA's addDForce ignores bFactor). Energy ½ ks (d − L)².

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include <vector>

namespace penalty {

class RigidSpringForceField final : public BaseForceField {
public:
    /// Springs between frames of `state1` (Spring::a) and `state2` (Spring::b); the same state twice
    /// for springs inside one.
    RigidSpringForceField(Rigid3Object& state1, Rigid3Object& state2, std::vector<Spring> springs);
    [[nodiscard]] bool sofa_interaction() const override { return true; }  // SpringForceField<Rigid3>
    /// Checks the indices against the states and the coefficients (finite, >= 0).
    void init() override;
    void accumulate_force() override;
    void accumulate_dforce(double k_factor, double b_factor) override;
    void add_stiffness(TripletList& triplets, const StateOffsets& offsets, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] ForceFieldStates states() const override;
    [[nodiscard]] const std::vector<Spring>& springs() const { return springs_; }

private:
    Rigid3Object* s1_;
    Rigid3Object* s2_;
    std::vector<Spring> springs_;
    std::vector<Mat3> dfdx_;  ///< m per spring, from the last accumulate_force (0: no force)
    double energy_ = 0.0;
};

}  // namespace penalty
