#pragma once
/// @file
/// SOFA's InteractionEllipsoidForceField<Vec3d, Rigid3d>: ellipsoids carried by a frame of a Rigid3d
/// state (object 2) that push the points of a Vec3d state (object 1) out (stiffness > 0) or hold
/// them in (stiffness < 0).
///
/// Per point x, in the frame's local coordinates p = q⁻¹·(x − c) (c, q: the frame's center and
/// orientation, or those of its inverse with object2_invert), with per ellipsoid e a center cₑ
/// and radii rₑ (InteractionEllipsoidForceField::calcF):
///   n²ₑ = Σⱼ (p − cₑ)ⱼ²/rₑⱼ²; the ellipsoid of least n² acts, when (n² − 1)·stiffness < 0;
///   v = n − 1 (n = √n²), g = (p − cₑ) ⊘ r², f_local = −|k|·v·g/|g| − d·|v|·(q⁻¹·v₁)
///   (k: stiffness, N; d: damping, N·s/m; the frame's own velocity is ignored, as SOFA);
///   f on the point = q·f_local; the frame's linear force gets −f when object2_forces (no torque,
///   as SOFA: its torque line is commented out).
/// Stiffness (addDForce): df₁ = k_factor·q·(M·q⁻¹·(dx₁ − dx₂,linear)), df₂,linear = −Σ df₁, with
/// M(i, j) = gᵢgⱼ(α + β/r²ⱼ) + δᵢⱼ·γ/r²ᵢ, α = −|k|/(n|g|), γ = −|k|v/|g| and SOFA's
/// β = −|k|v/|g|² (its sign and power are a SOFA bug: the derivative of f has β = +|k|v/|g|³;
/// reproduced by default, fixed by set_exact_stiffness(true)). The damping term has no matrix
/// (SOFA's buildDampingMatrix is empty). SOFA reports no potential energy (0 here too: f is not a
/// gradient unless the ellipsoid is a sphere).

#include "penalty/mechanics/force_field.hpp"

#include <vector>

namespace penalty {

struct InteractionEllipsoidParameters {
    std::vector<Vec3> centers{};  ///< cₑ in the frame's local coordinates (m); empty: one at 0
    std::vector<Vec3> radii{};    ///< rₑ (m, non-zero); missing ones repeat the last (none: 1)
    double stiffness = 500.0;     ///< k (N): > 0 pushes out, < 0 holds in
    double damping = 5.0;         ///< d (N·s/m)
    Index frame_index = 0;        ///< object2_dof_index
    bool object2_forces = true;   ///< the frame receives the opposite linear force
    bool object2_invert = false;  ///< the inverse of the frame is used
};

class InteractionEllipsoidForceField final : public BaseForceField {
public:
    /// Throws std::invalid_argument for a zero or non-finite radius, a non-finite value or a
    /// frame index out of the Rigid3d state (checked at init()).
    InteractionEllipsoidForceField(Vec3Object& points, Rigid3Object& frames, InteractionEllipsoidParameters parameters);
    [[nodiscard]] bool sofa_interaction() const override { return true; }  // MixedInteractionForceField

    void init() override;
    void accumulate_force() override;
    void accumulate_dforce(double k_factor, double b_factor) override;
    void add_stiffness(TripletList& triplets, const StateOffsets& offsets, double factor) const override;
    /// Object 1 alone when object2_forces is false (the frame is then only read).
    [[nodiscard]] ForceFieldStates states() const override;
    void list_read_states(std::vector<const BaseState*>& out) const override;

    /// true: the exact derivative of f (β = +|k|v/|g|³) instead of SOFA's matrix.
    void set_exact_stiffness(bool exact) { exact_stiffness_ = exact; }
    [[nodiscard]] const InteractionEllipsoidParameters& parameters() const { return parameters_; }
    /// Points inside (or outside, k < 0) an ellipsoid at the last accumulate_force.
    [[nodiscard]] std::size_t contact_count() const { return contacts_.size(); }

private:
    struct Contact {
        Index point = 0;
        Mat3 local_stiffness;  ///< M, in the frame's local axes
    };
    /// calcF: the local force and M of a local point p with local velocity v; false: no contact.
    bool local_force(const Vec3& p, const Vec3& v, Vec3& force, Mat3& stiffness) const;
    [[nodiscard]] RigidFrame frame() const;

    Vec3Object* points_;
    Rigid3Object* frames_;
    InteractionEllipsoidParameters parameters_;
    std::vector<Vec3> inverse_radii2_;  ///< 1/rₑ² per ellipsoid
    std::vector<Contact> contacts_;
    Quat orientation_ = Quat::Identity();  ///< the frame's q at the last accumulate_force
    bool exact_stiffness_ = false;
};

}  // namespace penalty
