#pragma once
/// @file
/// SOFA's HexahedralFEMForceField (methods large and polar) and the mass of its two "AndMass"
/// variants (HexahedralFEMForceFieldAndMass, HexahedronFEMForceFieldAndMass).
///
/// HexahedralFEMForceField shares the corotational scheme of HexahedronFEMForceField
/// (LinearElementForceField<8>: f = −Rᵀ K^e (R(x − x₀) − r), K = −Rᵀ K^e R), with its own element
/// stiffness (HexahedralFEMForceField::computeElementStiffness / integrateStiffness): the exact
/// integral over an axis-aligned box with J⁻¹ = diag(2/l), l = x⁰₆ − x⁰₀ in the WORLD frame, and
/// volume factor V/8 with V = |x⁰₁ − x⁰₀|·|x⁰₃ − x⁰₀|·|x⁰₄ − x⁰₀|. Two SOFA quirks are reproduced:
///  - a diagonal entry K_ij(a, a) uses (J⁻¹_aa)² for every term, its shear terms included (exact
///    only for cubes): K_ij(a,a) = (J⁻¹_aa)² [ (λ+2μ) ∫g_a^i g_a^j + μ Σ_{c≠a} ∫g_c^i g_c^j ],
///    K_ij(a,b) = J⁻¹_aa J⁻¹_bb [ λ ∫g_a^i g_b^j + μ ∫g_b^i g_a^j ] (a ≠ b), g_c^i = ∂N_i/∂ξ_c;
///  - each entry of ∫(...) is rounded to float before the product by V/8.

#include "penalty/mechanics/fem.hpp"

namespace penalty {

/// SOFA's HexahedralFEMForceField: methods Large (frame from the mean edges, as
/// HexahedronFEMForceField) and Polar (HexahedralFEMForceField::computeRotationPolar: polar factor of
/// the matrix whose rows are the mean edges along x, y and z).
class HexahedralFEMForceField final : public HexahedronElementForceField {
public:
    HexahedralFEMForceField(Vec3Object& state, const MeshTopology& topology, double young_modulus, double poisson_ratio,
                            FemMethod method = FemMethod::Large);
    [[nodiscard]] const std::vector<Element>& hexahedra() const { return elements_; }

