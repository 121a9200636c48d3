// SOFA's TetrahedronHyperelasticityFEMForceField (hyperelastic_fem.hpp): forces f = −V₀ F S g and
// the exact per-element stiffness blocks, in Eigen's 3×3 algebra.
#include "penalty/mechanics/hyperelastic_fem.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace penalty {

TetrahedronHyperelasticityFEMForceField::TetrahedronHyperelasticityFEMForceField(Vec3Object& state,
                                                                                 std::vector<Tetrahedron> tetrahedra,
                                                                                 HyperelasticLaw law)
    : ForceField<Vec3Types>(state), tetrahedra_(std::move(tetrahedra)), law_(std::move(law)) {
    const std::size_t n = material_parameter_count(law_.material);
    if (law_.parameters.size() != n)
        throw_invalid_argument("TetrahedronHyperelasticityFEMForceField: material ", material_name(law_.material),
                               " needs ", n, " parameters, got ", law_.parameters.size());
    for (const double p : law_.parameters)
        if (!std::isfinite(p))
            throw_invalid_argument("TetrahedronHyperelasticityFEMForceField: parameters must be finite");
    if (law_.material == HyperelasticMaterial::Ogden && law_.parameters[1] == 0)
        throw_invalid_argument("TetrahedronHyperelasticityFEMForceField: Ogden's alpha1 must be non-zero");
}

void TetrahedronHyperelasticityFEMForceField::init() {
    // createTetrahedronRestInformation: 6V = (p₂ − p₀) × (p₃ − p₀) · (p₁ − p₀);
    // gⱼ = ±(p_{j+2} − p_{j+1}) × (p_{j+3} − p_{j+1}) / 6V, sign − for j even
    const auto& x0 = state_->rest_position;
    elements_.assign(tetrahedra_.size(), Element{});
    scatter_.clear();  // made again for these tetrahedra at the next force on threads
    for (std::size_t e = 0; e < tetrahedra_.size(); ++e) {
        std::array<Vec3, 4> p;
        for (std::size_t k = 0; k < 4; ++k) {
            const PointId v = tetrahedra_[e][k];
            if (v < 0 || static_cast<std::size_t>(v) >= x0.size())
                throw_invalid_argument("TetrahedronHyperelasticityFEMForceField: tetrahedron ", e, " uses point ", v,
                                       " out of range (", x0.size(), " points)");
            p[k] = x0[static_cast<std::size_t>(v)];
        }
        const double six_volume = (p[2] - p[0]).cross(p[3] - p[0]).dot(p[1] - p[0]);
        const double scale = std::max({(p[1] - p[0]).norm(), (p[2] - p[0]).norm(), (p[3] - p[0]).norm()});
        if (!(std::abs(six_volume) > 1e-12 * scale * scale * scale))
            throw_invalid_argument("TetrahedronHyperelasticityFEMForceField: tetrahedron ", e,
                                   " is flat at rest (volume ", six_volume / 6, ")");
        Element& el = elements_[e];
        el.rest_volume = std::abs(six_volume / 6);
        for (std::size_t j = 0; j < 4; ++j) {
            const double sign = j % 2 ? 1.0 : -1.0;
            const Vec3& a = p[(j + 1) % 4];
            el.shape[j] = sign * (p[(j + 2) % 4] - a).cross(p[(j + 3) % 4] - a) / six_volume;
        }
    }
}

void TetrahedronHyperelasticityFEMForceField::add_force(std::span<Vec3> f, std::span<const Vec3> x,
                                                        std::span<const Vec3>) {
    PENALTY_DEMAND(elements_.size() == tetrahedra_.size());
    energy_ = detail::force_in_order</*Add=*/false>(
        scatter_, std::span<const Tetrahedron>(tetrahedra_), f, 1, element_energies_,
        [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred, double* energies) {
            return force_range(first, end, f, x, deferred, energies);
        });
}

