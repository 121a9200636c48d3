#include "penalty/mechanics/rest_shape_springs.hpp"

#include "penalty/mechanics/ordered_scatter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace penalty {

namespace {

/// The springs of a large field run in ranges of kSpringsPerTask on TBB's threads (when no point
/// has two; detail::for_each_range decides from how many).
constexpr std::size_t kSpringsPerTask = 2048;

void check_stiffness(const std::vector<double>& values, const char* parameter) {
    for (double v : values)
        if (!std::isfinite(v) || v < 0.0)
            throw_invalid_argument("RestShapeSpringsForceField: ", parameter, " must be finite and >= 0, got ", v);
}

/// SOFA's Quat::operator*(Quat) (Hamilton product, SOFA's order of operations).
Quat sofa_product(const Quat& a, const Quat& b) {
    const double w = a.w() * b.w() - (a.x() * b.x() + a.y() * b.y() + a.z() * b.z());
    const double x = a.w() * b.x() + a.x() * b.w() + a.y() * b.z() - a.z() * b.y();
    const double y = a.w() * b.y() + a.y() * b.w() + a.z() * b.x() - a.x() * b.z();
    const double z = a.w() * b.z() + a.z() * b.w() + a.x() * b.y() - a.y() * b.x();
    return Quat(w, x, y, z);
}

/// SOFA's Quat::inverse: the conjugate over the norm (0 for a zero quaternion).
Quat sofa_inverse(const Quat& q) {
    double norm = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w());
    if (norm == 0.0) return Quat(0, 0, 0, 0);
    norm = 1.0 / norm;
    return Quat(q.w() * norm, -q.x() * norm, -q.y() * norm, -q.z() * norm);
}

/// SOFA's Quat::normalize: scaled by 1/√|q|² when |q|² is more than 1e-10 away from 1.
Quat sofa_normalized(Quat q) {
    const double mag = q.x() * q.x() + q.y() * q.y() + q.z() * q.z() + q.w() * q.w();
    if (std::abs(mag - 1.0) > 1.0e-10) {
        if (mag != 0) {
            const double s = 1.0 / std::sqrt(mag);
            q = Quat(q.w() * s, q.x() * s, q.y() * s, q.z() * s);
        } else {
            q = Quat(1, q.x(), q.y(), q.z());
        }
    }
    return q;
}

/// SOFA's Quat::quatToAxis for w ≥ 0: angle θ ∈ [0, π] (asin of the vector part's norm when
/// w > 0.999, else 2·acos w) and the unit axis ((0, 1, 0) when sin(θ/2) < ε).
void quat_to_axis(const Quat& q, Vec3& axis, double& angle) {
    double sin_half;
    if (q.w() > 0.999) {
        sin_half = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
        angle = 2.0 * std::asin(sin_half);
    } else {
        const double half = std::acos(q.w());
        sin_half = std::sin(half);
        angle = 2 * half;
    }
    if (sin_half < std::numeric_limits<double>::epsilon()) axis = Vec3(0, 1, 0);
    else axis = Vec3(q.x(), q.y(), q.z()) / sin_half;
}

/// The filtered translation (inactive directions zeroed).
template <std::size_t N>
Vec3 filtered(Vec3 d, const std::array<bool, N>& active, std::size_t first) {
    for (std::size_t c = 0; c < 3; ++c)
        if (!active[first + c]) d[static_cast<Eigen::Index>(c)] = 0;
    return d;
}

}  // namespace

template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::set_stiffness(std::vector<double> stiffness) {
    check_stiffness(stiffness, "stiffness");
    stiffness_ = stiffness.empty() ? std::vector<double>{100.0} : std::move(stiffness);
}

template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::set_angular_stiffness(std::vector<double> stiffness) {
    check_stiffness(stiffness, "angularStiffness");
    angular_stiffness_ = std::move(stiffness);
}

template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::set_external_rest_shape(const MechanicalObject<DataTypes>* external,
                                                                    std::vector<Index> external_points) {
    external_ = external;
    external_points_ = std::move(external_points);
}

