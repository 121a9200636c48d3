/// HexahedronFEMForceField (include/penalty/mechanics/fem.hpp), in SOFA's operations and order;
/// from OrderedScatter::kMinElements elements its force and product on TBB's threads with the
/// bits of one thread (LinearElementForceField::scatter_in_order).
#include "penalty/mechanics/fem.hpp"

#include "kernels/mechanics/hexahedron_stiffness.hpp"
#include "sofa_vector_ops.hpp"

#include <Eigen/Dense>

#include <array>
#include <cmath>

namespace penalty {

// ---- hexahedron, in SOFA's operations ------------------------------------------------------------
namespace {
/// Signs of the corners along x, y, z (HexahedronFEMForceField::_coef, SOFA's vertex order).
constexpr int kHexahedronCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                         {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

/// ∂X_c/∂ξ at the Gauss point (x1, x2, x3) of corners n (HexahedronFEMForceField::
/// computeElementStiffness, the general hexahedron's J(c, ·), each sum as written).
Mat3 hexahedron_jacobian(const std::array<Vec3, 8>& n, double x1, double x2, double x3) {
    Mat3 j;
    for (int c = 0; c < 3; ++c) {
        j(c, 0) = (n[1][c] - n[0][c]) * (1 - x2) * (1 - x3) / 8 + (n[2][c] - n[3][c]) * (1 + x2) * (1 - x3) / 8 +
                  (n[5][c] - n[4][c]) * (1 - x2) * (1 + x3) / 8 + (n[6][c] - n[7][c]) * (1 + x2) * (1 + x3) / 8;
        j(c, 1) = (n[3][c] - n[0][c]) * (1 - x1) * (1 - x3) / 8 + (n[2][c] - n[1][c]) * (1 + x1) * (1 - x3) / 8 +
                  (n[7][c] - n[4][c]) * (1 - x1) * (1 + x3) / 8 + (n[6][c] - n[5][c]) * (1 + x1) * (1 + x3) / 8;
        j(c, 2) = (n[4][c] - n[0][c]) * (1 - x1) * (1 - x2) / 8 + (n[5][c] - n[1][c]) * (1 + x1) * (1 - x2) / 8 +
                  (n[6][c] - n[2][c]) * (1 + x1) * (1 + x2) / 8 + (n[7][c] - n[3][c]) * (1 - x1) * (1 + x2) / 8;
    }
    return j;
}

/// Whether the corners n form a parallelepiped to 0.1 % of its edges (computeElementStiffness's
/// test): then J is constant, half the edges 0→1, 0→3, 0→4.
bool is_parallelepiped(const std::array<Vec3, 8>& n) {
    const Vec3 lx = sofa_vec::minus(n[1], n[0]), lz = sofa_vec::minus(n[4], n[0]);
    const auto off = [](const Vec3& a, const Vec3& b, const Vec3& c) {
        return sofa_vec::norm(sofa_vec::minus(sofa_vec::plus(a, b), c));
    };
    const double x = sofa_vec::norm(lx) * 0.001, z = sofa_vec::norm(lz) * 0.001;
    return off(n[3], lx, n[2]) < x && off(n[0], lz, n[4]) < z && off(n[1], lz, n[5]) < z && off(n[2], lz, n[6]) < z &&
           off(n[3], lz, n[7]) < z;
}

/// One Gauss point's contribution to K (the loop body of computeElementStiffness with SOFA's
/// DN_USE_J and MAT_STIFFNESS_USE_W): the shape gradients q = dN/dξ·J⁻¹, MBᵢ = M·Bᵢ with
/// M's U, V, W, kᵢⱼ = Bⱼᵀ·MBᵢ over B's non-zero pattern, times det J, added transposed into the
/// upper blocks j ≥ i.
void add_gauss_point(HexahedronFEMForceField::ElementMatrix& k, const Mat3& j_inverse, double det_j, double x1,
                     double x2, double x3, double u, double v, double w) {
    std::array<double, 8> qx{}, qy{}, qz{};
    for (int i = 0; i < 8; ++i) {
        const double c0 = kHexahedronCorner[i][0], c1 = kHexahedronCorner[i][1], c2 = kHexahedronCorner[i][2];
        const double dn1 = c0 * (1 + c1 * x2) * (1 + c2 * x3) / 8.0;
        const double dn2 = (1 + c0 * x1) * c1 * (1 + c2 * x3) / 8.0;
        const double dn3 = (1 + c0 * x1) * (1 + c1 * x2) * c2 / 8.0;
        qx[i] = dn1 * j_inverse(0, 0) + dn2 * j_inverse(1, 0) + dn3 * j_inverse(2, 0);
        qy[i] = dn1 * j_inverse(0, 1) + dn2 * j_inverse(1, 1) + dn3 * j_inverse(2, 1);
        qz[i] = dn1 * j_inverse(0, 2) + dn2 * j_inverse(1, 2) + dn3 * j_inverse(2, 2);
    }
    for (int i = 0; i < 8; ++i) {
        Eigen::Matrix<double, 6, 3> mb;
        mb << u * qx[i], v * qy[i], v * qz[i], v * qx[i], u * qy[i], v * qz[i], v * qx[i], v * qy[i], u * qz[i],
            w * qy[i], w * qx[i], 0.0, 0.0, w * qz[i], w * qy[i], w * qz[i], 0.0, w * qx[i];
        for (int jj = i; jj < 8; ++jj) {
            Mat3 b;  // Bⱼᵀ·MBᵢ
            b(0, 0) = qx[jj] * mb(0, 0) + qy[jj] * mb(3, 0) + qz[jj] * mb(5, 0);
            b(0, 1) = qx[jj] * mb(0, 1) + qy[jj] * mb(3, 1);
            b(0, 2) = qx[jj] * mb(0, 2) + qz[jj] * mb(5, 2);
            b(1, 0) = qy[jj] * mb(1, 0) + qx[jj] * mb(3, 0);
            b(1, 1) = qy[jj] * mb(1, 1) + qx[jj] * mb(3, 1) + qz[jj] * mb(4, 1);
            b(1, 2) = qy[jj] * mb(1, 2) + qz[jj] * mb(4, 2);
            b(2, 0) = qz[jj] * mb(2, 0) + qx[jj] * mb(5, 0);
            b(2, 1) = qz[jj] * mb(2, 1) + qy[jj] * mb(4, 1);
            b(2, 2) = qz[jj] * mb(2, 2) + qy[jj] * mb(4, 2) + qx[jj] * mb(5, 2);
            for (int m = 0; m < 3; ++m)
                for (int l = 0; l < 3; ++l) k(i * 3 + m, jj * 3 + l) += b(l, m) * det_j;
        }
    }
}
}  // namespace

HexahedronFEMForceField::ElementMatrix HexahedronFEMForceField::compute_stiffness(const std::array<Vec3, 8>&,
                                                                                  const Eigen::Matrix<double, 6, 6>&,
                                                                                  std::size_t e) const {
    if (!given_stiffness_.empty()) {
        if (e >= given_stiffness_.size())
            throw_invalid_argument(component_, ": no given stiffness for hexahedron ", e, " (", given_stiffness_.size(),
                                   " given)");
        return given_stiffness_[e];
    }
    // HexahedronFEMForceField::computeElementStiffness (GENERIC_STIFFNESS_MATRIX) on the element's
    // rotated rest corners (initSmall / initLarge / initPolar), eight Gauss points in SOFA's
    // order, then mirrored and times the stiffness factor
    const std::array<Vec3, 8> n = rotated_rest_corners(e, rest_rotation(e));
    // computeMaterialStiffness: the matrix (1, ν/(1−ν), (1−2ν)/(2(1−ν))) times E(1−ν)/((1+ν)(1−2ν))
    const double nu = poisson_;
    const double scale = (young_ * (1 - nu)) / ((1 + nu) * (1 - 2 * nu));
    const double u = 1.0 * scale, v = (nu / (1 - nu)) * scale, w = ((1 - 2 * nu) / (2 * (1 - nu))) * scale;
    const bool parallel = is_parallelepiped(n);
    Mat3 j;
    if (parallel) {
        const Vec3 lx = sofa_vec::minus(n[1], n[0]), ly = sofa_vec::minus(n[3], n[0]), lz = sofa_vec::minus(n[4], n[0]);
        for (int c = 0; c < 3; ++c) {
            j(c, 0) = lx[c] / 2;
            j(c, 1) = ly[c] / 2;
            j(c, 2) = lz[c] / 2;
        }
    }
    ElementMatrix k = ElementMatrix::Zero();
    const double inv_sqrt3 = 1.0 / std::sqrt(3.0);
    for (int g1 = -1; g1 <= 1; g1 += 2)
        for (int g2 = -1; g2 <= 1; g2 += 2)
            for (int g3 = -1; g3 <= 1; g3 += 2) {
                const double x1 = g1 * inv_sqrt3, x2 = g2 * inv_sqrt3, x3 = g3 * inv_sqrt3;
                if (!parallel) j = hexahedron_jacobian(n, x1, x2, x3);
                const double det_j = sofa_vec::determinant(j);
                if (!std::isfinite(det_j) || det_j <= 0.0)
                    throw_invalid_argument(component_, ": hexahedron ", e, " is degenerate or inverted (Jacobian ",
                                           det_j, ")");
                add_gauss_point(k, sofa_vec::inverse(j), det_j, x1, x2, x3, u, v, w);
            }
    for (int r = 0; r < 24; ++r)
        for (int c = r + 1; c < 24; ++c) k(c, r) = k(r, c);
    if (!stiffness_factors_.empty()) k *= stiffness_factors_.at(e);  // K *= stiffnessFactor
    return k;
}

Mat3 HexahedronFEMForceField::rest_rotation(std::size_t e) const {
    std::array<Vec3, 8> p;
    for (std::size_t w = 0; w < 8; ++w) p[w] = state_->rest_position[static_cast<std::size_t>(elements_[e][w])];
    return method_ == FemMethod::Small ? Mat3::Identity() : element_rotation(p);
}

std::array<Vec3, 8> HexahedronFEMForceField::rotated_rest_corners(std::size_t e, const Mat3& r0) const {
    // _rotatedInitialElements: R₀·x⁰_w, each corner on its own (R₀ the identity for small)
    std::array<Vec3, 8> n;
    for (std::size_t w = 0; w < 8; ++w)
        n[w] = sofa_vec::times(r0, state_->rest_position[static_cast<std::size_t>(elements_[e][w])]);
    return n;
}

void HexahedronFEMForceField::init() {
    LinearElementForceField<8>::init();  // K^e by compute_stiffness
    for (std::size_t e = 0; e < elements_.size(); ++e) {
        rotation_[e] = rest_rotation(e);
        rest_local_[e] = rotated_rest_corners(e, rotation_[e]);
    }
}

void HexahedronFEMForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3>) {
    PENALTY_DEMAND(ke_.size() == elements_.size());
    energy_ = force_in_order</*Add=*/true>(
        f, 1, [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred, double* energies) {
            return force_range(first, end, f, x, deferred, energies);
        });
}

double HexahedronFEMForceField::force_range(std::size_t first, std::size_t end, std::span<Vec3> f,
                                            std::span<const Vec3> x, const detail::DeferredTerms& deferred,
                                            double* energies) {
    // accumulateForceSmall / Large / Polar: D = R₀x⁰ − R·x (small: R₀x⁰ − x), F = K·D,
    // f += Rᵀ·F (small: f += F); energy ½ D·F (beyond SOFA)
    double total = 0.0;
    for (std::size_t e = first; e < end; ++e) {
        std::array<Vec3, 8> p;
        for (std::size_t w = 0; w < 8; ++w) p[w] = x[static_cast<std::size_t>(elements_[e][w])];
        const bool small = method_ == FemMethod::Small;
        if (!small) rotation_[e] = element_rotation(p);
        const Mat3& r = rotation_[e];
        Eigen::Matrix<double, 24, 1> d;
        for (std::size_t w = 0; w < 8; ++w) {
            const Vec3 deformed = small ? p[w] : sofa_vec::times(r, p[w]);
            for (std::size_t c = 0; c < 3; ++c)
                d[static_cast<Index>(3 * w + c)] =
                    rest_local_[e][w][static_cast<Index>(c)] - deformed[static_cast<Index>(c)];
        }
        const Eigen::Matrix<double, 24, 1> force = detail::hexahedron_stiffness_times(kernel_path_, ke_[e], d);
        std::array<Vec3, 8> terms;
        for (std::size_t w = 0; w < 8; ++w) {
            const Vec3 fw = force.segment<3>(static_cast<Index>(3 * w));
            terms[w] = small ? fw : sofa_vec::transpose_times(r, fw);
        }
        detail::store_or_apply(deferred, e, terms, [&](std::size_t w, const Vec3& term) {
            f[static_cast<std::size_t>(elements_[e][w])] += term;
        });
        const double energy = 0.5 * d.dot(force);
        if (energies) energies[e] = energy;
        else total += energy;
    }
    return total;
}

void HexahedronElementForceField::set_kernel_path(KernelPath path) {
    kernel_path_ = checked_kernel_path(path, component_, /*has_avx512=*/false);
}

void HexahedronFEMForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double) const {
    scatter_in_order</*Add=*/false>(df, 1,
                                    [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred) {
                                        dforce_range(first, end, df, dx, k_factor, deferred);
                                    });
}

