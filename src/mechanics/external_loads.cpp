// PlaneForceField, ConstantForceField, ConicalForceField: see include/penalty/mechanics/external_loads.hpp
// and docs/components/external_loads.md.
#include "penalty/mechanics/external_loads.hpp"

#include "penalty/core/error.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <utility>

namespace penalty {

namespace {

/// Adds factor·(−k)·n nᵀ at the 3×3 diagonal block of point p (SOFA's addKToMatrix order:
/// coefficient n_l·(−k·factor)·n_c).
void add_normal_block(TripletList& triplets, Index offset, Index p, const Vec3& n, double minus_k_factor) {
    const Index row = offset + 3 * p;
    for (Index l = 0; l < 3; ++l)
        for (Index c = 0; c < 3; ++c) triplets.emplace_back(row + l, row + c, n[l] * minus_k_factor * n[c]);
}

}  // namespace

// ---- PlaneForceField ----------------------------------------------------------------------------

namespace {
/// The parameters both templates of PlaneForceField accept (std::invalid_argument otherwise).
void check_plane_parameters(const PlaneForceFieldParameters& p) {
    if (!all_finite(p.normal) || !std::isfinite(p.offset))
        throw_invalid_argument("PlaneForceField: normal and d must be finite");
    if (!(p.stiffness >= 0.0) || !(p.damping >= 0.0) || !(p.max_force >= 0.0))
        throw_invalid_argument("PlaneForceField: stiffness, damping and maxForce must be >= 0, found ", p.stiffness,
                               ", ", p.damping, ", ", p.max_force);
}
}  // namespace

PlaneForceField::PlaneForceField(Vec3Object& state, const PlaneForceFieldParameters& parameters)
    : ForceField<Vec3Types>(state), parameters_(parameters) {
    check_plane_parameters(parameters_);
}

namespace {

/// PlaneForceField<DataTypes>::addForce's law on the points' positions (getCPos) and linear
/// velocities (getDPos): calls add(i, force) for each point that gets a force, in order; returns
/// the energy Σ ½ k d² of those points.
template <class Position, class Velocity, class Add>
double plane_forces(const PlaneForceFieldParameters& p, Index count, Position position, Velocity velocity, Add add) {
    double energy = 0.0;
    // localRange (PlaneForceField::addForce): [first, last] clipped to the points
    auto begin = Index{0};
    auto end = count;
    if (p.local_range[0] >= 0) begin = p.local_range[0];
    if (p.local_range[1] >= 0 && p.local_range[1] + 1 < end) end = p.local_range[1] + 1;
    const double limit_squared = p.max_force * p.max_force;
    for (Index i = begin; i < end; ++i) {
        const auto ui = static_cast<std::size_t>(i);
        const double depth = position(ui).dot(p.normal) - p.offset;  // < 0 below the plane
        if (!(p.bilateral || depth < 0.0)) continue;
        const double force_intensity = -p.stiffness * depth;
        const double damping_intensity = -p.damping * depth;
        Vec3 force = p.normal * force_intensity - velocity(ui) * damping_intensity;
        const double amplitude_squared = force.squaredNorm();
        if (limit_squared > 0.0 && amplitude_squared > limit_squared)
            force *= std::sqrt(limit_squared / amplitude_squared);
        add(i, force);
        energy += 0.5 * p.stiffness * depth * depth;
    }
    return energy;
}

}  // namespace

void PlaneForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) {
    active_.clear();
    energy_ = plane_forces(
        parameters_, static_cast<Index>(x.size()), [&](std::size_t i) -> const Vec3& { return x[i]; },
        [&](std::size_t i) -> const Vec3& { return v[i]; },
        [&](Index i, const Vec3& force) {
            f[static_cast<std::size_t>(i)] += force;
            active_.push_back(i);
        });
}

void PlaneForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                 double /*b_factor*/) const {
    // PlaneForceField::addDForce: df_p += n·(−k·kFactor·(dx_p·n)) on the active points; no B
    const double fact = -parameters_.stiffness * k_factor;
    const Vec3& n = parameters_.normal;
    for (const Index p : active_) {
        const auto up = static_cast<std::size_t>(p);
        df[up] += n * (fact * dx[up].dot(n));
    }
}

void PlaneForceField::add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const {
    const double fact = -parameters_.stiffness * factor;
    for (const Index p : active_) add_normal_block(triplets, offset, p, parameters_.normal, fact);
}

// ---- PlaneForceField<Rigid3> --------------------------------------------------------------------

RigidPlaneForceField::RigidPlaneForceField(Rigid3Object& state, const PlaneForceFieldParameters& parameters)
    : ForceField<Rigid3Types>(state), parameters_(parameters) {
    check_plane_parameters(parameters_);
}

void RigidPlaneForceField::add_force(std::span<RigidDeriv> f, std::span<const RigidFrame> x,
                                     std::span<const RigidDeriv> v) {
    // getCPos: the frame's centre; getDPos: the linear velocity; setDPos: the linear force
    active_.clear();
    energy_ = plane_forces(
        parameters_, static_cast<Index>(x.size()), [&](std::size_t i) -> const Vec3& { return x[i].center; },
        [&](std::size_t i) -> const Vec3& { return v[i].linear; },
        [&](Index i, const Vec3& force) {
            f[static_cast<std::size_t>(i)].linear += force;
            active_.push_back(i);
        });
}

void RigidPlaneForceField::add_dforce(std::span<RigidDeriv> df, std::span<const RigidDeriv> dx, double k_factor,
                                      double /*b_factor*/) const {
    const double fact = -parameters_.stiffness * k_factor;
    const Vec3& n = parameters_.normal;
    for (const Index p : active_) {
        const auto up = static_cast<std::size_t>(p);
        df[up].linear += n * (fact * dx[up].linear.dot(n));
    }
}

void RigidPlaneForceField::add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const {
    // addKToMatrix: the 6×6 block n6·(−k·factor)·n6ᵀ with n6 = (n, 0): its linear 3×3 block only
    // (the other coefficients are 0)
    const double fact = -parameters_.stiffness * factor;
    for (const Index p : active_) {
        const Index row = offset + 6 * p;
        for (Index l = 0; l < 3; ++l)
            for (Index c = 0; c < 3; ++c)
                triplets.emplace_back(row + l, row + c, parameters_.normal[l] * fact * parameters_.normal[c]);
    }
}

// ---- ConstantForceField -------------------------------------------------------------------------

ConstantForceField::ConstantForceField(Vec3Object& state, ConstantForceFieldParameters parameters)
    : ForceField<Vec3Types>(state), parameters_(std::move(parameters)) {
    if (parameters_.forces.empty() && !parameters_.total_force)
        throw_invalid_argument("ConstantForceField: neither 'forces' nor 'totalForce' is given");
    for (const Vec3& force : parameters_.forces)
        if (!all_finite(force)) throw_invalid_argument("ConstantForceField: 'forces' must be finite");
    if (parameters_.total_force && !all_finite(*parameters_.total_force))
        throw_invalid_argument("ConstantForceField: 'totalForce' must be finite");
}

void ConstantForceField::init() {
    const auto size = static_cast<Index>(state_->num_dofs());
    // ConstantForceField::init: no indices means every point
    indices_ = parameters_.indices;
    if (indices_.empty())
        for (Index i = 0; i < size; ++i) indices_.push_back(i);
    for (const Index j : indices_)
        if (j < 0 || j >= size)
            throw_invalid_argument("ConstantForceField: index ", j, " is out of range (the state has ", size,
                                   " points)");
    map_points();
    const auto count = indices_.size();
    point_forces_.clear();
    valid_ = true;
    if (!parameters_.forces.empty()) {
        // updateFromForcesVector: one force for every index (computeForceFromSingleForce), or one per
        // index; another count makes the component Invalid (computeForceFromForcesVector), the list
        // staying as given
        if (parameters_.forces.size() == 1) point_forces_.assign(count, parameters_.forces.front());
        else point_forces_ = parameters_.forces;
        valid_ = point_forces_.size() == count;
    } else {
        // computeForceFromTotalForce: T / n for each index
        if (count == 0) throw_invalid_argument("ConstantForceField: 'totalForce' on a state without points");
        point_forces_.assign(count, Vec3(*parameters_.total_force / static_cast<double>(count)));
    }
    callbacks_ran_ = false;
    indices_changed_ = false;
    total_force_data_ = parameters_.total_force.value_or(Vec3::Zero());
}