double TetrahedronHyperelasticityFEMForceField::force_range(std::size_t first, std::size_t end, std::span<Vec3> f,
                                                            std::span<const Vec3> x,
                                                            const detail::DeferredTerms& deferred, double* energies) {
    double total = 0.0;
    for (std::size_t e = first; e < end; ++e) {
        Element& el = elements_[e];
        const auto& t = tetrahedra_[e];
        const Vec3& x0 = x[static_cast<std::size_t>(t[0])];
        Mat3 def = Mat3::Zero();  // F = Σ (xⱼ − x₀) ⊗ gⱼ
        for (std::size_t j = 1; j < 4; ++j) def += (x[static_cast<std::size_t>(t[j])] - x0) * el.shape[j].transpose();
        const double jac = def.determinant();
        const Mat3 c = def.transpose() * def;
        const Mat3 s = law_.second_piola(c, jac);
        const double energy = el.rest_volume * law_.energy_density(c, jac);
        if (energies) energies[e] = energy;
        else total += energy;
        // f_k −= V₀·F·S·g_k
        std::array<Vec3, 4> terms;
        for (std::size_t k = 0; k < 4; ++k) terms[k] = el.rest_volume * (def * (s * el.shape[k]));
        detail::store_or_apply(deferred, e, terms,
                               [&](std::size_t k, const Vec3& term) { f[static_cast<std::size_t>(t[k])] -= term; });
        // ∂fₖ/∂xₗ: column m = −V₀[(gₖ·S·gₗ) eₘ + F dS[dC] gₖ], dC = (Fᵀeₘ) ⊗ gₗ + gₗ ⊗ (Fᵀeₘ)
        // (updateTangentMatrix's M and N)
        for (std::size_t l = 0; l < 4; ++l) {
            std::array<Mat3, 3> ds;
            for (int m = 0; m < 3; ++m) {
                const Vec3 ft = def.row(m).transpose();
                const Mat3 dc = ft * el.shape[l].transpose() + el.shape[l] * ft.transpose();
                ds[static_cast<std::size_t>(m)] = law_.stress_derivative(c, jac, dc);
            }
            for (std::size_t k = 0; k < 4; ++k) {
                Mat3 block = Mat3::Identity() * el.shape[k].dot(s * el.shape[l]);
                for (int m = 0; m < 3; ++m) block.col(m) += def * (ds[static_cast<std::size_t>(m)] * el.shape[k]);
                el.stiffness[4 * k + l] = -el.rest_volume * block;
            }
        }
    }
    return total;
}

void TetrahedronHyperelasticityFEMForceField::add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                                                         double) const {
    // df_k += k·Σ_l K_kl·dx_l
    detail::scatter_in_order</*Add=*/true>(
        scatter_, std::span<const Tetrahedron>(tetrahedra_), df, 1,
        [&](std::size_t first, std::size_t end, const detail::DeferredTerms& deferred) {
            for (std::size_t e = first; e < end; ++e) {
                const auto& t = tetrahedra_[e];
                std::array<Vec3, 4> terms;
                for (std::size_t k = 0; k < 4; ++k) {
                    Vec3 sum = Vec3::Zero();
                    for (std::size_t l = 0; l < 4; ++l)
                        sum += elements_[e].stiffness[4 * k + l] * dx[static_cast<std::size_t>(t[l])];
                    terms[k] = k_factor * sum;
                }
                detail::store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) {
                    df[static_cast<std::size_t>(t[k])] += term;
                });
            }
        });
}

void TetrahedronHyperelasticityFEMForceField::add_stiffness_triplets(TripletList& triplets, Index offset,
                                                                     double factor) const {
    for (std::size_t e = 0; e < tetrahedra_.size(); ++e) {
        const auto& t = tetrahedra_[e];
        for (std::size_t k = 0; k < 4; ++k)
            for (std::size_t l = 0; l < 4; ++l) {
                const Mat3& b = elements_[e].stiffness[4 * k + l];
                for (Index r = 0; r < 3; ++r)
                    for (Index col = 0; col < 3; ++col)
                        triplets.emplace_back(offset + 3 * t[k] + r, offset + 3 * t[l] + col, factor * b(r, col));
            }
    }
}

}  // namespace penalty
