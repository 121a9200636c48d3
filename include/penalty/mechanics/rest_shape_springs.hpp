#pragma once
/// @file
/// SOFA's RestShapeSpringsForceField for Vec3d and Rigid3d: zero-length springs pulling points to
/// their rest shape (the state's rest positions, or the current positions of an external state).

#include "penalty/mechanics/followed_indices.hpp"
#include "penalty/mechanics/force_field.hpp"

#include <array>
#include <string>
#include <vector>

namespace penalty {

/// RestShapeSpringsForceField<DataTypes> (SOFA's RestShapeSpringsForceField::addForce, addDForce,
/// addKToMatrix, buildStiffnessMatrix). Spring i pulls point p = points[i] (all points when the
/// list is empty) toward its anchor a: the rest position of p, or, with an external rest shape,
/// the current position of external_points[i] (all points of the external state when empty) of
/// that state. With k = stiffness[i] (stiffness[0] when the list is shorter; default 100 N/m) and
/// the inactive directions zeroed in d = x_p − a:
///   Vec3:   f_p −= k·d,  df_p −= kFactor·k·dx_p (filtered),  E = ½ k |d|²;
///   Rigid3: linear part as Vec3 on the centres; angular: the rotation q_p·q_a⁻¹ (normalised,
///           w ≥ 0) as axis u and angle θ (SOFA's quatToAxis), u filtered by the active rotation
///           directions, torque −ka·θ·u, dtorque −kFactor·ka·dω (filtered), E += ½ ka θ²
///           (ka = angularStiffness[i], default 100; K's angular block −ka·I is exact at θ = 0).
/// The anchor does not move with dx: K = −k·I (filtered) on p's diagonal only.
template <class DataTypes>
class RestShapeSpringsForceField final : public ForceField<DataTypes>, public FollowedIndices {
public:
    using Coord = typename DataTypes::Coord;
    using Deriv = typename DataTypes::Deriv;
    static constexpr int kDirections = DataTypes::kDerivSize;  ///< 3 (Vec3), 6 (Rigid3: x y z rx ry rz)

    explicit RestShapeSpringsForceField(MechanicalObject<DataTypes>& state) : ForceField<DataTypes>(state) {}

    /// Points of the state (empty: all).
    void set_points(std::vector<Index> points) { points_ = std::move(points); }
    /// N/m, each finite and >= 0; empty: {100}.
    void set_stiffness(std::vector<double> stiffness);
    /// Rigid3: N·m/rad, each finite and >= 0; padded with 100 (or cut) to the stiffness count.
    void set_angular_stiffness(std::vector<double> stiffness);
    /// Directions in which the springs act (translation, then rotation for Rigid3).
    void set_active_directions(const std::array<bool, kDirections>& active) { active_ = active; }
    /// Anchors at the current positions of `external` (points external_points, all when empty)
    /// instead of the rest positions. Without one (nullptr) the anchors stay the points' rest
    /// positions and SOFA only checks external_points (as many as the points, each a rest position).
    void set_external_rest_shape(const MechanicalObject<DataTypes>* external, std::vector<Index> external_points);
    /// SOFA HEAD's buildStiffnessMatrix (the assembled matrix direct solvers use) takes the
    /// stiffness of spring i from stiffness[p] (the point's index, not the spring's) and ignores
    /// the inactive translation directions; addDForce and the older addKToMatrix do not. true
    /// (SOFA, the default): add_stiffness_triplets reproduces that; false: the matrix of addDForce.
    void set_sofa_assembly(bool sofa) { sofa_assembly_ = sofa; }

    /// SOFA's recompute_indices (default true): addForce resolves the springs again from `points`
    /// at each step (recomputeIndices). false: the springs of init stay (m_indices, by index, while
    /// `points` follows the topology): after a topological change spring i acts on whatever point
    /// is now at its index, anchored at that index's rest position (or its external point); a
    /// spring whose point or anchor is past its state's end acts on nothing (SOFA HEAD reads and
    /// writes past the vectors' ends there) until an addition brings the index back.
    void set_recompute_indices(bool recompute) { recompute_indices_ = recompute; }
    [[nodiscard]] bool recompute_indices() const { return recompute_indices_; }
    /// How many springs have a point or an anchor past its state's end (only without
    /// recompute_indices, after a topological change).
    [[nodiscard]] std::size_t springs_past_end() const;

    /// Resolves the point lists and checks them against the states (std::invalid_argument).
    void init() override;

