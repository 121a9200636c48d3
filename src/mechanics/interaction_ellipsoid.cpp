// SOFA's InteractionEllipsoidForceField<Vec3d, Rigid3d> (interaction_ellipsoid.hpp), in SOFA's
// operation order: InteractionEllipsoidForceField::initCalcF, calcF, addForce and addDForce.
#include "penalty/mechanics/interaction_ellipsoid.hpp"

#include "sofa_quaternion.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

InteractionEllipsoidForceField::InteractionEllipsoidForceField(Vec3Object& points, Rigid3Object& frames,
                                                               InteractionEllipsoidParameters parameters)
    : points_(&points), frames_(&frames), parameters_(std::move(parameters)) {
    const auto finite = [](const Vec3& v) { return v.allFinite(); };
    if (!std::all_of(parameters_.centers.begin(), parameters_.centers.end(), finite))
        throw_invalid_argument("InteractionEllipsoidForceField: center must be finite");
    for (const Vec3& r : parameters_.radii)
        if (!r.allFinite() || (r.array() == 0.0).any())
            throw_invalid_argument("InteractionEllipsoidForceField: vradius must be finite and non-zero, got (",
                                   r.transpose(), ")");
    if (!std::isfinite(parameters_.stiffness) || !std::isfinite(parameters_.damping))
        throw_invalid_argument("InteractionEllipsoidForceField: stiffness and damping must be finite");
    // initCalcF: as many ellipsoids as the longer list; a missing center or radius repeats the
    // last one given (no radius: 1, no center: 0)
    const std::size_t count = std::max(parameters_.centers.size(), parameters_.radii.size());
    std::vector<Vec3> centers(count, Vec3::Zero()), radii(count, Vec3::Ones());
    for (std::size_t e = 0; e < count; ++e) {
        if (!parameters_.centers.empty()) centers[e] = parameters_.centers[std::min(e, parameters_.centers.size() - 1)];
        if (!parameters_.radii.empty()) radii[e] = parameters_.radii[std::min(e, parameters_.radii.size() - 1)];
    }
    parameters_.centers = std::move(centers);
    parameters_.radii = std::move(radii);
    for (const Vec3& r : parameters_.radii)
        inverse_radii2_.emplace_back(1 / (r[0] * r[0]), 1 / (r[1] * r[1]), 1 / (r[2] * r[2]));
}

void InteractionEllipsoidForceField::init() {
    if (parameters_.frame_index < 0 || static_cast<std::size_t>(parameters_.frame_index) >= frames_->num_dofs())
        throw_invalid_argument("InteractionEllipsoidForceField: object2_dof_index ", parameters_.frame_index,
                               " is out of range (", frames_->num_dofs(), " frames)");
    orientation_ = frame().orientation;
}

RigidFrame InteractionEllipsoidForceField::frame() const {
    RigidFrame c = frames_->position[static_cast<std::size_t>(parameters_.frame_index)];
    if (!parameters_.object2_invert) return c;
    // RigidTypes::inverse: (−q⁻¹·c, q⁻¹)
    const Quat inverse = sofa_quat::inverse(c.orientation);
    return {-sofa_quat::rotate(inverse, c.center), inverse};
}

ForceFieldStates InteractionEllipsoidForceField::states() const {
    if (parameters_.object2_forces) return {points_, frames_};
    return ForceFieldStates(points_);
}

void InteractionEllipsoidForceField::list_read_states(std::vector<const BaseState*>& out) const {
    if (!parameters_.object2_forces) out.push_back(frames_);
}

