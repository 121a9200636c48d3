#pragma once
/// @file
/// PenaltyForceField: unilateral linear springs between contact points of two states
/// (SOFA's PenalityContactForceField<Vec3>, spec §9), plus opt-in normal damping and Coulomb
/// friction with a persistent tangential spring.
///
/// Conventions (one contact, DOF m1 of state 1 and DOF m2 of state 2):
///   n            unit normal, from side 1 toward side 2
///   u  = x2[m2] − x1[m1]                    relative position (m)
///   pen = dist − u·n                        penetration (m); the contact is active when pen > 0
///   f2[m2] += ks·pen·n,  f1[m1] −= ks·pen·n (N): pushes side 2 along +n, side 1 along −n
///   E   = ½·ks·pen²                         stored energy (J), f = −∂E/∂x
///   K   = ∂f/∂x (SOFA's sign: negative semi-definite); with K_c = ks·n·nᵀ the blocks are
///         (m1,m1): −K_c  (m1,m2): +K_c  (m2,m1): +K_c  (m2,m2): −K_c
/// The normal, dist and ks are frozen for the step; K treats n as constant, which is exact
/// because the force is linear in x for a fixed n.
///
/// Beyond SOFA, opt-in (PenaltyParameters); with the defaults every result is SOFA's:
///   damping c (N·s/m):  v_n = (v2[m2] − v1[m1])·n, f2 += −c·v_n·n while pen > 0,
///                       B = ∂f/∂v with blocks of −c·n·nᵀ as above;
///   Coulomb friction:   an elastic–perfectly-plastic tangential spring ξ (m, in the tangent
///                       plane, side 2 relative to side 1; Cundall–Strack), anchored when the
///                       contact becomes active, carried across steps through old_index,
///                       re-projected on the current tangent plane with its length kept.
///                       kt = tangential_stiffness_ratio·ks (N/m), f_s = −kt·ξ.
///                       Sticking while kt·|ξ| ≤ mu·|f_n| (mu = mu_s, or mu_v if the contact slid
///                       the step before): f_t2 = f_s − α·c_t·v_t, the damper scaled by
///                       α ∈ [0, 1] so that |f_t2| ≤ mu·|f_n|.
///                       Sliding otherwise: ξ is cut back to kt·|ξ| = mu_v·|f_n| (the anchor moves,
///                       the released spring energy is dissipated) and f_t2 = −kt·ξ.
///                       Within a step ξ(x) = ξ₀ + P·(u − u₀), P = I − n·nᵀ, so while sticking
///                       the tangential force is −∂(½·kt·|ξ|²)/∂x and K gains −kt·P blocks.
///                       Between steps ξ₀ = rotate(ξ_prev) + h·P·(v2 − v1): the motion of the
///                       previous step, as in DEM granular-history models (LAMMPS, Chrono DEM).

#include "penalty/core/index_types.hpp"
#include "penalty/core/types.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace penalty {

/// Whether contactFriction / mu_s / mu_v act. SOFA's penalty response receives them and ignores
/// them (`ignored`, the default).
enum class FrictionModel : std::uint8_t {
    ignored,  ///< SOFA: no tangential force
    coulomb,  ///< static/dynamic Coulomb friction with a persistent tangential spring
};

/// Opt-in extensions; the defaults reproduce SOFA exactly.
struct PenaltyParameters {
    double damping = 0.0;  ///< c: normal viscous damping (N·s/m), ≥ 0
    FrictionModel friction = FrictionModel::ignored;
    double tangential_stiffness_ratio = 1.0;  ///< kt / ks (dimensionless), > 0 when friction acts
    double tangential_damping = 0.0;          ///< c_t: viscous damping of the sticking tangential
                                              ///< spring (N·s/m), ≥ 0: f_t2 += −c_t·P·(v2 − v1)
    double time_step = 0.01;                  ///< h (s), > 0: accumulates ξ and dissipated energy

    /// Throws std::invalid_argument naming the parameter.
    void validate() const;
};

/// State of the tangential spring of one contact after the last add_force.
enum class FrictionState : std::uint8_t { none, sticking, sliding };

/// One penalty spring. Plain data; fields document sign, frame and units.
/// The fields add_force reads and writes on SOFA's path come first (the first 80 bytes, two
/// cache lines), the friction history and bookkeeping after.
struct PenaltyContact {
    Index m1 = 0;                 ///< DOF in state 1 (contact point of model 1)
    Index m2 = 0;                 ///< DOF in state 2
    Vec3 normal = Vec3::UnitX();  ///< unit, from side 1 toward side 2 (world)
    double dist = 0.0;            ///< rest distance (m): the spring pushes while (x2 − x1)·n < dist
    double ks = 0.0;              ///< normal stiffness (N/m)
    double pen = 0.0;             ///< penetration dist − (x2 − x1)·n at the last add_force (m)
    double normal_force = 0.0;    ///< f_n = ks·pen − c·v_n on side 2 along n (N), 0 if inactive
    int age = 0;                  ///< steps this contact has persisted (0 = new)
    FrictionState friction_state = FrictionState::none;
    bool step_started = false;    ///< add_force ran since add_contact (per-step bookkeeping done)
    bool slid_last_step = false;  ///< the dynamic threshold applies (hysteresis)
    bool has_history = false;     ///< shear_start carries a previous step's spring

