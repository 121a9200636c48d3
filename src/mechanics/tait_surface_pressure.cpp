#include "penalty/mechanics/tait_surface_pressure.hpp"

#include "sofa_vector_ops.hpp"

#include <cmath>

namespace penalty {

using sofa_vec::cross;
using sofa_vec::dot3;
using sofa_vec::scaled;

TaitSurfacePressureForceField::TaitSurfacePressureForceField(Vec3Object& state, const MeshTopology& topology,
                                                             TaitParameters p, ContextClock clock, ContextClock dt)
    : ForceField(state), topology_(&topology), p_(p), clock_(std::move(clock)), dt_(std::move(dt)) {}

void TaitSurfacePressureForceField::take_pressure_triangles() {
    triangles_ = topology_->triangles();
    for (const Quad& q : topology_->quads()) {
        triangles_.push_back({q[0], q[1], q[2]});
        triangles_.push_back({q[2], q[3], q[0]});
    }
}

// TaitSurfacePressureForceField::init → updateFromTopology at the topology's first revision
// (computePressureTriangles; volumeAfterTC, the rest volume, is the initialVolume).
void TaitSurfacePressureForceField::init() {
    take_pressure_triangles();
    for (const Triangle& t : triangles_)
        for (PointId v : t)
            if (v < 0 || std::size_t(v) >= state_->num_dofs())
                throw_invalid_argument("TaitSurfacePressureForceField: surface point ", v, " out of range (",
                                       state_->num_dofs(), " points)");
    initial_volume_ = volume_of(state_->rest_position);
    volume_after_change_ = initial_volume_;
    initial_area_ = area_after_change_ = area_of(state_->rest_position);
    current_injected_ = p_.current_injected_volume;
    last_step_time_ = -1e300;
    volume_ = volume_of(state_->position);
    pressure_and_stiffness(volume_, initial_volume_);
}

// computeMeshVolumeAndArea's volume: about the mean point, Σ ((a×b)·c)/6.
double TaitSurfacePressureForceField::volume_of(std::span<const Vec3> x) const {
    if (x.empty()) return 0;
    Vec3 center = Vec3::Zero();
    for (const Vec3& p : x) center += p;
    center /= double(x.size());
    double volume6 = 0;
    for (const Triangle& t : triangles_) {
        const Vec3 a = x[std::size_t(t[0])] - center, b = x[std::size_t(t[1])] - center,
                   c = x[std::size_t(t[2])] - center;
        volume6 += dot3(cross(a, b), c);
    }
    return volume6 / 6.0;
}

// computeMeshVolumeAndArea's area: Σ |(b − a)×(c − a)| / 2 (about the mean point, as SOFA).
double TaitSurfacePressureForceField::area_of(std::span<const Vec3> x) const {
    if (x.empty()) return 0;
    Vec3 center = Vec3::Zero();
    for (const Vec3& p : x) center += p;
    center /= double(x.size());
    double area2 = 0;
    for (const Triangle& t : triangles_) {
        const Vec3 a = x[std::size_t(t[0])] - center, b = x[std::size_t(t[1])] - center,
                   c = x[std::size_t(t[2])] - center;
        area2 += cross(b - a, c - a).norm();
    }
    return area2 / 2.0;
}

// updateFromTopology when the revision moved after init: the topology's surface again and its
// rest volume as volumeAfterTC (initialVolume, from init, is kept).
void TaitSurfacePressureForceField::topology_changed() {
    take_pressure_triangles();
    volume_after_change_ = volume_of(state_->rest_position);
    area_after_change_ = area_of(state_->rest_position);
    grad_v_.clear();
    x_.clear();
}

// computePressureAndStiffness (its "too much volume variation" zeroing is overwritten at once in
// SOFA: not reproduced as a separate case).
void TaitSurfacePressureForceField::pressure_and_stiffness(double volume, double v0) {
    const double b = p_.bulk_modulus, gamma = p_.gamma, p0 = p_.p0;
    if (b == 0 || gamma == 0 || v0 == 0) {
        stiffness_ = 0;
        pressure_ = p0;
        energy_ = -p0 * volume;
    } else if (gamma == 1) {
        stiffness_ = -b / v0;
        pressure_ = p0 - b * (volume / v0 - 1);
        energy_ = -p0 * volume + b * (volume * volume / (2 * v0) - volume);
    } else {
        const double ratio = std::pow(volume / v0, gamma);
        stiffness_ = volume == 0 ? 0 : -b * gamma * ratio / volume;
        pressure_ = p0 - b * (ratio - 1);
        energy_ = -p0 * volume + b * (ratio * volume / (gamma + 1) - volume);
    }
}

void TaitSurfacePressureForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> /*v*/) {
    // handleEvent(AnimateBeginEvent): once per step, at its start time
    const double now = clock_();
    if (now != last_step_time_) {
        last_step_time_ = now;
        const double inj = p_.injected_volume;
        if (inj != current_injected_) {
            const double max_inj = p_.max_injection_rate * dt_();
            if (std::fabs(inj - current_injected_) <= max_inj) current_injected_ = inj;
            else if (inj < current_injected_) current_injected_ -= max_inj;
            else current_injected_ += max_inj;
        }
    }
    const double v0 = initial_volume_ + current_injected_;
    volume_ = volume_of(x);
    // addForce's correction after a topological change (d_volumeAfterTC is set from init on: 0 until a change)
    pressure_and_stiffness(volume_ - (volume_after_change_ - initial_volume_), v0);
    grad_v_.assign(x.size(), Vec3::Zero());
    for (const Triangle& t : triangles_) {
        const Vec3 n = cross(x[std::size_t(t[1])] - x[std::size_t(t[0])], x[std::size_t(t[2])] - x[std::size_t(t[0])]);
        for (PointId v : t) grad_v_[std::size_t(v)] += n;
    }
    for (Vec3& g : grad_v_) g = Vec3(g[0] / 6, g[1] / 6, g[2] / 6);
    for (std::size_t i = 0; i < x.size(); ++i) f[i] += scaled(grad_v_[i], pressure_);
    x_.assign(x.begin(), x.end());
}

