#include "penalty/mechanics/beam_fem_force_field.hpp"

#include "sofa_quaternion.hpp"
#include "sofa_vector_ops.hpp"

#include <cmath>
#include <cstdint>
#include <numbers>

namespace penalty {

BeamFEMForceField::BeamFEMForceField(Rigid3Object& state, std::vector<std::array<Index, 2>> beams, BeamParameters p)
    : ForceField(state), beams_(std::move(beams)), p_(std::move(p)) {}

namespace {

using sofa_vec::in_element;

/// BeamFEMForceField::BeamInfo::init then computeStiffness (φy = φz = 0: SOFA's shear areas are 0).
BeamFEMForceField::Stiffness beam_local_stiffness(double e, double nu, double length, double r, double r_in) {
    const double g = e / (2.0 * (1.0 + nu));
    const double iz = std::numbers::pi * (r * r * r * r - r_in * r_in * r_in * r_in) / 4.0;
    const double iy = iz;
    const double j = iz + iy;
    const double area = std::numbers::pi * (r * r - r_in * r_in);
    const double phiy = 0.0, phiz = 0.0;
    const double l2 = length * length, l3 = l2 * length;
    const double eiy = e * iy, eiz = e * iz;
    BeamFEMForceField::Stiffness k = BeamFEMForceField::Stiffness::Zero();
    k(6, 6) = k(0, 0) = e * area / length;
    k(7, 7) = k(1, 1) = 12.0 * eiz / (l3 * (1.0 + phiy));
    k(8, 8) = k(2, 2) = 12.0 * eiy / (l3 * (1.0 + phiz));
    k(9, 9) = k(3, 3) = g * j / length;
    k(10, 10) = k(4, 4) = (4.0 + phiz) * eiy / (length * (1.0 + phiz));
    k(11, 11) = k(5, 5) = (4.0 + phiy) * eiz / (length * (1.0 + phiy));
    k(4, 2) = -6.0 * eiy / (l2 * (1.0 + phiz));
    k(5, 1) = 6.0 * eiz / (l2 * (1.0 + phiy));
    k(6, 0) = -k(0, 0);
    k(7, 1) = -k(1, 1);
    k(7, 5) = -k(5, 1);
    k(8, 2) = -k(2, 2);
    k(8, 4) = -k(4, 2);
    k(9, 3) = -k(3, 3);
    k(10, 2) = k(4, 2);
    k(10, 4) = (2.0 - phiz) * eiy / (length * (1.0 + phiz));
    k(10, 8) = -k(4, 2);
    k(11, 1) = k(5, 1);
    k(11, 5) = (2.0 - phiy) * eiz / (length * (1.0 + phiy));
    k(11, 7) = -k(5, 1);
    for (int r0 = 0; r0 <= 10; ++r0)
        for (int c = r0 + 1; c < 12; ++c) k(r0, c) = k(c, r0);
    return k;
}

/// SOFA's qDiff(a, b): b⁻¹ ⊗ a, a negated first when a·b < 0.
Quat q_diff(Quat a, const Quat& b) {
    if (a.x() * b.x() + a.y() * b.y() + a.z() * b.z() + a.w() * b.w() < 0) a = Quat(-a.w(), -a.x(), -a.y(), -a.z());
    return sofa_quat::product(sofa_quat::inverse(b), a);
}

/// k·d as type::Mat::operator*(Vec): row i = k(i,0)d₀, then += k(i,j)d_j for j = 1..11.
Eigen::Matrix<double, 12, 1> times(const BeamFEMForceField::Stiffness& k, const Eigen::Matrix<double, 12, 1>& d) {
    Eigen::Matrix<double, 12, 1> r;
    for (int i = 0; i < 12; ++i) {
        double s = k(i, 0) * d[0];
        for (int j = 1; j < 12; ++j) s += k(i, j) * d[j];
        r[i] = s;
    }
    return r;
}

}  // namespace

void BeamFEMForceField::init() {
    const auto n = state_->num_dofs();
    if (p_.young_modulus.empty() || p_.poisson_ratio.empty())
        throw_invalid_argument("BeamFEMForceField: needs a Young modulus and a Poisson ratio");
    k_.clear();
    for (std::size_t i = 0; i < beams_.size(); ++i) {
        const auto [a, b] = beams_[i];
        if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= n || static_cast<std::size_t>(b) >= n)
            throw_invalid_argument("BeamFEMForceField: beam ", i, " joins frames ", a, " and ", b, ", out of range (",
                                   n, " frames)");
        const Vec3 d = state_->rest_position[static_cast<std::size_t>(a)].center -
                       state_->rest_position[static_cast<std::size_t>(b)].center;
        const double length = std::sqrt(sofa_vec::dot3(d, d));
        if (!(length > 0)) throw_invalid_argument("BeamFEMForceField: beam ", i, " has zero rest length");
        k_.push_back(beam_local_stiffness(in_element(p_.young_modulus, i), in_element(p_.poisson_ratio, i), length,
                                          p_.radius, p_.radius_inner));
    }
    ends_.clear();
    for (const auto& [a, b] : beams_) ends_.push_back({static_cast<PointId>(a), static_cast<PointId>(b)});
    scatter_.clear();
    frame_.assign(beams_.size(), Quat::Identity());
    for (std::size_t i = 0; i < beams_.size(); ++i)
        frame_[i] = sofa_quat::normalized(state_->position[static_cast<std::size_t>(beams_[i][0])].orientation);
}