bool InteractionEllipsoidForceField::local_force(const Vec3& p, const Vec3& v, Vec3& force, Mat3& stiffness) const {
    // the ellipsoid of least n² (the first one on ties)
    Vec3 best_dp = Vec3::Zero();
    double best_n2 = -1;
    std::size_t best = 0;
    for (std::size_t e = 0; e < parameters_.centers.size(); ++e) {
        const Vec3 dp(p[0] - parameters_.centers[e][0], p[1] - parameters_.centers[e][1],
                      p[2] - parameters_.centers[e][2]);
        double n2 = 0;
        for (int j = 0; j < 3; ++j) n2 += (dp[j] * dp[j]) * inverse_radii2_[e][j];
        if (e == 0 || n2 < best_n2) {
            best_n2 = n2;
            best = e;
            best_dp = dp;
        }
    }
    if (!((best_n2 - 1) * parameters_.stiffness < 0)) return false;
    const Vec3& inv_r2 = inverse_radii2_[best];
    const double k = std::abs(parameters_.stiffness);
    const double norm = std::sqrt(best_n2);
    const double depth = norm - 1;  // v
    Vec3 grad;
    for (int j = 0; j < 3; ++j) grad[j] = best_dp[j] * inv_r2[j];
    const double grad_norm2 = grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2];
    const double grad_norm = std::sqrt(grad_norm2);
    const double force_intensity = -k * depth / grad_norm;
    const double damping_intensity = parameters_.damping * std::abs(depth);
    for (int j = 0; j < 3; ++j) force[j] = grad[j] * force_intensity - v[j] * damping_intensity;
    const double fact1 = -k / (norm * grad_norm);
    const double fact2 = -k * depth / grad_norm;
    // SOFA: −|k|v/|g|²; the derivative of −|k|v·g/|g| gives +|k|v/|g|³
    const double fact3 = exact_stiffness_ ? k * depth / (grad_norm2 * grad_norm) : -k * depth / grad_norm2;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) stiffness(i, j) = grad[i] * grad[j] * (fact1 + fact3 * inv_r2[j]);
        stiffness(i, i) += fact2 * inv_r2[i];
    }
    return true;
}

void InteractionEllipsoidForceField::accumulate_force() {
    const RigidFrame c = frame();
    orientation_ = c.orientation;
    contacts_.clear();
    Vec3 frame_force = Vec3::Zero();
    for (std::size_t i = 0; i < points_->num_dofs(); ++i) {
        const Vec3& x = points_->position[i];
        const Vec3 p =
            sofa_quat::inverse_rotate(c.orientation, Vec3(x[0] - c.center[0], x[1] - c.center[1], x[2] - c.center[2]));
        const Vec3 v = sofa_quat::inverse_rotate(c.orientation, points_->velocity[i]);
        Vec3 local = Vec3::Zero();
        Mat3 m;
        if (!local_force(p, v, local, m)) continue;
        const Vec3 force = sofa_quat::rotate(c.orientation, local);
        points_->force[i] += force;
        frame_force -= force;
        contacts_.push_back({static_cast<Index>(i), m});
    }
    if (parameters_.object2_forces)
        frames_->force[static_cast<std::size_t>(parameters_.frame_index)].linear += frame_force;
}

void InteractionEllipsoidForceField::accumulate_dforce(double k_factor, double) {
    const auto frame_index = static_cast<std::size_t>(parameters_.frame_index);
    const Vec3 frame_dx = parameters_.object2_forces ? frames_->dx[frame_index].linear : Vec3::Zero();
    Vec3 frame_df = Vec3::Zero();
    for (const Contact& c : contacts_) {
        const Vec3& dx = points_->dx[static_cast<std::size_t>(c.point)];
        const Vec3 du(dx[0] - frame_dx[0], dx[1] - frame_dx[1], dx[2] - frame_dx[2]);
        const Vec3 local = sofa_quat::inverse_rotate(orientation_, du);
        Vec3 dforce;
        for (int i = 0; i < 3; ++i)
            dforce[i] = c.local_stiffness(i, 0) * local[0] + c.local_stiffness(i, 1) * local[1] +
                        c.local_stiffness(i, 2) * local[2];
        dforce *= k_factor;
        const Vec3 df = sofa_quat::rotate(orientation_, dforce);
        points_->df[static_cast<std::size_t>(c.point)] += df;
        frame_df -= df;
    }
    if (parameters_.object2_forces) frames_->df[frame_index].linear += frame_df;
}

void InteractionEllipsoidForceField::add_stiffness(TripletList& t, const StateOffsets& offsets, double factor) const {
    // df₁ = W (dx₁ − dx₂), df₂ = −W (dx₁ − dx₂), W = q·M·q⁻¹ (world axes)
    const Mat3 rotation = sofa_quat::to_matrix(orientation_);
    const Index o1 = offsets(points_);
    const Index o2 = parameters_.object2_forces ? offsets(frames_) + 6 * parameters_.frame_index : 0;
    for (const Contact& c : contacts_) {
        const Mat3 w = factor * rotation * c.local_stiffness * rotation.transpose();
        const Index row = o1 + 3 * c.point;
        for (Index i = 0; i < 3; ++i)
            for (Index j = 0; j < 3; ++j) {
                t.emplace_back(row + i, row + j, w(i, j));
                if (!parameters_.object2_forces) continue;
                t.emplace_back(row + i, o2 + j, -w(i, j));
                t.emplace_back(o2 + i, row + j, -w(i, j));
                t.emplace_back(o2 + i, o2 + j, w(i, j));
            }
    }
}

}  // namespace penalty