    /// SOFA's d_points as given (empty: all points): the TopologySubsetIndices a topological change
    /// edits (topology_followers.hpp, SubsetIndicesFollower).
    [[nodiscard]] const std::vector<Index>& point_list() const { return points_; }
    /// The `points` list after a topological change; the springs are resolved again at the next
    /// resolve_after_change (or add_force).
    void follow_points(std::vector<Index> points);
    /// SOFA's recomputeIndices and checkOutOfBoundsIndices, which addForce runs at each step
    /// (recompute_indices): the springs again from `points` (all points when empty, even once a
    /// change emptied the list) and external_points (all points of the external state when empty,
    /// else `points`). A point past its state's end, or as many external points as points no more,
    /// and SOFA clears the springs (an error message, the force field off): the same here, and
    /// false is returned. Does nothing and returns active() unless the points or a state's size
    /// changed since the last resolution.
    bool resolve_after_change();
    /// false once resolve_after_change turned the springs off.
    [[nodiscard]] bool active() const { return active_springs_; }
    /// Why resolve_after_change turned the springs off (SOFA's message), or empty.
    [[nodiscard]] const std::string& inactive_reason() const { return inactive_reason_; }

    /// With recompute_indices, a source of `points` (FollowedIndices: `points="@box.indices"` over
    /// moving positions) is read first: SOFA's addForce reads d_points in recomputeIndices.
    void add_force(std::span<Deriv> f, std::span<const Coord> x, std::span<const Deriv> v) override;
    void add_dforce(std::span<Deriv> df, std::span<const Deriv> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// ½ Σ k |d|² (+ ½ Σ ka θ² for Rigid3) at the last add_force (SOFA returns 0).
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] bool list_dx_read(const BaseState& state, std::vector<std::uint32_t>& rows) const override;
    /// The external rest shape, when there is one (its positions are read).
    void list_read_states(std::vector<const BaseState*>& out) const override {
        if (external_ != nullptr) out.push_back(external_);
    }
    [[nodiscard]] const std::vector<Index>& points() const { return indices_; }
    [[nodiscard]] const MechanicalObject<DataTypes>* external_rest_shape() const { return external_; }

private:
    [[nodiscard]] double stiffness_of(std::size_t spring) const {
        return stiffness_[spring < stiffness_.size() ? spring : 0];
    }
    [[nodiscard]] double angular_stiffness_of(std::size_t spring) const {
        return angular_stiffness_[spring < angular_stiffness_.size() ? spring : 0];
    }
    /// Spring i's point and anchor are inside their states (always, but without recompute_indices
    /// after a change that shrank a state).
    [[nodiscard]] bool spring_in_range(std::size_t i, std::size_t dofs, std::size_t anchors) const {
        return std::size_t(indices_[i]) < dofs && std::size_t(anchor_indices_[i]) < anchors;
    }
    [[nodiscard]] std::size_t anchor_count() const {
        return external_ != nullptr ? external_->num_dofs() : this->state_->rest_position.size();
    }
    /// SOFA's recomputeIndices + checkOutOfBoundsIndices; false (nothing resolved) when SOFA
    /// deactivates the springs, with the reason in `why`.
    bool resolve(std::string& why);

    std::vector<Index> points_;
    std::vector<Index> last_points_;  ///< points_ before the source's read (a change resolves again)
    std::vector<Index> external_points_;
    bool points_changed_ = false;
    bool active_springs_ = true;
    std::string inactive_reason_;
    std::size_t resolved_dofs_ = 0, resolved_external_dofs_ = 0;  ///< the states' sizes at the last resolution
    std::vector<Index> indices_;                                  ///< resolved points
    /// No point has two springs (resolve): the springs then run in ranges on threads, each
    /// writing only its own point's row.
    bool distinct_points_ = false;
    std::vector<double> spring_energy_;  ///< add_force on threads: each spring's, summed in order after
    std::vector<Index> anchor_indices_;  ///< resolved anchors (in the external state, or = indices_)
    std::vector<double> stiffness_{100.0};
    std::vector<double> angular_stiffness_;
    std::array<bool, kDirections> active_ = [] {
        std::array<bool, kDirections> a{};
        a.fill(true);
        return a;
    }();
    const MechanicalObject<DataTypes>* external_ = nullptr;
    bool sofa_assembly_ = true;
    bool recompute_indices_ = true;
    double energy_ = 0.0;
};

extern template class RestShapeSpringsForceField<Vec3Types>;
extern template class RestShapeSpringsForceField<Rigid3Types>;

}  // namespace penalty