template <class Pass>
void BeamFEMForceField::scatter_ends_in_order(std::span<RigidDeriv> out, const Pass& pass) const {
    detail::scatter_stored_in_order(scatter_, std::span<const std::array<PointId, 2>>(ends_), deferred_terms_, pass,
                                    [&](std::size_t frame, const EndTerms& terms) {
                                        out[frame].linear += terms[0];
                                        out[frame].angular += terms[1];
                                    });
}

void BeamFEMForceField::add_end_terms(std::span<RigidDeriv> out, std::size_t beam, unsigned deferred,
                                      const std::array<EndTerms, 2>& terms) const {
    for (std::size_t end = 0; end < 2; ++end) {
        if ((deferred >> end) & 1U) {
            deferred_terms_[scatter_.deferred_slot(beam, end)] = terms[end];
            continue;
        }
        RigidDeriv& target = out[static_cast<std::size_t>(beams_[beam][end])];
        target.linear += terms[end][0];
        target.angular += terms[end][1];
    }
}

// BeamFEMForceField::accumulateForceLarge per beam, in edge order; from
// OrderedScatter::kMinElements beams on TBB's threads with the bits of one thread (an end's
// force and torque stored together where the scatter defers it, added in beam order after; the
// energies summed in beam order).
void BeamFEMForceField::add_force(std::span<RigidDeriv> f, std::span<const RigidFrame> x,
                                  std::span<const RigidDeriv> /*v*/) {
    const std::vector<RigidFrame>& x0 = state_->rest_position;
    const bool on_threads = detail::OrderedScatter::worth_threads(beams_.size());
    energies_.resize(on_threads ? beams_.size() : 0);
    double energy = 0.0;
    const auto pass = [&](std::size_t first, std::size_t last, const std::uint8_t* deferred_mask) {
        for (std::size_t i = first; i < last; ++i) {
            const auto a = static_cast<std::size_t>(beams_[i][0]), b = static_cast<std::size_t>(beams_[i][1]);
            frame_[i] = sofa_quat::normalized(x[a].orientation);
            const Vec3 rest = sofa_quat::inverse_rotate(x0[a].orientation, Vec3(x0[b].center - x0[a].center));
            const Vec3 now = sofa_quat::inverse_rotate(x[a].orientation, Vec3(x[b].center - x[a].center));
            const Vec3 u = now - rest;
            const Quat dq0 = sofa_quat::normalized(q_diff(x0[b].orientation, x0[a].orientation));
            const Quat dq = sofa_quat::normalized(q_diff(x[b].orientation, x[a].orientation));
            const Vec3 theta = sofa_quat::to_rotation_vector(sofa_quat::normalized(q_diff(dq, dq0)));
            Eigen::Matrix<double, 12, 1> d;
            d << 0, 0, 0, 0, 0, 0, u[0], u[1], u[2], theta[0], theta[1], theta[2];
            const Eigen::Matrix<double, 12, 1> force = times(k_[i], d);
            const double beam_energy = 0.5 * d.dot(force);
            if (on_threads) energies_[i] = beam_energy;
            else energy += beam_energy;
            const Quat& q = x[a].orientation;
            const Vec3 fa1 = sofa_quat::rotate(q, force.segment<3>(0)), fa2 = sofa_quat::rotate(q, force.segment<3>(3));
            const Vec3 fb1 = sofa_quat::rotate(q, force.segment<3>(6)), fb2 = sofa_quat::rotate(q, force.segment<3>(9));
            add_end_terms(f, i, deferred_mask != nullptr ? deferred_mask[i] : 0U, {{{-fa1, -fa2}, {-fb1, -fb2}}});
        }
    };
    scatter_ends_in_order(f, pass);
    if (on_threads)
        for (const double e : energies_) energy += e;
    energy_ = energy;
}