void ConstantForceField::map_points() {
    const auto size = static_cast<Index>(state_->num_dofs());
    points_.clear();
    for (const Index j : indices_) points_.push_back(parameters_.index_from_end ? size - 1 - j : j);
}

void ConstantForceField::run_update_callbacks() {
    // The three callbacks run in the order they were added; each writes the component state, so
    // the state of the last (updateFromForcesVector or updateFromTotalForce again) stands.
    const std::size_t count = indices_.size();
    if (!parameters_.forces.empty()) {
        // updateFromForcesVector, twice: one force is spread over the indices
        // (computeForceFromSingleForce), then the forces must number the indices
        // (computeForceFromForcesVector). Spread over the count of init, they stay that many.
        if (point_forces_.size() == 1) point_forces_.assign(count, Vec3(point_forces_.front()));
        valid_ = point_forces_.size() == count;
    } else {
        // updateFromTotalForce: T / n for each index; none: Invalid, the forces stay
        valid_ = count != 0;
        if (valid_) point_forces_.assign(count, Vec3(*parameters_.total_force / static_cast<double>(count)));
    }
    if (valid_ && !parameters_.forces.empty()) total_force_data_ = total_force();  // computeForceFromForcesVector
    map_points();
    const auto size = static_cast<Index>(state_->num_dofs());
    if (valid_)  // SOFA would write out of its force vector
        for (const Index p : points_)
            if (p < 0 || p >= size)
                throw_invalid_argument("ConstantForceField: followed index ", p, " is out of range (the state has ",
                                       size, " points)");
}

void ConstantForceField::take_callback_state(const ConstantForceField& before) {
    if (before.parameters_.total_force != parameters_.total_force) return;  // written: SOFA's Data holds it
    if (before.parameters_.forces != parameters_.forces) {
        // written forces: this build's init is SOFA's callbacks on them, which write `totalForce`
        // only when valid (computeForceFromForcesVector): until then it keeps its value
        total_force_data_ = before.total_force_data_;
        return;
    }
    point_forces_ = before.point_forces_;
    total_force_data_ = before.total_force_data_;
    valid_ = before.valid_;
    callbacks_ran_ = before.callbacks_ran_;
    indices_changed_ = before.indices_changed_ || indices_ != before.indices_;
}

std::vector<Vec3> ConstantForceField::forces_data() const {
    return callbacks_ran_ ? point_forces_ : parameters_.forces;
}

void ConstantForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> /*v*/) {
    // d_componentState's read (isComponentStateValid) runs the callbacks when a Data changed: the
    // first time (init made the forces they make), and after d_indices changed
    if (!callbacks_ran_) {
        callbacks_ran_ = true;
        if (valid_ && !parameters_.forces.empty()) total_force_data_ = total_force();
    }
    bool changed = std::exchange(indices_changed_, false);
    if (has_index_source()) {
        last_indices_ = indices_;
        changed = follow(indices_) != last_indices_ || changed;
    }
    if (changed) run_update_callbacks();
    // addForce: nothing while the component is Invalid; f_p(j) += F_j; getPotentialEnergy: E = −Σ F_j·x_p(j)
    energy_ = 0.0;
    if (!valid_) return;
    for (std::size_t j = 0; j < points_.size(); ++j) {
        const auto p = static_cast<std::size_t>(points_[j]);
        f[p] += point_forces_[j];
        energy_ -= point_forces_[j].dot(x[p]);
    }
}

