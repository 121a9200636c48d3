// SOFA's plasticity of TetrahedronFEMForceField (method large): the force of each element as
// TetrahedronFEMForceField::accumulateForceLarge and computeForce compute it with
// plasticMaxThreshold > 0, in SOFA's operation order (fem.hpp, TetrahedronFEMForceField::Plasticity).
#include "kernels/mechanics/tetrahedron_large.hpp"
#include "penalty/mechanics/fem.hpp"

#include "sofa_vector_ops.hpp"
#include "tetrahedron_large_element.hpp"

#include <cmath>
#include <type_traits>
#include <variant>

namespace penalty {

void TetrahedronFEMForceField::set_plasticity(const Plasticity& p) {
    if (method_ != FemMethod::Large && p.max_threshold > 0)
        throw_invalid_argument(component_,
                               ": plasticity (plasticMaxThreshold > 0) is supported with method large only");
    for (const double v : {p.max_threshold, p.yield_threshold, p.creep})
        if (!std::isfinite(v) || v < 0)
            throw_invalid_argument(component_, ": plasticity thresholds and creep must be finite and >= 0, got ", v);
    plasticity_ = p;
    plastic_strain_.assign(elements_.size(), std::array<double, 6>{});
}

namespace {

/// F of computeForce with plasticity: Jᵀδ over J's non-zero terms, the plastic update, K·(Jᵀδ −
/// εp) over K's non-zero terms, then J·(KJᵀD); each sum left to right as SOFA writes it. j(r, c)
/// and k(i, k) give J's and D/(36V)'s entries (an element's lane).
template <class StrainDisplacementEntries, class MaterialEntries>
Eigen::Matrix<double, 12, 1> plastic_force(const StrainDisplacementEntries& j, const MaterialEntries& k,
                                           const Eigen::Matrix<double, 12, 1>& d, std::array<double, 6>& plastic,
                                           const TetrahedronFEMForceField::Plasticity& p) {
    std::array<double, 6> e;
    e[0] = j(0, 0) * d[0] + j(3, 0) * d[3] + j(6, 0) * d[6] + j(9, 0) * d[9];
    e[1] = j(1, 1) * d[1] + j(4, 1) * d[4] + j(7, 1) * d[7] + j(10, 1) * d[10];
    e[2] = j(2, 2) * d[2] + j(5, 2) * d[5] + j(8, 2) * d[8] + j(11, 2) * d[11];
    e[3] = j(0, 3) * d[0] + j(1, 3) * d[1] + j(3, 3) * d[3] + j(4, 3) * d[4] + j(6, 3) * d[6] + j(7, 3) * d[7] +
           j(9, 3) * d[9] + j(10, 3) * d[10];
    e[4] = j(1, 4) * d[1] + j(2, 4) * d[2] + j(4, 4) * d[4] + j(5, 4) * d[5] + j(7, 4) * d[7] + j(8, 4) * d[8] +
           j(10, 4) * d[10] + j(11, 4) * d[11];
    e[5] = j(0, 5) * d[0] + j(2, 5) * d[2] + j(3, 5) * d[3] + j(5, 5) * d[5] + j(6, 5) * d[6] + j(8, 5) * d[8] +
           j(9, 5) * d[9] + j(11, 5) * d[11];
    // elastic = total − plastic; creep when |elastic|² > yield²; clamp |plastic| to max
    std::array<double, 6> elastic;
    for (std::size_t i = 0; i < 6; ++i) elastic[i] = e[i] - plastic[i];
    double norm2 = elastic[0] * elastic[0];
    for (std::size_t i = 1; i < 6; ++i) norm2 += elastic[i] * elastic[i];
    if (norm2 > p.yield_threshold * p.yield_threshold)
        for (std::size_t i = 0; i < 6; ++i) plastic[i] += p.creep * elastic[i];
    double plastic_norm2 = plastic[0] * plastic[0];
    for (std::size_t i = 1; i < 6; ++i) plastic_norm2 += plastic[i] * plastic[i];
    if (plastic_norm2 > p.max_threshold * p.max_threshold) {
        const double scale = p.max_threshold / std::sqrt(plastic_norm2);
        for (double& v : plastic) v *= scale;
    }
    for (std::size_t i = 0; i < 6; ++i) e[i] -= plastic[i];
    std::array<double, 6> s;
    for (int i = 0; i < 3; ++i) s[std::size_t(i)] = k(i, 0) * e[0] + k(i, 1) * e[1] + k(i, 2) * e[2];
    for (int i = 3; i < 6; ++i) s[std::size_t(i)] = k(i, i) * e[std::size_t(i)];
    Eigen::Matrix<double, 12, 1> f;
    for (int v = 0; v < 4; ++v) {
        const int r = 3 * v;
        f[r] = j(r, 0) * s[0] + j(r, 3) * s[3] + j(r, 5) * s[5];
        f[r + 1] = j(r + 1, 1) * s[1] + j(r + 1, 3) * s[3] + j(r + 1, 4) * s[4];
        f[r + 2] = j(r + 2, 2) * s[2] + j(r + 2, 4) * s[4] + j(r + 2, 5) * s[5];
    }
    return f;
}

}  // namespace

void TetrahedronFEMForceField::add_force_plastic(std::span<Vec3> f, std::span<const Vec3> x) {
    if (plastic_strain_.size() != elements_.size()) plastic_strain_.assign(elements_.size(), std::array<double, 6>{});
    energy_ = 0.0;
    std::visit(
        [&](auto& blocks) {
            using Block = typename std::remove_cvref_t<decltype(blocks)>::value_type;
            for (std::size_t e = 0; e < elements_.size(); ++e) {
                const auto& el = elements_[e];
                const auto vertex = [&](std::size_t k) { return static_cast<std::size_t>(el[k]); };
                Block& block = blocks[e / Block::kLanes];
                const std::size_t lane = e % Block::kLanes;
                const Mat3 r = detail::large_frame(x[vertex(0)], x[vertex(1)], x[vertex(2)]);
                detail::store_lane_rotation(block, lane, r);  // the products' R
                std::array<Vec3, 4> deformed;
                for (std::size_t k = 0; k < 4; ++k) deformed[k] = sofa_vec::times(r, x[vertex(k)]);
                const auto& rest = rest_local_[e];
                Eigen::Matrix<double, 12, 1> delta = Eigen::Matrix<double, 12, 1>::Zero();
                delta[3] = rest[1][0] - (deformed[1][0] - deformed[0][0]);
                delta[6] = rest[2][0] - (deformed[2][0] - deformed[0][0]);
                delta[7] = rest[2][1] - (deformed[2][1] - deformed[0][1]);
                for (int c = 0; c < 3; ++c) delta[9 + c] = rest[3][c] - (deformed[3][c] - deformed[0][c]);
                const Eigen::Matrix<double, 12, 1> force = plastic_force(
                    detail::LaneStrainDisplacement<detail::OneLane, Block>{block, lane},
                    detail::LaneMaterial<detail::OneLane, Block>{block, lane}, delta, plastic_strain_[e], plasticity_);
                energy_ += 0.5 * delta.dot(force);
                for (std::size_t k = 0; k < 4; ++k)
                    f[vertex(k)] += sofa_vec::transpose_times(r, force.segment<3>(3 * static_cast<Index>(k)));
            }
        },
        large_);
}

}  // namespace penalty