// BeamFEMForceField::applyStiffnessLarge: df += (−R k Rᵀ dx)·k_factor per beam (on threads as
// add_force).
void BeamFEMForceField::add_dforce(std::span<RigidDeriv> df, std::span<const RigidDeriv> dx, double k_factor,
                                   double /*b_factor*/) const {
    const auto pass = [&](std::size_t first, std::size_t last, const std::uint8_t* deferred_mask) {
        for (std::size_t i = first; i < last; ++i) {
            const auto a = static_cast<std::size_t>(beams_[i][0]), b = static_cast<std::size_t>(beams_[i][1]);
            const Quat q = sofa_quat::normalized(frame_[i]);
            Eigen::Matrix<double, 12, 1> d;
            d.segment<3>(0) = sofa_quat::inverse_rotate(q, dx[a].linear);
            d.segment<3>(3) = sofa_quat::inverse_rotate(q, dx[a].angular);
            d.segment<3>(6) = sofa_quat::inverse_rotate(q, dx[b].linear);
            d.segment<3>(9) = sofa_quat::inverse_rotate(q, dx[b].angular);
            const Eigen::Matrix<double, 12, 1> local = times(k_[i], d);
            const Vec3 fa1 = sofa_quat::rotate(q, local.segment<3>(0)), fa2 = sofa_quat::rotate(q, local.segment<3>(3));
            const Vec3 fb1 = sofa_quat::rotate(q, local.segment<3>(6)), fb2 = sofa_quat::rotate(q, local.segment<3>(9));
            add_end_terms(df, i, deferred_mask != nullptr ? deferred_mask[i] : 0U,
                          {{{sofa_vec::scaled(-fa1, k_factor), sofa_vec::scaled(-fa2, k_factor)},
                            {sofa_vec::scaled(-fb1, k_factor), sofa_vec::scaled(-fb2, k_factor)}}});
        }
    };
    scatter_ends_in_order(df, pass);
}

// BeamFEMForceField::buildStiffnessMatrix: −(R k Rᵀ) blockwise; with useSymmetricAssembly the
// upper blocks mirrored (the diagonal blocks averaged with their transposes).
void BeamFEMForceField::add_stiffness_triplets(TripletList& t, Index offset, double factor) const {
    for (std::size_t i = 0; i < beams_.size(); ++i) {
        const Mat3 r = sofa_quat::to_matrix(sofa_quat::normalized(frame_[i]));
        Stiffness k = Stiffness::Zero();
        for (int x1 = 0; x1 < 12; x1 += 3)
            for (int y1 = p_.symmetric_assembly ? x1 : 0; y1 < 12; y1 += 3) {
                const Mat3 m = r * k_[i].block<3, 3>(x1, y1) * r.transpose();
                if (!p_.symmetric_assembly) {
                    k.block<3, 3>(x1, y1) = m;
                    continue;
                }
                k.block<3, 3>(x1, y1) += m;
                k.block<3, 3>(y1, x1) += m.transpose();
                if (x1 == y1) k.block<3, 3>(x1, y1) *= 0.5;
            }
        Index index[12];
        for (Index c = 0; c < 6; ++c) {
            index[c] = offset + 6 * beams_[i][0] + c;
            index[6 + c] = offset + 6 * beams_[i][1] + c;
        }
        for (int x1 = 0; x1 < 12; ++x1)
            for (int y1 = 0; y1 < 12; ++y1) t.emplace_back(index[x1], index[y1], -k(x1, y1) * factor);
    }
}

}  // namespace penalty
