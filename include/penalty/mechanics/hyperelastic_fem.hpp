#pragma once
/// @file
/// SOFA's TetrahedronHyperelasticityFEMForceField: linear tetrahedra with a hyperelastic material
/// W(C) (C = FᵀF the right Cauchy-Green tensor, J = det F), total Lagrangian.
///
/// Per tetrahedron (TetrahedronHyperelasticityFEMForceField::createTetrahedronRestInformation,
/// addForce, updateTangentMatrix, addDForce): shape vectors gⱼ = ∇Nⱼ at rest, F = Σⱼ xⱼ ⊗ gⱼ,
/// second Piola-Kirchhoff stress S = 2 ∂W/∂C, nodal force fₖ = −V₀·F·S·gₖ (V₀ the rest volume),
/// energy E = Σ V₀·W. Stiffness ∂fₖ/∂xₗ·δ = −V₀[(gₖ·S·gₗ) δ + F·dS[dC]·gₖ] with
/// dC = (Fᵀδ) ⊗ gₗ + gₗ ⊗ (Fᵀδ) (the change of C when vertex l moves by δ): SOFA's edge matrices
/// (M + N)·V₀ are these blocks (its material tangents are the exact derivatives dS[H]); here they
/// are kept per vertex pair of each element.
///
/// Materials (parameters in `ParameterSet` order; `hyperelastic_materials.cpp`, from SOFA's
/// material/*.h), with I₁ = tr C, I₂ = ½(I₁² − tr C²):
///  - ArrudaBoyce (μ, k₀): W = μ Σᵢ₌₁..₅ cᵢ (J^(−2i/3) I₁ⁱ − 3ⁱ) + k₀/2 (ln J)²,
///    c = (1/2, 1/160, 11/(1050·8²), 19/(7000·8³), 519/(673750·8⁴)) (BoyceAndArruda);
///  - StVenantKirchhoff (μ, λ): W = λ/2 (tr E)² + μ tr E², E = (C − I)/2 (STVenantKirchhoff);
///  - NeoHookean (μ, λ): W = μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)² (NeoHookean);
///  - MooneyRivlin (c₁, c₂, k₀): W = c₁(J^(−2/3) I₁ − 3) + c₂ J^(−4/3) I₂ + k₀/2 (ln J)²
///    (MooneyRivlin's stress and tangent; its getStrainEnergy's integer powers are a SOFA bug that
///    only its energy report sees);
///  - Ogden (μ₁, α₁, k₀): W = μ₁/α₁² (J^(−α₁/3) tr C^(α₁/2) − 3) + k₀/2 (ln J)² (Ogden: the
///    spectral derivative of C^(α₁/2 − 1), SOFA's relative tolerance 1e-8 for equal eigenvalues).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <string_view>
#include <utility>
#include <vector>

namespace penalty {

enum class HyperelasticMaterial { ArrudaBoyce, StVenantKirchhoff, NeoHookean, MooneyRivlin, Ogden };

/// SOFA's materialName of each material, and the number of parameters it reads.
[[nodiscard]] std::string_view material_name(HyperelasticMaterial m);
[[nodiscard]] std::size_t material_parameter_count(HyperelasticMaterial m);

/// W(C) (J/m³), S = 2∂W/∂C and its derivative dS[H] (H symmetric) at C with J = det F > 0.
struct HyperelasticLaw {
    HyperelasticMaterial material = HyperelasticMaterial::ArrudaBoyce;
    std::vector<double> parameters;

    [[nodiscard]] double energy_density(const Mat3& c, double j) const;
    [[nodiscard]] Mat3 second_piola(const Mat3& c, double j) const;
    [[nodiscard]] Mat3 stress_derivative(const Mat3& c, double j, const Mat3& h) const;
};

class TetrahedronHyperelasticityFEMForceField final : public ForceField<Vec3Types> {
public:
    /// Throws std::invalid_argument when the parameter count is not the material's or a value is
    /// not finite.
    TetrahedronHyperelasticityFEMForceField(Vec3Object& state, std::vector<Tetrahedron> tetrahedra,
                                            HyperelasticLaw law);

    /// Shape vectors and rest volumes from the rest positions; a flat tetrahedron is an error.
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// Σ V₀·W at the last add_force (J).
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const std::vector<Tetrahedron>& tetrahedra() const { return tetrahedra_; }
    /// The tetrahedra after a topological change (then init(): the rest data of every element).
    void set_tetrahedra(std::vector<Tetrahedron> tetrahedra) { tetrahedra_ = std::move(tetrahedra); }
    [[nodiscard]] const HyperelasticLaw& law() const { return law_; }
    /// From OrderedScatter::kMinElements tetrahedra on several threads, the force and the product
    /// run on TBB's threads with the bits of one thread; their split as the last of them made it.
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }

private:
    struct Element {
        std::array<Vec3, 4> shape{};  ///< gⱼ = ∇Nⱼ at rest (1/m)
        double rest_volume = 0;       ///< V₀ (m³)
        /// ∂fₖ/∂xₗ at the last add_force, block 4k + l.
        std::array<Mat3, 16> stiffness{};
    };
    std::vector<Tetrahedron> tetrahedra_;
    HyperelasticLaw law_;
    std::vector<Element> elements_;
    double energy_ = 0;
    /// The force over tetrahedra [first, end) with each one's ∂fₖ/∂xₗ, the terms `deferred` marks
    /// stored instead of subtracted; returns the energy summed in element order, or 0 with
    /// element e's into energies[e] (not null).
    double force_range(std::size_t first, std::size_t end, std::span<Vec3> f, std::span<const Vec3> x,
                       const detail::DeferredTerms& deferred, double* energies);
    mutable detail::OrderedScatter scatter_;  ///< made again when the tetrahedra change (init clears it)
    std::vector<double> element_energies_;    ///< the force's on threads, summed in element order
};

}  // namespace penalty