    /// Method large: the common corotational data, then SOFA's rest local positions R₀·x⁰_w
    /// (HexahedralFEMForceField::initLarge).
    void init() override;
    /// Method large with SOFA's operations in SOFA's order (accumulateForceLarge: the frame from
    /// the mean edges, D = R₀x⁰ − R·x, F = K·D summed in column order, f += Rᵀ·F), so that a scene
    /// matches SOFA's trajectory bit for bit; polar: the common path.
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    /// Method large as SOFA's addDForce: X = (R·dx)·k, F = K·X, df −= Rᵀ·F; polar: the common path.
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;

protected:
    [[nodiscard]] ElementMatrix compute_stiffness(const std::array<Vec3, 8>& rest_local,
                                                  const Eigen::Matrix<double, 6, 6>& d, std::size_t e) const override;
    [[nodiscard]] Mat3 element_rotation(const std::array<Vec3, 8>& p) const override;

private:
    std::vector<std::array<Vec3, 8>> rotated_rest_;  ///< R₀·x⁰_w per element (method large)
};

/// Whose element mass: HexahedronFEMForceFieldAndMass (V·(∫·ρ)·c) or HexahedralFEMForceFieldAndMass
/// ((V·ρ)·∫): the same value but for the last bits.
enum class HexahedronMassFormula { hexahedron, hexahedral };

/// The mass of SOFA's HexahedralFEMForceFieldAndMass and HexahedronFEMForceFieldAndMass (density ρ,
/// kg/m³), on the rest positions. Per hexahedron, V = |x⁰₁ − x⁰₀|·|x⁰₃ − x⁰₀|·|x⁰₄ − x⁰₀| and:
///  - element mass matrix M^e = w·(1₈ 1₈ᵀ ⊗ I₃), w = c·ρ·V·∫ with ∫ = 8/27: SOFA's
///    computeElementMass evaluates the integral of node i for every pair (i, j), so every 3×3 block
///    is the same (a SOFA quirk, reproduced: Σ M^e = 512/27·ρV per direction, not ρV); c is the
///    cell's mass coefficient (1, or SparseGridTopology::getMassCoef: 0.5 for a boundary cell when
///    fillWeighted). In SOFA's operations, to the bit: ∫ summed term by term as integrateMass
///    (1/72 + 1/72 + 1/216 + 1/24 + 1/8 + 1/72 + 1/24 + 1/24, not 8/27 in its last bit), w = V·(∫·ρ)·c
///    (HexahedronFEMForceFieldAndMass) or (V·ρ)·∫ (HexahedralFEMForceFieldAndMass, HexahedronMassFormula),
///    M·dx as addMDx's 24×24 product (Σ_k w·dx_k), the lumped row sums entry by entry, and, with
///    set_rotated_rest_source, V of M^e on the force field's rotated rest corners;
///  - particle masses m_k = Σ_e c·ρ·V/8 over the hexahedra of k: the gravity force m_k·g
///    (…AndMass::addForce adds it with the elastic force);
///  - lumped (`lumpedMass`): M = diag(row sums of M^e);
///  - M⁻¹ is not available (SOFA's accFromF is not implemented): explicit solvers are refused.
class HexahedronElementMass final : public BaseMass {
public:
    HexahedronElementMass(Vec3Object& state, std::vector<Hexahedron> hexahedra, double density, bool lumped,
                          const char* component, HexahedronMassFormula formula = HexahedronMassFormula::hexahedron);

    /// Per-hexahedron factors c on the element mass matrix and the particle masses
    /// (SparseGridTopology::getMassCoef); empty: 1. Set before init().
    void set_mass_factors(std::vector<double> factors) { mass_factors_ = std::move(factors); }
    /// The element volumes of the mass matrix from `fem`'s rotated rest corners, as
    /// HexahedronFEMForceFieldAndMass::computeElementMass reads _rotatedInitialElements (the
    /// particle masses keep the rest positions); `fem` on the same hexahedra, initialized before
    /// this mass. Null: the rest positions.
    void set_rotated_rest_source(const HexahedronFEMForceField* fem) { rotated_rest_source_ = fem; }
    void init() override;

    void add_gravity_force(const Vec3& gravity) override;
    void add_mdx(double factor) override;
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const override;
    void add_mass_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double kinetic_energy() const override;
    [[nodiscard]] double gravity_potential_energy(const Vec3& gravity) const override;
    [[nodiscard]] double total_mass() const override;
    [[nodiscard]] BaseState* state() const override { return state_; }

    [[nodiscard]] double density() const { return density_; }
    [[nodiscard]] bool lumped() const { return lumped_; }
    /// m_k (kg), the masses gravity acts on.
    [[nodiscard]] const std::vector<double>& particle_masses() const { return particle_masses_; }
    /// The weight w_e of hexahedron e: M^e = w_e·(1₈ 1₈ᵀ ⊗ I₃) (kg).
    [[nodiscard]] const std::vector<double>& element_weights() const { return element_weights_; }

private:
    /// y += factor·M·x on per-DOF vectors.
    void multiply_add(std::span<Vec3> y, std::span<const Vec3> x, double factor) const;

    Vec3Object* state_;
    std::vector<Hexahedron> hexahedra_;
    double density_;
    bool lumped_;
    const char* component_;
    HexahedronMassFormula formula_;
    std::vector<double> mass_factors_;
    const HexahedronFEMForceField* rotated_rest_source_ = nullptr;
    std::vector<double> element_weights_;
    std::vector<double> particle_masses_;
    std::vector<double> lumped_masses_;  ///< per DOF (same in x, y, z), when lumped
};

}  // namespace penalty