// RestShapeSpringsForceField::recomputeIndices and checkOutOfBoundsIndices (in SOFA's order:
// the points, then the anchors against the external state, or against the rest positions when
// there is none, then the two counts).
template <class DataTypes>
bool RestShapeSpringsForceField<DataTypes>::resolve(std::string& why) {
    const std::size_t n = this->state_->num_dofs();
    resolved_dofs_ = n;
    resolved_external_dofs_ = external_ != nullptr ? external_->num_dofs() : 0;
    std::vector<Index> points = points_;
    if (points.empty())
        for (std::size_t i = 0; i < n; ++i) points.push_back(Index(i));
    std::vector<Index> anchors = external_points_;
    if (anchors.empty()) {
        if (external_ == nullptr) anchors = points;
        else
            for (std::size_t i = 0; i < external_->num_dofs(); ++i) anchors.push_back(Index(i));
    }
    const std::size_t anchor_count = external_ != nullptr ? external_->num_dofs() : this->state_->rest_position.size();
    for (Index i : points)
        if (i < 0 || std::size_t(i) >= n) {
            why = "point " + std::to_string(i) + " is out of range (" + std::to_string(n) + " points)";
            return false;
        }
    for (Index i : anchors)
        if (i < 0 || std::size_t(i) >= anchor_count) {
            why = "external point " + std::to_string(i) + " is out of range (" + std::to_string(anchor_count) +
                  (external_ != nullptr ? " points in the external rest shape)" : " rest positions)");
            return false;
        }
    if (anchors.size() != points.size()) {
        why = std::to_string(points.size()) + " points but " + std::to_string(anchors.size()) +
              " external points (SOFA: 'Dimensions of the source and the targeted points are different')";
        return false;
    }
    // without an external rest shape SOFA's addForce anchors spring i at point i's rest position
    anchor_indices_ = external_ != nullptr ? std::move(anchors) : points;
    indices_ = std::move(points);
    std::vector<std::uint8_t> seen(n, 0);
    distinct_points_ = std::all_of(indices_.begin(), indices_.end(),
                                   [&](Index i) { return std::exchange(seen[std::size_t(i)], 1) == 0; });
    return true;
}

// RestShapeSpringsForceField::bwdInit: the lists resolved and checked (an error here, where SOFA
// prints one and leaves the force field off).
template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::init() {
    std::string why;
    if (!resolve(why)) throw_invalid_argument("RestShapeSpringsForceField: ", why);
    points_changed_ = false;
    active_springs_ = true;
    if constexpr (std::is_same_v<DataTypes, Rigid3Types>) {
        // bwdInit: angularStiffness padded with 100 or cut to the stiffness count.
        angular_stiffness_.resize(stiffness_.size(), 100.0);
    }
}

template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::follow_points(std::vector<Index> points) {
    points_ = std::move(points);
    points_changed_ = true;
}

template <class DataTypes>
std::size_t RestShapeSpringsForceField<DataTypes>::springs_past_end() const {
    const std::size_t dofs = this->state_->num_dofs(), anchors = anchor_count();
    std::size_t out = 0;
    for (std::size_t i = 0; i < indices_.size(); ++i) out += spring_in_range(i, dofs, anchors) ? 0 : 1;
    return out;
}

// addForce's recomputeIndices (recompute_indices, the default): the same lists give the same
// springs, so only a change of the points or of a state's size resolves them again. Without
// recompute_indices addForce keeps init's springs: nothing to do.
template <class DataTypes>
bool RestShapeSpringsForceField<DataTypes>::resolve_after_change() {
    if (!recompute_indices_) return active_springs_;
    const std::size_t external = external_ != nullptr ? external_->num_dofs() : 0;
    if (!points_changed_ && this->state_->num_dofs() == resolved_dofs_ && external == resolved_external_dofs_)
        return active_springs_;
    points_changed_ = false;
    active_springs_ = resolve(inactive_reason_);
    if (active_springs_) inactive_reason_.clear();
    else {
        indices_.clear();  // checkOutOfBoundsIndices failed: m_indices.clear()
        anchor_indices_.clear();
    }
    return active_springs_;
}

