#pragma once
/// @file
/// SOFA's mechanical loads on one Vec3 state (Sofa/Component/MechanicalLoad): PlaneForceField,
/// ConstantForceField and ConicalForceField. Sign conventions of force_field.hpp: f in N,
/// K = ∂f/∂x (N/m, negative semi-definite here), f = −∂E/∂x where E is defined.
/// The formulas, SOFA's quirks and the method each follows are in docs/components/external_loads.md.

#include "penalty/mechanics/followed_indices.hpp"
#include "penalty/mechanics/force_field.hpp"

#include <array>
#include <optional>
#include <vector>

namespace penalty {

// ---- PlaneForceField ----------------------------------------------------------------------------

/// Parameters of PlaneForceField (defaults: SOFA's PlaneForceField constructor).
struct PlaneForceFieldParameters {
    /// n: used as given, NOT normalised (SOFA normalises only in setPlane, never from a scene),
    /// so the depth d below scales with |n| (unitless when |n| = 1).
    Vec3 normal = Vec3(0.0, 1.0, 0.0);
    double offset = 0.0;       ///< SOFA's `d` (m): the plane is {x : x·n = offset}
    double stiffness = 500.0;  ///< k (N/m), >= 0
    double damping = 5.0;      ///< c (N·s/m per m of depth, see below), >= 0
    double max_force = 0.0;    ///< |f| per point is clamped to this (N); 0: no clamp
    bool bilateral = false;    ///< true: every point is pushed towards the plane, on both sides
    /// SOFA's localRange: only points first..last (inclusive) are considered; −1: no bound.
    std::array<int, 2> local_range = {-1, -1};
};

/// PlaneForceField (SOFA's PlaneForceField<Vec3>::addForce / addDForce / addKToMatrix): for each
/// point i in the local range with depth d = x_i·n − offset < 0 (any d when bilateral):
///   f_i += n·(−k d) − v_i·(−c d)        (the damping term is along the whole velocity)
/// then |f_i| clamped to max_force when max_force > 0. The points that got a force are the
/// "active" ones; the stiffness is K_ii = −k n nᵀ on them only (from the last add_force), with no
/// damping and no clamp term (SOFA). B = 0 (SOFA: no damping matrix).
/// Energy: SOFA does not implement it (0); here E = Σ_active ½ k d², the potential of the
/// undamped, unclamped force (f = −∂E/∂x since ∂d/∂x = n).
class PlaneForceField final : public ForceField<Vec3Types> {
public:
    PlaneForceField(Vec3Object& state, const PlaneForceFieldParameters& parameters);

    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const PlaneForceFieldParameters& parameters() const { return parameters_; }
    /// Indices of the points that got a force at the last add_force, ascending.
    [[nodiscard]] const std::vector<Index>& active_points() const { return active_; }

private:
    PlaneForceFieldParameters parameters_;
    std::vector<Index> active_;
    double energy_ = 0.0;
};

/// PlaneForceField<Rigid3> (SOFA's PlaneForceField.cpp instantiates the same template for Rigid3):
/// the law above on the frames' centres (DataTypes::getCPos) and linear velocities (getDPos), the
/// force on the linear part (setDPos): no torque; K: −k n nᵀ on the linear block of the active
/// frames (addDForce on the linear dx; addKToMatrix's 6×6 block n₆ n₆ᵀ with n₆ = (n, 0)).
class RigidPlaneForceField final : public ForceField<Rigid3Types> {
public:
    RigidPlaneForceField(Rigid3Object& state, const PlaneForceFieldParameters& parameters);