void HexahedronFEMForceField::dforce_range(std::size_t first, std::size_t end, std::span<Vec3> df,
                                           std::span<const Vec3> dx, double k_factor,
                                           const detail::DeferredTerms& deferred) const {
    // addDForce: X = R·dx (the identity for small, as SOFA multiplies), F = K·X,
    // df −= (Rᵀ·F)·kFactor
    for (std::size_t e = first; e < end; ++e) {
        const Mat3& r = rotation_[e];
        Eigen::Matrix<double, 24, 1> local;
        for (std::size_t w = 0; w < 8; ++w)
            local.segment<3>(static_cast<Index>(3 * w)) =
                sofa_vec::times(r, dx[static_cast<std::size_t>(elements_[e][w])]);
        const Eigen::Matrix<double, 24, 1> force = detail::hexahedron_stiffness_times(kernel_path_, ke_[e], local);
        std::array<Vec3, 8> terms;
        for (std::size_t w = 0; w < 8; ++w)
            terms[w] = sofa_vec::scaled(sofa_vec::transpose_times(r, Vec3(force.segment<3>(static_cast<Index>(3 * w)))),
                                        k_factor);
        detail::store_or_apply(deferred, e, terms, [&](std::size_t w, const Vec3& term) {
            df[static_cast<std::size_t>(elements_[e][w])] -= term;
        });
    }
}

Mat3 hexahedron_edge_frame(const std::array<Vec3, 8>& p) {
    // initLarge / accumulateForceLarge: the mean edges, each summed as written, then
    // computeRotationLarge: x̂ = h/|h|, ẑ = (x̂ × v)/|x̂ × v|, ŷ = ẑ × x̂ (rows)
    const Vec3 horizontal = (p[1] - p[0] + p[2] - p[3] + p[5] - p[4] + p[6] - p[7]) * 0.25;
    const Vec3 vertical = (p[3] - p[0] + p[2] - p[1] + p[7] - p[4] + p[6] - p[5]) * 0.25;
    const Vec3 ex = sofa_vec::normalized(horizontal);
    const Vec3 ez = sofa_vec::normalized(sofa_vec::cross(ex, vertical));
    const Vec3 ey = sofa_vec::cross(ez, ex);
    Mat3 r;
    r << ex[0], ex[1], ex[2], ey[0], ey[1], ey[2], ez[0], ez[1], ez[2];
    return r;
}

Mat3 HexahedronFEMForceField::element_rotation(const std::array<Vec3, 8>& p) const {
    return method_ == FemMethod::Polar ? hexahedron_polar_frame(p) : hexahedron_edge_frame(p);
}

}  // namespace penalty