Vec3 ConstantForceField::total_force() const {
    Vec3 total = Vec3::Zero();
    for (const Vec3& force : point_forces_) total += force;
    return total;
}

// ---- ConicalForceField --------------------------------------------------------------------------

ConicalForceField::ConicalForceField(Vec3Object& state, const ConicalForceFieldParameters& parameters)
    : ForceField<Vec3Types>(state), parameters_(parameters) {
    const auto& p = parameters_;
    if (!all_finite(p.center) || !all_finite(p.height) || !std::isfinite(p.angle_deg))
        throw_invalid_argument("ConicalForceField: coneCenter, coneHeight and coneAngle must be finite");
    if (!std::isfinite(p.stiffness) || !std::isfinite(p.damping))
        throw_invalid_argument("ConicalForceField: stiffness and damping must be finite");
}

bool ConicalForceField::is_inside(const Vec3& x) const {
    // ConicalForceField::isIn
    const Vec3 u = x - parameters_.center;
    const double h = parameters_.height.norm();
    const double distance = u.norm();
    if (distance > h) return false;
    const double angle_deg = std::acos(u.dot(parameters_.height) / (h * distance)) * 180.0 / std::numbers::pi;
    return !(angle_deg > parameters_.angle_deg);  // NaN at the apex: inside
}

void ConicalForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) {
    const auto& p = parameters_;
    const double h = p.height.norm();
    const Vec3 axis = p.height.normalized();
    contacts_.clear();
    energy_ = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (is_inside(x[i])) continue;
        const Vec3 u = x[i] - p.center;
        const double distance = u.norm();
        if (distance > h) {
            // beyond the spherical cap: radial, depth d = |u| − h; damping −v·(−c d) as SOFA
            const double depth = distance - h;
            const double force_intensity = -p.stiffness * depth;
            const double damping_intensity = -p.damping * depth;
            f[i] += u * (force_intensity / distance) - v[i] * damping_intensity;
            contacts_.push_back({static_cast<Index>(i), u / distance});
            energy_ += 0.5 * p.stiffness * depth * depth;
            continue;
        }
        Vec3 direction;
        double depth = 0.0;
        if (u.dot(axis) > 0.0) {
            // beside the cone: rotate u towards the axis by (angle(u, â) − α) about â × u, project x
            // on that generatrix (ConicalForceField::addForce, with a quaternion there)
            const double excess = std::acos(u.dot(axis) / distance) - p.angle_deg * std::numbers::pi / 180.0;
            const Vec3 rotation_axis = axis.cross(u).normalized();
            const Vec3 generatrix = (Eigen::AngleAxisd(-excess, rotation_axis) * u).normalized();
            const Vec3 projection = p.center + generatrix * generatrix.dot(u);
            const Vec3 to_surface = projection - x[i];
            depth = to_surface.norm();
            direction = to_surface / depth;
        } else {
            // behind the apex: towards the apex
            depth = distance;
            direction = -u / distance;
        }
        f[i] += direction * (p.stiffness * depth) + direction * (p.damping * -direction.dot(v[i]));
        contacts_.push_back({static_cast<Index>(i), direction});
        energy_ += 0.5 * p.stiffness * depth * depth;
    }
}

void ConicalForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                   double /*b_factor*/) const {
    // ConicalForceField::addDForce: df_i += (n (dx_i·n))·(−k)·kFactor; no B
    for (const Contact& c : contacts_) {
        const auto i = static_cast<std::size_t>(c.index);
        df[i] += (c.normal * dx[i].dot(c.normal)) * -parameters_.stiffness * k_factor;
    }
}

void ConicalForceField::add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const {
    for (const Contact& c : contacts_)
        add_normal_block(triplets, offset, c.index, c.normal, -parameters_.stiffness * factor);
}

}  // namespace penalty