    void add_force(std::span<RigidDeriv> f, std::span<const RigidFrame> x, std::span<const RigidDeriv> v) override;
    void add_dforce(std::span<RigidDeriv> df, std::span<const RigidDeriv> dx, double k_factor,
                    double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const PlaneForceFieldParameters& parameters() const { return parameters_; }
    [[nodiscard]] const std::vector<Index>& active_points() const { return active_; }

private:
    PlaneForceFieldParameters parameters_;
    std::vector<Index> active_;
    double energy_ = 0.0;
};

// ---- ConstantForceField -------------------------------------------------------------------------

/// Parameters of ConstantForceField as written in a scene (SOFA's ConstantForceField Data).
struct ConstantForceFieldParameters {
    std::vector<Index> indices;       ///< empty: every point of the state (SOFA's init)
    std::vector<Vec3> forces;         ///< per index (N), or one force for every index
    std::optional<Vec3> total_force;  ///< split evenly over the indices (N); ignored when forces are given
    bool index_from_end = false;      ///< index j means point n − 1 − j
};

/// ConstantForceField (SOFA's ConstantForceField<Vec3>): f_{p(j)} += F_j, with p(j) = indices[j]
/// (n − 1 − indices[j] when index_from_end) and F_j (init, updateFromForcesVector /
/// computeForceFromSingleForce / computeForceFromTotalForce):
///   - `forces` given with one entry per index: F_j = forces[j];
///   - `forces` given with one entry: F_j = forces[0] for every index;
///   - else `total_force` T: F_j = T / (number of indices).
/// K = 0, B = 0; energy E = −Σ_j F_j·x_{p(j)} (getPotentialEnergy). Indices that follow an engine
/// (`indices="@box.indices"` over moving positions) are taken at each addForce; a new count
/// re-spreads one `forces` entry or `totalForce`, and makes SOFA's component Invalid (no force)
/// when the forces, already spread over the old count, no longer fit (run_update_callbacks).
class ConstantForceField final : public ForceField<Vec3Types>, public FollowedIndices {
public:
    /// Throws std::invalid_argument when neither forces nor total_force is given.
    ConstantForceField(Vec3Object& state, ConstantForceFieldParameters parameters);

    /// Resolves the indices (every point when empty) and the per-index forces against the state's
    /// size; throws std::invalid_argument for an index out of range. A `forces` count that is
    /// neither 1 nor the number of indices makes the component Invalid (valid() false, no force),
    /// as SOFA's update callbacks do (computeForceFromForcesVector): a scene builder refuses it in a
    /// scene file, and accepts it after a write of `indices` or `forces` while the scene runs,
    /// until a write makes the counts fit again.
    void init() override;
    /// f_p(j) += F_j; with indices that follow a source (FollowedIndices), the source is read first
    /// and a changed list re-runs SOFA's update callbacks (run_update_callbacks).
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, double) const override {}
    [[nodiscard]] double potential_energy() const override { return energy_; }

    /// The points receiving a force and their forces (after init), in the order of `indices`.
    [[nodiscard]] const std::vector<Index>& points() const { return points_; }
    [[nodiscard]] const std::vector<Vec3>& point_forces() const { return point_forces_; }
    /// Σ F_j (N).
    [[nodiscard]] Vec3 total_force() const;
    /// SOFA's component state: false (Invalid, no force) while the per-index forces do not fit the
    /// count of the indices (followed or written indices of another count, a written `forces` list
    /// of another count), or with `totalForce` and no index.
    [[nodiscard]] bool valid() const { return valid_; }
    /// SOFA's `indices` Data after init: the given ones, or every point.
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }
    /// SOFA's `forces` Data: the scene's value until the update callbacks first ran (the first
    /// addForce: isComponentStateValid), then what they made of it (one force spread over the
    /// indices, computeForceFromSingleForce; with `totalForce`, T / n each), kept while the
    /// component is Invalid.
    [[nodiscard]] std::vector<Vec3> forces_data() const;
    /// SOFA's `totalForce` Data: the scene's value (0 0 0 when not given) until the callbacks first
    /// ran; with `forces`, then Σ F_j summed in index order from 0 (computeForceFromForcesVector,
    /// the last callback), kept while the component is Invalid.
    [[nodiscard]] Vec3 total_force_data() const { return total_force_data_; }
    /// A rebuild after a write of the scene's Data (indices written by a controller, another
    /// component's Data): when this one's `forces` and `totalForce` are `before`'s, SOFA's component
    /// keeps the Data its callbacks made (one `forces` value stays as many copies as the indices had)
    /// and its state; new indices run the callbacks at the next addForce (another count of spread
    /// forces: Invalid). Written `forces` leave `totalForce` as it was until the callbacks, valid,
    /// write the new sum.
    void take_callback_state(const ConstantForceField& before);

private:
    /// SOFA's callbacks updateFromIndices, updateFromForcesVector and updateFromTotalForce, run
    /// when the indices changed; the last one's state stands (Base::addUpdateCallback order).
    void run_update_callbacks();
    /// points_ from indices_ (n − 1 − j with index_from_end).
    void map_points();