    Index index1 = 0;   ///< collision element of model 1 (export / grab only)
    Index index2 = 0;   ///< collision element of model 2
    double mu_s = 0.0;  ///< static friction coefficient (used only with FrictionModel::coulomb)
    double mu_v = 0.0;  ///< dynamic friction coefficient (idem)

    // --- beyond SOFA: set by add_force, carried by add_contact(old_index) -------------------
    Vec3 tangential_force = Vec3::Zero();  ///< friction force on side 2 (N), ⟂ n
    Vec3 shear = Vec3::Zero();             ///< ξ after the cap at the last add_force (m)
    double damper_scale = 1.0;             ///< α: share of the tangential damper applied while sticking
    Vec3 shear_start = Vec3::Zero();       ///< ξ₀ at the start of the step (m)
    Vec3 u_start = Vec3::Zero();           ///< u at the start of the step (m)
};

/// A contact drawn as a segment x1[m1] → x2[m2] (replaces SOFA's draw).
struct ContactSegment {
    Vec3 point1;  ///< x1[m1] (m)
    Vec3 point2;  ///< x2[m2] (m)
    Vec3 normal;  ///< from side 1 toward side 2
    double pen;   ///< dist − (x2 − x1)·n at these positions (m); > 0 pushes
    int age;
    Vec3 force;  ///< total force on side 2 (N) from the last add_force; −force on side 1
    Index index1, index2;
};

/// Result of a grab query: a point of the other side in contact with a grabbed DOF
/// (replaces SOFA's grabPoint).
struct GrabbedPoint {
    Vec3 position;         ///< current position of the other side's contact point (m)
    ElementIndex element;  ///< collision element on the other side
    DofIndex tool_dof;     ///< the grabbed DOF of the tool side
};

enum class ContactSide : std::uint8_t { first, second };

/// One active contact's product on SOFA's path (PenalityContactForceField::addDForce, SOFA's
/// operations in SOFA's order): dpen = −(dx2 − dx1)·n, dfN = ks·dpen·kFactor, df1 += −n·dfN,
/// df2 −= −n·dfN. PenaltyForceField::add_dforce and the solver's flat contact products both
/// call it.
inline void add_sofa_contact_dforce(const Vec3& n, double ks, const Vec3& dx1, const Vec3& dx2, double k_factor,
                                    Vec3& df1, Vec3& df2) {
    const Vec3 du = dx2 - dx1;
    const double dpen = -(du[0] * n[0] + du[1] * n[1] + du[2] * n[2]);
    const double dfn = ks * dpen * k_factor;
    const Vec3 dforce(-(n[0] * dfn), -(n[1] * dfn), -(n[2] * dfn));
    df1 += dforce;
    df2 -= dforce;
}

/// SOFA's PenalityContactForceField<Vec3> between state 1 and state 2 (which may be the same
/// state: pass the same spans on both sides and the same offsets when assembling).
class PenaltyForceField {
public:
    PenaltyForceField() = default;
    explicit PenaltyForceField(PenaltyParameters parameters);

    [[nodiscard]] const PenaltyParameters& parameters() const { return parameters_; }
    void set_parameters(const PenaltyParameters& parameters);

    /// Moves the current contacts to the previous list (for add_contact's old_index) and empties
    /// the list, reserving `reserve` entries.
    void clear(std::size_t reserve = 0);

    /// Appends a contact with pen = 0 between DOF m1 of state 1 and DOF m2 of state 2, made of
    /// collision elements element1 and element2 (PenaltyContact::index1, index2). `old_index` is 1-based into the
    /// previous list (0 = new): age = previous age + 1 when 1 ≤ old_index ≤ previous size, else 0 (SOFA); with friction
    /// the tangential spring is carried over from that previous contact. Throws std::invalid_argument for negative or
    /// non-finite stiffness / friction, a non-finite dist, a NaN or non-unit normal (| |n| − 1 | > 1e-6), or a negative
    /// index.
    void add_contact(DofIndex m1, DofIndex m2, ElementIndex element1, ElementIndex element2, const Vec3& normal,
                     double dist, double ks, double mu_s = 0.0, double mu_v = 0.0, Index old_index = 0);

