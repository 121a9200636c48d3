// The hyperelastic materials of TetrahedronHyperelasticityFEMForceField (hyperelastic_fem.hpp):
// W(C), S = 2∂W/∂C and dS[H], as SOFA's material/*.h deriveSPKTensor and applyElasticityTensor
// give them, in Eigen's 3×3 algebra.
#include "penalty/mechanics/hyperelastic_fem.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <cmath>

namespace penalty {

std::string_view material_name(HyperelasticMaterial m) {
    switch (m) {
        case HyperelasticMaterial::ArrudaBoyce:
            return "ArrudaBoyce";
        case HyperelasticMaterial::StVenantKirchhoff:
            return "StVenantKirchhoff";
        case HyperelasticMaterial::NeoHookean:
            return "NeoHookean";
        case HyperelasticMaterial::MooneyRivlin:
            return "MooneyRivlin";
        case HyperelasticMaterial::Ogden:
            return "Ogden";
    }
    return "";
}

std::size_t material_parameter_count(HyperelasticMaterial m) {
    return m == HyperelasticMaterial::MooneyRivlin || m == HyperelasticMaterial::Ogden ? 3 : 2;
}

namespace {

/// BoyceAndArruda's coefficients cᵢ of (J^(−2i/3) I₁ⁱ − 3ⁱ), i = 1 … 5.
constexpr std::array<double, 5> kArrudaBoyce{1.0 / 2.0, 1.0 / 160.0, 11.0 / (1050.0 * 8 * 8),
                                             19.0 / (7000.0 * 8 * 8 * 8), 519.0 / (673750.0 * 8 * 8 * 8 * 8)};

/// What the laws share at one C: C⁻¹, I₁, ln J.
struct Invariants {
    Mat3 c_inverse;
    double i1;
    double log_j;
    Invariants(const Mat3& c, double j) : c_inverse(c.inverse()), i1(c.trace()), log_j(std::log(j)) {}
};

/// Ogden's spectral quantities: P = C^(α/2 − 1), T = tr C^(α/2), and C's eigen decomposition.
struct OgdenSpectrum {
    Eigen::SelfAdjointEigenSolver<Mat3> eigen;
    Mat3 power;    ///< P
    double trace;  ///< T
    OgdenSpectrum(const Mat3& c, double alpha) : eigen(c) {
        const Vec3 l = eigen.eigenvalues();
        const Mat3& v = eigen.eigenvectors();
        const double p = alpha / 2 - 1;
        power = v * Vec3(std::pow(l[0], p), std::pow(l[1], p), std::pow(l[2], p)).asDiagonal() * v.transpose();
        trace = std::pow(l[0], alpha / 2) + std::pow(l[1], alpha / 2) + std::pow(l[2], alpha / 2);
    }
    /// dP[H] = V (G ∘ VᵀHV) Vᵀ, G_ab = (λₐᵖ − λ_bᵖ)/(λₐ − λ_b), or p λₐ^(p−1) when
    /// |λₐ − λ_b| < 1e-8·max(|λₐ|, |λ_b|) (Ogden::ElasticityTensor's degenerate case).
    [[nodiscard]] Mat3 power_derivative(double alpha, const Mat3& h) const {
        const Vec3 l = eigen.eigenvalues();
        const Mat3& v = eigen.eigenvectors();
        const double p = alpha / 2 - 1;
        Mat3 g;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                const double scale = std::max(std::abs(l[a]), std::abs(l[b]));
                g(a, b) = std::abs(l[a] - l[b]) < 1e-8 * scale
                              ? p * std::pow(l[a], p - 1)
                              : (std::pow(l[a], p) - std::pow(l[b], p)) / (l[a] - l[b]);
            }
        return v * g.cwiseProduct(v.transpose() * h * v) * v.transpose();
    }
};

}  // namespace

double HyperelasticLaw::energy_density(const Mat3& c, double j) const {
    const auto& q = parameters;
    const double log_j = std::log(j), i1 = c.trace();
    switch (material) {
        case HyperelasticMaterial::ArrudaBoyce: {
            double w = 0;
            for (int i = 1; i <= 5; ++i)
                w += kArrudaBoyce[static_cast<std::size_t>(i - 1)] *
                     (std::pow(j, -2.0 * i / 3) * std::pow(i1, i) - std::pow(3.0, i));
            return q[0] * w + q[1] * log_j * log_j / 2;
        }
        case HyperelasticMaterial::StVenantKirchhoff: {
            const Mat3 e = (c - Mat3::Identity()) / 2;
            return q[1] / 2 * e.trace() * e.trace() + q[0] * (e * e).trace();
        }
        case HyperelasticMaterial::NeoHookean:
            return q[0] / 2 * (i1 - 3) - q[0] * log_j + q[1] / 2 * log_j * log_j;
        case HyperelasticMaterial::MooneyRivlin: {
            const double i2 = (i1 * i1 - (c * c).trace()) / 2;
            return q[0] * (std::pow(j, -2.0 / 3) * i1 - 3) + q[1] * (std::pow(j, -4.0 / 3) * i2 - 3) +
                   q[2] * log_j * log_j / 2;
        }
        case HyperelasticMaterial::Ogden: {
            const OgdenSpectrum s(c, q[1]);
            return q[0] / (q[1] * q[1]) * (std::pow(j, -q[1] / 3) * s.trace - 3) + q[2] * log_j * log_j / 2;
        }
    }
    return 0;
}