    ConstantForceFieldParameters parameters_;
    std::vector<Index> indices_;       ///< SOFA's d_indices (every point when none are given)
    std::vector<Index> last_indices_;  ///< indices_ before the source's read (a change re-runs the callbacks)
    std::vector<Index> points_;
    std::vector<Vec3> point_forces_;        ///< SOFA's d_forces once its callbacks ran (one per index when valid)
    Vec3 total_force_data_ = Vec3::Zero();  ///< SOFA's d_totalForce
    double energy_ = 0.0;
    bool valid_ = true;
    bool callbacks_ran_ = false;    ///< the callbacks ran once (the first addForce)
    bool indices_changed_ = false;  ///< a rebuild changed the indices: the next addForce runs the callbacks
};

// ---- ConicalForceField --------------------------------------------------------------------------

/// Parameters of ConicalForceField (defaults: SOFA's ConicalForceField constructor).
struct ConicalForceFieldParameters {
    Vec3 center = Vec3::Zero();  ///< apex c of the cone (m)
    Vec3 height = Vec3::Zero();  ///< axis a (m): direction and length h = |a| of the cone
    double angle_deg = 10.0;     ///< half-angle α of the cone (degrees)
    double stiffness = 500.0;    ///< k (N/m)
    double damping = 5.0;        ///< c (N·s/m, see below)
};

/// ConicalForceField (SOFA's ConicalForceField<Vec3>::isIn / addForce / addDForce): keeps points in
/// the cone of apex c, axis â = a/|a| and half-angle α, closed by the sphere |x − c| = h. For a
/// point outside (u = x − c; isIn: |u| > h or angle(u, a) > α):
///   - |u| > h (beyond the cap): depth d = |u| − h, f = −k d û + c d v  (SOFA: the damping term
///     has d > 0 here, so it pushes along v);
///   - else u·â > 0 (beside the cone): p' = the projection of x on the cone's generatrix in the
///     plane (â, u) (u rotated towards â by angle(u, â) − α, SOFA with a quaternion), d = |p' − x|,
///     n = (p' − x)/d, f = k d n − c (n·v) n;
///   - else (behind the apex): d = |u|, n = −û, f = k d n − c (n·v) n.
/// Stiffness: K_ii = −k n nᵀ with n the unit direction of each contact of the last add_force
/// (beyond the cap n = û); the curvature terms of the exact Jacobian are dropped (SOFA), so K is
/// the part of ∂f/∂x along n. Energy: SOFA returns 0; here E = Σ ½ k d², the potential of the
/// undamped force.
class ConicalForceField final : public ForceField<Vec3Types> {
public:
    struct Contact {
        Index index = 0;
        Vec3 normal = Vec3::Zero();  ///< unit direction n of the stiffness −k n nᵀ
    };

    ConicalForceField(Vec3Object& state, const ConicalForceFieldParameters& parameters);

    /// SOFA's isIn: |x − c| <= h and angle(x − c, a) <= α (a point at the apex is in).
    [[nodiscard]] bool is_inside(const Vec3& x) const;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const ConicalForceFieldParameters& parameters() const { return parameters_; }
    /// The contacts of the last add_force, by ascending point index.
    [[nodiscard]] const std::vector<Contact>& contacts() const { return contacts_; }

private:
    ConicalForceFieldParameters parameters_;
    std::vector<Contact> contacts_;
    double energy_ = 0.0;
};

}  // namespace penalty
