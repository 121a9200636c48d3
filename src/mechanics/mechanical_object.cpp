#include "penalty/mechanics/mechanical_object.hpp"

#include <cmath>
#include <numbers>

namespace penalty {

Quat InitialTransform::rotation() const {
    const double k = std::numbers::pi / 180.0;
    return Quat(Eigen::AngleAxisd(rotation_deg.z() * k, Vec3::UnitZ()) *
                Eigen::AngleAxisd(rotation_deg.y() * k, Vec3::UnitY()) *
                Eigen::AngleAxisd(rotation_deg.x() * k, Vec3::UnitX()));
}

RigidFrame rigid_add(const RigidFrame& x, const RigidDeriv& v, double h) {
    RigidFrame out;
    out.center = x.center + h * v.linear;
    const Vec3 w = h * v.angular;
    const Quat omega(0.0, w.x(), w.y(), w.z());
    const Quat dq = omega * x.orientation;
    Quat q(x.orientation.w() + 0.5 * dq.w(), x.orientation.x() + 0.5 * dq.x(),
           x.orientation.y() + 0.5 * dq.y(), x.orientation.z() + 0.5 * dq.z());
    q.normalize();
    out.orientation = q;
    return out;
}

namespace {
void check_finite(const Vec3& p, std::string_view name, std::size_t i) {
    if (!p.allFinite()) throw_invalid_argument("MechanicalObject '", name, "': position[", i, "] is not finite");
}
}  // namespace

template <>
void MechanicalObject<Vec3Types>::add_to_position(double h, const Eigen::Ref<const Eigen::VectorXd>& v) {
    PENALTY_DEMAND(static_cast<std::size_t>(v.size()) == scalar_size());
    for (std::size_t i = 0; i < position.size(); ++i) position[i] += h * v.segment<3>(static_cast<Eigen::Index>(3 * i));
}

template <>
void MechanicalObject<Rigid3Types>::add_to_position(double h, const Eigen::Ref<const Eigen::VectorXd>& v) {
    PENALTY_DEMAND(static_cast<std::size_t>(v.size()) == scalar_size());
    for (std::size_t i = 0; i < position.size(); ++i) {
        RigidDeriv d;
        d.linear = v.segment<3>(static_cast<Eigen::Index>(6 * i));
        d.angular = v.segment<3>(static_cast<Eigen::Index>(6 * i + 3));
        position[i] = rigid_add(position[i], d, h);
    }
}

namespace {
/// SOFA's size rules: rest positions given without positions become the positions; fewer
/// velocities than positions are completed with the last given one.
template <class State>
void complete_sizes(State& s) {
    if (s.rest_position.size() > s.position.size()) s.position = s.rest_position;
    const std::size_t n = s.position.size();
    if (s.velocity.size() > n)
        throw_invalid_argument("MechanicalObject '", s.name, "': ", s.velocity.size(), " velocities for ", n, " positions");
    if (!s.velocity.empty() && s.velocity.size() < n) s.velocity.resize(n, s.velocity.back());
}
}  // namespace

template <>
void MechanicalObject<Vec3Types>::init() {
    complete_sizes(*this);
    const std::size_t n = position.size();
    for (std::size_t i = 0; i < n; ++i) check_finite(position[i], name, i);
    if (!transform.is_identity() && !initialized_) {
        // SOFA's reinit(): scale, rotation, translation of the positions only; the rest
        // positions are copied from the transformed positions unless given with the right size.
        const Mat3 r = transform.rotation().toRotationMatrix();
        for (auto& p : position) p = r * p.cwiseProduct(transform.scale3d) + transform.translation;
    }
    if (rest_position.size() != n) rest_position = position;
    velocity.resize(n, Vec3::Zero());
    force.assign(n, Vec3::Zero());
    external_force.assign(n, Vec3::Zero());
    dx.assign(n, Vec3::Zero());
    df.assign(n, Vec3::Zero());
    initialized_ = true;
}

template <>
void MechanicalObject<Rigid3Types>::init() {
    complete_sizes(*this);
    const std::size_t n = position.size();
    for (std::size_t i = 0; i < n; ++i) {
        check_finite(position[i].center, name, i);
        if (!position[i].orientation.coeffs().allFinite() || position[i].orientation.norm() < 1e-12) {
            throw_invalid_argument("MechanicalObject '", name, "': position[", i, "] has an invalid quaternion");
        }
        position[i].orientation.normalize();
    }
    if (!transform.is_identity() && !initialized_) {
        const Quat q = transform.rotation();
        auto apply = [&](RigidFrame& p) {
            p.center = q * p.center.cwiseProduct(transform.scale3d) + transform.translation;
            p.orientation = q * p.orientation;
        };
        for (auto& p : position) apply(p);
    }
    if (rest_position.size() != n) rest_position = position;
    velocity.resize(n);
    force.assign(n, RigidDeriv{});
    external_force.assign(n, RigidDeriv{});
    dx.assign(n, RigidDeriv{});
    df.assign(n, RigidDeriv{});
    initialized_ = true;
}


}  // namespace penalty