Mat3 HyperelasticLaw::second_piola(const Mat3& c, double j) const {
    const auto& q = parameters;
    const Invariants v(c, j);
    const Mat3 id = Mat3::Identity();
    switch (material) {
        case HyperelasticMaterial::ArrudaBoyce: {
            // 2μ Σ cᵢ J^(−2i/3) (i I₁^(i−1) I − (i/3) I₁ⁱ C⁻¹) + k₀ ln J C⁻¹
            Mat3 s = Mat3::Zero();
            for (int i = 1; i <= 5; ++i)
                s += kArrudaBoyce[static_cast<std::size_t>(i - 1)] * std::pow(j, -2.0 * i / 3) *
                     (i * std::pow(v.i1, i - 1) * id - (i / 3.0) * std::pow(v.i1, i) * v.c_inverse);
            return 2 * q[0] * s + q[1] * v.log_j * v.c_inverse;
        }
        case HyperelasticMaterial::StVenantKirchhoff:
            return (q[1] * 0.5 * (v.i1 - 3) - q[0]) * id + q[0] * c;
        case HyperelasticMaterial::NeoHookean:
            return q[0] * id + (q[1] * v.log_j - q[0]) * v.c_inverse;
        case HyperelasticMaterial::MooneyRivlin: {
            const double i2 = (v.i1 * v.i1 - (c * c).trace()) / 2;
            return 2 * q[0] * std::pow(j, -2.0 / 3) * (id - v.i1 / 3 * v.c_inverse) +
                   2 * q[1] * std::pow(j, -4.0 / 3) * (v.i1 * id - c - 2 * i2 / 3 * v.c_inverse) +
                   q[2] * v.log_j * v.c_inverse;
        }
        case HyperelasticMaterial::Ogden: {
            const OgdenSpectrum s(c, q[1]);
            const double fj = std::pow(j, -q[1] / 3);
            return fj * q[0] / q[1] * (s.power - s.trace / 3 * v.c_inverse) + q[2] * v.log_j * v.c_inverse;
        }
    }
    return Mat3::Zero();
}

Mat3 HyperelasticLaw::stress_derivative(const Mat3& c, double j, const Mat3& h) const {
    const auto& q = parameters;
    const Invariants v(c, j);
    const Mat3 id = Mat3::Identity();
    const Mat3 chc = v.c_inverse * h * v.c_inverse;  // C⁻¹HC⁻¹ = −dC⁻¹
    const double tr_h = h.trace();
    const double tr_hc = (v.c_inverse * h).trace();                   // C⁻¹:H = 2 d(ln J)
    const Mat3 volumetric = tr_hc / 2 * v.c_inverse - v.log_j * chc;  // d(ln J C⁻¹)
    switch (material) {
        case HyperelasticMaterial::ArrudaBoyce: {
            Mat3 ds = Mat3::Zero();
            for (int i = 1; i <= 5; ++i) {
                const double a = i * std::pow(v.i1, i - 1), b = (i / 3.0) * std::pow(v.i1, i);
                const double da = i * (i - 1) * (i >= 2 ? std::pow(v.i1, i - 2) : 0.0) * tr_h,
                             db = i * (i / 3.0) * std::pow(v.i1, i - 1) * tr_h;
                const Mat3 term = a * id - b * v.c_inverse;
                const Mat3 dterm = da * id - db * v.c_inverse + b * chc;
                ds += kArrudaBoyce[static_cast<std::size_t>(i - 1)] * std::pow(j, -2.0 * i / 3) *
                      (dterm - (i / 3.0) * tr_hc * term);
            }
            return 2 * q[0] * ds + q[1] * volumetric;
        }
        case HyperelasticMaterial::StVenantKirchhoff:
            return q[1] / 2 * tr_h * id + q[0] * h;
        case HyperelasticMaterial::NeoHookean:
            return (q[0] - q[1] * v.log_j) * chc + q[1] * tr_hc / 2 * v.c_inverse;
        case HyperelasticMaterial::MooneyRivlin: {
            const double i2 = (v.i1 * v.i1 - (c * c).trace()) / 2;
            const double di2 = v.i1 * tr_h - (c * h).trace();
            const Mat3 a1 = id - v.i1 / 3 * v.c_inverse, a2 = v.i1 * id - c - 2 * i2 / 3 * v.c_inverse;
            const Mat3 da1 = -tr_h / 3 * v.c_inverse + v.i1 / 3 * chc;
            const Mat3 da2 = tr_h * id - h - 2.0 / 3 * (di2 * v.c_inverse - i2 * chc);
            return 2 * q[0] * std::pow(j, -2.0 / 3) * (da1 - tr_hc / 3 * a1) +
                   2 * q[1] * std::pow(j, -4.0 / 3) * (da2 - 2 * tr_hc / 3 * a2) + q[2] * volumetric;
        }
        case HyperelasticMaterial::Ogden: {
            const double alpha = q[1];
            const OgdenSpectrum s(c, alpha);
            const double fj = std::pow(j, -alpha / 3);
            const double dfj = -alpha / 6 * fj * tr_hc;
            const double dtrace = alpha / 2 * (s.power * h).trace();
            const Mat3 iso = s.power - s.trace / 3 * v.c_inverse;
            const Mat3 diso = s.power_derivative(alpha, h) - dtrace / 3 * v.c_inverse + s.trace / 3 * chc;
            return q[0] / alpha * (dfj * iso + fj * diso) + q[2] * volumetric;
        }
    }
    return Mat3::Zero();
}

}  // namespace penalty
