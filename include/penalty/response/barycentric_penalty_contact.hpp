#pragma once
/// @file
/// BarycentricPenaltyContact: the persistent contact object of one model pair (SOFA's
/// BarycentricPenalityContact<M1, M2>, spec §7). Each step it turns the pair's detection outputs
/// into springs of one PenaltyForceField between the contact points of two contact mappers.
///
/// Per kept output i (after SOFA's per-id deduplication, ContactTracker):
///   d0   = C_intersection + contactDistance(model1) + contactDistance(model2)      (m)
///   dist = d0 + r1 + r2     (r from the mappers: Vec3 sphere radius, rigid sphere radius in
///                            SOFA HEAD, else 0)                                     (m)
///   ks   = k1·k2, divided by dist when dist ≠ 0 (exact comparison)     (SOFA law, "N/m")
///        = k1·k2/(k1 + k2), 0 when k1 + k2 = 0            (physical law, opt-in, k in N/m)
///   mu_s = mu_v = contactFriction(model1) + contactFriction(model2)
///   spring between contact point m1 (mapper 1) and m2 (mapper 2), normal from model 1 to
///   model 2, old_index from the tracker so that age and friction history carry over.
///
/// Embedding: call set_detection_outputs() once per step after detection, then evaluate the
/// forces on the parents with add_force() (explicit) or hand force_field() and the mappers to a
/// solver (see simulation/contact_pipeline.hpp for the scene-graph version).

#include "penalty/collision/collision_model.hpp"
#include "penalty/collision/detection_output.hpp"
#include "penalty/response/contact_mapper.hpp"
#include "penalty/response/contact_tracker.hpp"
#include "penalty/response/penalty_force_field.hpp"

#include <memory>
#include <span>
#include <vector>

namespace penalty {

/// How the per-model contact stiffnesses combine.
enum class StiffnessLaw : std::uint8_t {
    sofa,      ///< default: ks = k1·k2/dist (k1·k2 when dist = 0); k has no physical unit
    physical,  ///< beyond SOFA: k1, k2 in N/m in series, ks = k1·k2/(k1 + k2), independent of dist
};

/// Parameters of the penalty response (the defaults reproduce SOFA HEAD).
struct ContactResponseParameters {
    PenaltyParameters penalty;  ///< damping, friction (beyond SOFA, off by default)
    StiffnessLaw stiffness_law = StiffnessLaw::sofa;
    RigidSphereRadius rigid_sphere_radius = RigidSphereRadius::sofa_head;

    /// Throws std::invalid_argument naming the parameter.
    void validate() const;
};

/// Spring stiffness of a contact (see the file comment); throws for negative or non-finite k.
[[nodiscard]] double combined_contact_stiffness(StiffnessLaw law, double k1, double k2, double dist);

/// combined_contact_stiffness for k1, k2 already checked (finite, ≥ 0): physical k1·k2/(k1 + k2)
/// (0 if both are 0); SOFA's k1·k2/dist, or k1·k2 when dist is exactly 0 (§14.9).
[[nodiscard]] inline double combined_contact_stiffness_of_checked(StiffnessLaw law, double k1, double k2, double dist) {
    if (law == StiffnessLaw::physical) {
        const double s = k1 + k2;
        return s == 0.0 ? 0.0 : k1 * k2 / s;
    }
    double ks = k1 * k2;
    if (dist != 0.0) ks /= dist;
    return ks;
}

/// Contact time scale sqrt(m/ks) (s) of a spring ks (N/m) between masses m1, m2 (kg): m is the
/// reduced mass m1·m2/(m1 + m2) (an infinite mass = a static side: m = the other mass).
/// An explicit (symplectic Euler) step is stable for h < 2·sqrt(m/ks); for accuracy take h of
/// about a tenth of sqrt(m/ks). Returns +inf when ks = 0.
[[nodiscard]] double contact_critical_time_step(double ks, double m1, double m2);

class BarycentricPenaltyContact {
public:
    /// `intersection_contact_distance`: the intersection method's contactDistance C (m; 0 for
    /// Discrete). The models are not owned and must outlive the contact; (model1, model2) in the
    /// intersector's registered order (as in the DetectionOutputs).
    BarycentricPenaltyContact(const CollisionModel& model1, const CollisionModel& model2,
                              double intersection_contact_distance, const ContactResponseParameters& parameters = {});

    /// SOFA's setDetectionOutputs (§7.1): deduplicates, rebuilds the spring list (clear, then
    /// add_contact per kept output with its old_index) and updates the contact points.
    /// Throws std::invalid_argument naming the model and element for an element out of range.
    void set_detection_outputs(std::span<const DetectionOutput> outputs);

    /// Recomputes contact-point positions/velocities from the parent states (weights frozen).
    void update_contact_points();

    /// Explicit evaluation at the current parent state: update_contact_points(), then
    /// parent_f1 += J1ᵀ f1, parent_f2 += J2ᵀ f2 with (f1, f2) the spring forces on the contact
    /// points (flat parent vectors, see contact_mapper.hpp; they may alias when both models
    /// share a state).
    void add_force(std::span<double> parent_f1, std::span<double> parent_f2);
    /// parent_df += Jᵀ (k_factor·K + b_factor·B) J dq with the active set of the last add_force.
    void add_dforce(std::span<double> parent_df1, std::span<double> parent_df2, std::span<const double> parent_dq1,
                    std::span<const double> parent_dq2, double k_factor, double b_factor = 0.0);

    [[nodiscard]] const CollisionModel& model1() const { return *model1_; }
    [[nodiscard]] const CollisionModel& model2() const { return *model2_; }
    [[nodiscard]] ContactMapper& mapper1() { return *mapper1_; }
    [[nodiscard]] ContactMapper& mapper2() { return *mapper2_; }
    [[nodiscard]] const ContactMapper& mapper1() const { return *mapper1_; }
    [[nodiscard]] const ContactMapper& mapper2() const { return *mapper2_; }
    [[nodiscard]] PenaltyForceField& force_field() { return field_; }
    [[nodiscard]] const PenaltyForceField& force_field() const { return field_; }
    [[nodiscard]] const ContactTracker& tracker() const { return tracker_; }
    [[nodiscard]] const ContactResponseParameters& parameters() const { return parameters_; }
    [[nodiscard]] double intersection_contact_distance() const { return intersection_cd_; }
    /// Contact spring forces on the contact points of the last add_force (N).
    [[nodiscard]] ConstVec3Span contact_forces1() const { return f1_; }
    [[nodiscard]] ConstVec3Span contact_forces2() const { return f2_; }
    /// Largest ks of the current springs (N/m under the physical law), 0 without contact.
    [[nodiscard]] double max_stiffness() const;

private:
    const CollisionModel* model1_;
    const CollisionModel* model2_;
    double intersection_cd_;
    ContactResponseParameters parameters_;
    std::unique_ptr<ContactMapper> mapper1_;
    std::unique_ptr<ContactMapper> mapper2_;
    PenaltyForceField field_;
    ContactTracker tracker_;
    std::vector<Vec3> f1_, f2_, dx1_, dx2_, df1_, df2_;  // scratch on the contact points
};

}  // namespace penalty