// TaitSurfacePressureForceField::addDForce.
void TaitSurfacePressureForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                               double /*b_factor*/) const {
    if (x_.empty()) return;  // no add_force since a topological change
    double dv = 0;
    for (std::size_t i = 0; i < grad_v_.size(); ++i) dv += dot3(grad_v_[i], dx[i]);
    const double scale1 = k_factor * stiffness_ * dv;
    for (std::size_t i = 0; i < x_.size(); ++i) df[i] += scaled(grad_v_[i], scale1);
    const double scale2 = k_factor * pressure_ / 6;
    for (const Triangle& t : triangles_) {
        const auto a = std::size_t(t[0]), b = std::size_t(t[1]), c = std::size_t(t[2]);
        const Vec3 d = scaled(cross(dx[b] - dx[a], x_[c] - x_[a]) + cross(x_[b] - x_[a], dx[c] - dx[a]), scale2);
        df[a] += d;
        df[b] += d;
        df[c] += d;
    }
}

namespace {
using sofa_vec::cross_matrix;  // [u]× v = u × v
}  // namespace

void TaitSurfacePressureForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    if (x_.empty()) return;  // no add_force since a topological change
    const auto add = [&](std::size_t r, std::size_t c, const Mat3& m) {
        for (Index i = 0; i < 3; ++i)
            for (Index j = 0; j < 3; ++j)
                t.emplace_back(offset + 3 * Index(r) + i, offset + 3 * Index(c) + j, m(i, j) * factor);
    };
    if (stiffness_ != 0)
        for (std::size_t i = 0; i < grad_v_.size(); ++i) {
            if (grad_v_[i].isZero(0)) continue;
            for (std::size_t j = 0; j < grad_v_.size(); ++j)
                if (!grad_v_[j].isZero(0)) add(i, j, stiffness_ * grad_v_[i] * grad_v_[j].transpose());
        }
    if (pressure_ == 0) return;
    const double s = pressure_ / 6;
    for (const Triangle& tri : triangles_) {
        const auto a = std::size_t(tri[0]), b = std::size_t(tri[1]), c = std::size_t(tri[2]);
        const Mat3 e1 = cross_matrix(x_[b] - x_[a]) * s, e2 = cross_matrix(x_[c] - x_[a]) * s;
        for (const std::size_t r : {a, b, c}) {
            add(r, b, -e2);
            add(r, a, e2 - e1);
            add(r, c, e1);
        }
    }
}

}  // namespace penalty