    /// Replaces the normal law of contact i, ks·(dist − u·n), by ks'·(dist' − u·n) for the rest
    /// of the step (beyond SOFA: the tunnelling guard's stiffening, tunnelling_guard.hpp). Throws
    /// std::invalid_argument for i out of range, a negative or non-finite ks or a non-finite dist.
    void set_normal_law(std::size_t i, double ks, double dist);

    /// Keeps the current contacts for one more step, as if the same detection happened again:
    /// equivalent to clear() then add_contact(..., old_index = i + 1) for every contact i.
    void renew_contacts();

    /// Accumulates the contact forces (N) into f1 (state 1) and f2 (state 2) and stores pen,
    /// the normal and tangential forces and the friction state in every contact.
    /// f1/f2 must have the sizes of x1/x2; indices outside the states throw std::invalid_argument.
    void add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1, ConstVec3Span v2);

    /// df += k_factor·K·dx + b_factor·B·dx, with the active set and friction states of the last
    /// add_force (SOFA: pen > 0 as stored). Sliding friction contributes nothing (explicit).
    void add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                    double b_factor = 0.0) const;

    /// Appends factor·K (K = ∂f/∂x, SOFA's blocks and sign) as 3×3 blocks. Row/column of DOF m of
    /// state s is offset_s + 3·m. Same state: offset1 == offset2 (blocks are summed).
    void add_stiffness_triplets(TripletList& triplets, Index offset1, Index offset2, double factor = 1.0) const;
    /// Appends factor·B (B = ∂f/∂v: −c·n·nᵀ blocks), empty without damping (SOFA).
    void add_damping_triplets(TripletList& triplets, Index offset1, Index offset2, double factor = 1.0) const;

    /// K as a sparse matrix. Two-state layout: (3·n1 + 3·n2)² with state 2 after state 1.
    /// Same-state layout (same_state = true): (3·n1)², n2 ignored. std::invalid_argument for a
    /// negative size or a contact whose DOF is outside its state.
    [[nodiscard]] SparseMatrix stiffness_matrix(Index n1, Index n2, bool same_state) const;
    [[nodiscard]] SparseMatrix damping_matrix(Index n1, Index n2, bool same_state) const;

    /// Stored energy (J) at the last add_force: Σ ½·ks·pen² over active contacts, plus
    /// ½·kt·|ξ|² of sticking tangential springs. (SOFA logs an error and returns 0.)
    [[nodiscard]] double potential_energy() const;
    /// Energy dissipated so far (J) by normal damping (c·v_n²·h per step) and by sliding
    /// (mu_v·|f_n| times the anchor displacement), accumulated once per step.
    [[nodiscard]] double dissipated_energy() const { return dissipated_damping_ + dissipated_sliding_; }
    [[nodiscard]] double dissipated_by_damping() const { return dissipated_damping_; }
    [[nodiscard]] double dissipated_by_sliding() const { return dissipated_sliding_; }
    void reset_dissipated_energy();

    /// Segments for visualisation at positions x1/x2.
    [[nodiscard]] std::vector<ContactSegment> export_contacts(ConstVec3Span x1, ConstVec3Span x2) const;

    /// For every contact (in order) and every tool DOF (in order) whose DOF on `tool_side`
    /// equals it: the other side's contact-point position and element (SOFA's grabPoint).
    [[nodiscard]] std::vector<GrabbedPoint> grab_points(ContactSide tool_side, std::span<const DofIndex> tool_dofs,
                                                        ConstVec3Span other_positions) const;

    [[nodiscard]] std::span<const PenaltyContact> contacts() const { return contacts_; }
    [[nodiscard]] std::span<const PenaltyContact> previous_contacts() const { return previous_; }
    [[nodiscard]] std::size_t size() const { return contacts_.size(); }
    /// Number of contacts with pen > 0 at the last add_force.
    [[nodiscard]] std::size_t active_count() const;

private:
    template <bool kDamping, bool kFriction>
    void add_force_impl(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                        ConstVec3Span v2);
    /// Throws if a contact's DOF index is outside states of sizes n1, n2; the verified sizes are
    /// cached until the contact list changes, so the hot loops need no per-contact check.
    void check_indices(const char* function, std::size_t n1, std::size_t n2) const;
    /// Throws std::invalid_argument for a negative size or a contact outside the states.
    void check_matrix_sizes(const char* function, Index n1, Index n2, bool same_state) const;
    static constexpr std::size_t kUnchecked = static_cast<std::size_t>(-1);

    PenaltyParameters parameters_{};
    std::vector<PenaltyContact> contacts_;
    std::vector<PenaltyContact> previous_;
    double dissipated_damping_ = 0.0;
    double dissipated_sliding_ = 0.0;
    mutable std::size_t checked_size1_ = kUnchecked;
    mutable std::size_t checked_size2_ = kUnchecked;
};

}  // namespace penalty