template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::add_force(std::span<Deriv> f, std::span<const Coord> x,
                                                      std::span<const Deriv> /*v*/) {
    if (recompute_indices_ && has_index_source()) {
        last_points_ = points_;
        if (follow(points_) != last_points_) points_changed_ = true;
    }
    resolve_after_change();
    const std::vector<Coord>& anchors = external_ != nullptr ? external_->position : this->state_->rest_position;
    const std::size_t dofs = this->state_->num_dofs();
    // f_p −= k·(x_p − a) (the filtered directions), energy ½k|x_p − a|²; Rigid: and the angular
    // spring of the rotation x_p·a⁻¹, −ka·angle·axis, ½ka·angle²|axis|²
    const auto spring_force = [&](std::size_t i) {
        const auto p = static_cast<std::size_t>(indices_[i]);
        const auto a = static_cast<std::size_t>(anchor_indices_[i]);
        const double k = stiffness_of(i);
        if constexpr (std::is_same_v<DataTypes, Vec3Types>) {
            const Vec3 d = filtered(Vec3(x[p] - anchors[a]), active_, 0);
            f[p] -= d * k;
            return 0.5 * k * d.squaredNorm();
        } else {
            const Vec3 d = filtered(Vec3(x[p].center - anchors[a].center), active_, 0);
            f[p].linear -= d * k;
            Quat dq = sofa_normalized(sofa_product(x[p].orientation, sofa_inverse(anchors[a].orientation)));
            if (dq.w() < 0.) dq = Quat(-dq.w(), -dq.x(), -dq.y(), -dq.z());
            Vec3 axis = Vec3::Zero();  // SOFA leaves it uninitialised when w >= 1 (the angle is 0)
            double angle = 0.;
            if (dq.w() < 1.0) quat_to_axis(dq, axis, angle);
            axis = filtered(axis, active_, 3);
            const double ka = angular_stiffness_of(i);
            f[p].angular -= axis * angle * ka;
            return 0.5 * k * d.squaredNorm() + 0.5 * ka * angle * angle * axis.squaredNorm();
        }
    };
    const std::size_t count = indices_.size();
    double energy = 0.0;
    if (!distinct_points_ || !detail::ranges_on_threads(count)) {
        for (std::size_t i = 0; i < count; ++i)
            if (spring_in_range(i, dofs, anchors.size()))  // (without recompute_indices, after a change)
                energy += spring_force(i);
    } else {
        // each spring its own point's row; the energy summed in spring order after, as the loop
        spring_energy_.resize(count);
        detail::for_each_range(count, kSpringsPerTask, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i)
                spring_energy_[i] = spring_in_range(i, dofs, anchors.size()) ? spring_force(i) : 0.0;
        });
        for (std::size_t i = 0; i < count; ++i)
            if (spring_in_range(i, dofs, anchors.size())) energy += spring_energy_[i];
    }
    energy_ = energy;
}

template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::add_dforce(std::span<Deriv> df, std::span<const Deriv> dx, double k_factor,
                                                       double /*b_factor*/) const {
    const std::size_t dofs = this->state_->num_dofs(), anchors = anchor_count();
    // df_p −= k·kFactor·dx_p (the filtered directions); Rigid: and −ka·kFactor·dω_p
    const auto springs = [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            if (!spring_in_range(i, dofs, anchors)) continue;
            const auto p = static_cast<std::size_t>(indices_[i]);
            const double k = stiffness_of(i);
            if constexpr (std::is_same_v<DataTypes, Vec3Types>) {
                df[p] -= filtered(dx[p], active_, 0) * k * k_factor;
            } else {
                df[p].linear -= filtered(dx[p].linear, active_, 0) * k * k_factor;
                df[p].angular -= filtered(dx[p].angular, active_, 3) * angular_stiffness_of(i) * k_factor;
            }
        }
    };
    if (distinct_points_) detail::for_each_range(indices_.size(), kSpringsPerTask, springs);  // each its own row
    else springs(0, indices_.size());
}

// addKToMatrix (sofa_assembly_ false) or SOFA HEAD's buildStiffnessMatrix (true): −k on the
// diagonal of each active direction of each point (buildStiffnessMatrix: every translation
// direction, k = stiffness[point index]).
template <class DataTypes>
void RestShapeSpringsForceField<DataTypes>::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    constexpr Index width = DataTypes::kDerivSize;
    const std::size_t dofs = this->state_->num_dofs(), anchors = anchor_count();
    for (std::size_t i = 0; i < indices_.size(); ++i) {
        if (!spring_in_range(i, dofs, anchors)) continue;
        const Index p = indices_[i];
        const double k = sofa_assembly_ ? stiffness_of(static_cast<std::size_t>(p)) : stiffness_of(i);
        for (Index c = 0; c < 3; ++c)
            if (sofa_assembly_ || active_[static_cast<std::size_t>(c)])
                t.emplace_back(offset + width * p + c, offset + width * p + c, -k * factor);
        if constexpr (std::is_same_v<DataTypes, Rigid3Types>) {
            const double ka =
                sofa_assembly_ ? angular_stiffness_of(static_cast<std::size_t>(p)) : angular_stiffness_of(i);
            for (Index c = 3; c < 6; ++c)
                if (active_[static_cast<std::size_t>(c)])
                    t.emplace_back(offset + width * p + c, offset + width * p + c, -ka * factor);
        }
    }
}

template <class DataTypes>
bool RestShapeSpringsForceField<DataTypes>::list_dx_read(const BaseState& state,
                                                         std::vector<std::uint32_t>& rows) const {
    if (&state != this->state_) return true;
    const std::size_t dofs = this->state_->num_dofs(), anchors = anchor_count();
    for (std::size_t i = 0; i < indices_.size(); ++i)
        if (spring_in_range(i, dofs, anchors)) rows.push_back(static_cast<std::uint32_t>(indices_[i]));
    return true;
}

template class RestShapeSpringsForceField<Vec3Types>;
template class RestShapeSpringsForceField<Rigid3Types>;

}  // namespace penalty
