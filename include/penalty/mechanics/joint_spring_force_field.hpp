#pragma once
/// @file
/// SOFA's JointSpringForceField<Rigid3d>: springs between two frames m1 (of state 1) and m2 (of
/// state 2, possibly the same state) that hold their relative translation and rotation, with a
/// soft or hard stiffness per axis and angular limits.
///
/// Per spring, in the frame of m1 (ref = q1; JointSpringForceField::addSpringForce):
///   d = (c2 − c1) − initTrans, q = normalize((q1⁻¹ ⊗ q2) ⊗ initRot), torsion θ = axis·angle of q
///   (quatToAxis, the angle brought into [−π, π]);
///   KT_i = soft (free axis i) or hard translation stiffness, KR_i likewise for rotations;
///   force on m1:  F = ref·(KT ⊙ ref⁻¹·d) + kd·(v2 − v1)  (m2 gets −F);
///   torque on m1: T = ref·τ + kd·(ω2 − ω1), τ_i = KR_i·θ_i (no free rotation, or a free one
///   inside its limits), pivot cases about one free axis (SOFA's "pivot /x /y /z": the two
///   locked components from the rotated axis), and past a limit the bloc stiffness times the
///   rotation beyond the nearest limit (projectTorsion).
/// Stiffness (addSpringDForce): dF = ref·(KT ⊙ ref⁻¹·(dx2 − dx1)), dT likewise with KR, both as
/// SOFA (the rotation of ref with dx1 is not differentiated: K is SOFA's, exact for the
/// translations and at zero torsion, approximate elsewhere); no damping matrix (SOFA's
/// buildDampingMatrix is empty: kd acts explicitly). Units: N/m, N·m/rad, N·s/m.

#include "penalty/mechanics/force_field.hpp"

#include <array>
#include <string_view>
#include <vector>

namespace penalty {

struct JointSpring {
    Index m1 = 0, m2 = 0;
    double kd = 0;                                                              ///< damping (N·s/m and N·m·s/rad)
    std::array<bool, 6> free_movements{false, false, false, true, true, true};  ///< tx ty tz rx ry rz
    double soft_translation = 0, hard_translation = 10000;
    double soft_rotation = 0, hard_rotation = 10000;
    double bloc_rotation = 100;  ///< past a limit (default hard_rotation/100)
    std::array<double, 6> limit_angles{-100000., 100000., -100000., 100000., -100000., 100000.};  ///< rad
    Vec3 init_trans = Vec3::Zero();    ///< rest offset c2 − c1 (m, world axes)
    Quat init_rot = Quat::Identity();  ///< rest rotation offset
    /// SOFA takes initTrans and initRot from the positions at init exactly when REST_T was
    /// written (JointSpring::operator>> sets needToInitialize* = REST_T found; reproduced).
    bool init_from_positions = false;

    // Set by each add_force (read by add_dforce), as SOFA's spring members.
    Quat ref = Quat::Identity();
    Vec3 torsion = Vec3::Zero(), lawful_torsion = Vec3::Zero();
    Vec3 kt = Vec3::Zero(), kr = Vec3::Zero();
};

/// Parses SOFA's `spring` text: `BEGIN_SPRING m1 m2 [FREE_AXIS 6 flags] [KS_T soft hard]
/// [KS_R soft hard] [KS_B bloc] [KD kd] [R_LIM_X min max] [R_LIM_Y ..] [R_LIM_Z ..]
/// [REST_T x y z] [REST_R qx qy qz qw] END_SPRING`, repeated. As SOFA's vector reading, the
/// springs are read into one object in turn: m1, m2, KS_T, KS_R and KD not written keep the
/// previous spring's values (the defaults for the first); the rest is reset per spring. A zero
/// KS_B becomes hard_rotation/100; equal limits lock that rotation. std::invalid_argument on an
/// unknown keyword or a malformed number.
[[nodiscard]] std::vector<JointSpring> parse_joint_springs(std::string_view text);

class JointSpringForceField final : public BaseForceField {
public:
    JointSpringForceField(Rigid3Object& state1, Rigid3Object& state2, std::vector<JointSpring> springs);
    [[nodiscard]] bool sofa_interaction() const override { return true; }  // PairInteractionForceField
    /// Checks the indices; takes the rest offsets from the positions where the spring asks
    /// (JointSpringForceField::bwdInit).
    void init() override;
    void accumulate_force() override;
    void accumulate_dforce(double k_factor, double b_factor) override;
    void add_stiffness(TripletList& triplets, const StateOffsets& offsets, double factor) const override;
    /// ½ Σ KT_i (ref⁻¹·d)_i² + ½ Σ KR_i θ_i² at the last accumulate_force (J): the spring's
    /// energy where F and T derive from it (translations; rotations at small torsion). SOFA
    /// reports 0.
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] ForceFieldStates states() const override;
    [[nodiscard]] const std::vector<JointSpring>& springs() const { return springs_; }

    /// The force and torque on m1 of spring `s` at the given frames and velocities (m2 gets the
    /// opposite); updates the spring's ref, torsion and stiffness like add_force.
    static RigidDeriv spring_force(JointSpring& s, const RigidFrame& x1, const RigidFrame& x2, const RigidDeriv& v1,
                                   const RigidDeriv& v2, double& energy);

private:
    Rigid3Object* s1_;
    Rigid3Object* s2_;
    std::vector<JointSpring> springs_;
    double energy_ = 0;
};

}  // namespace penalty
