#pragma once
/// @file
/// SOFA's TriangularTensorMassForceField: linear elasticity of a triangle membrane written as one
/// 3×3 tensor D_e per edge, assembled once from the rest positions x⁰
/// (TriangularTensorMassForceField::applyTriangleCreation). With λ = E ν / (1 − ν²),
/// μ = E (1 − ν) / (1 − ν²) (updateLameCoefficients; SOFA's choice, not the usual Lamé
/// coefficients), for triangle t = (t0, t1, t2) of rest area A (Heron, from the squared edge
/// lengths ℓ_j² of the edge opposite t_j), cot_j = (ℓ_{j+1}² + ℓ_{j+2}² − ℓ_j²) / (4A), and for
/// each j with k = j+1, l = j+2 (mod 3), p_l = x⁰_j − x⁰_k, p_k = x⁰_j − x⁰_l:
///   M = λ/(4A) · p_l p_kᵀ + μ/(8A) · p_k p_lᵀ − cot_j (λ + μ)/2 · I
/// added to the tensor of edge e = edges_in_triangle[t][j] as M when e's first vertex is t_l,
/// else as Mᵀ. The force is linear in the displacement u = x − x⁰: for each edge e = (v0, v1)
/// with δ = u_v1 − u_v0, f_v1 += D_e δ and f_v0 −= D_eᵀ δ (addForce); K is constant
/// (addDForce). The velocities are not read (no damping).

#include "penalty/mechanics/edge_triangle_scatter.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <vector>

namespace penalty {

/// Material of TriangularTensorMassForceField (SOFA's defaults).
struct TensorMassParameters {
    double young_modulus = 1000.0;  ///< E (Pa)
    double poisson_ratio = 0.3;     ///< ν, with ν² ≠ 1
};

class TriangularTensorMassForceField final : public ForceField<Vec3Types> {
public:
    /// `topology` must outlive the force field; throws std::invalid_argument on bad parameters.
    TriangularTensorMassForceField(Vec3Object& state, const MeshTopology& topology, TensorMassParameters parameters);

    /// The edge tensors from the state's rest positions (which become x⁰).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// E = −½ Σ_e (u_v1·D_e δ − u_v0·D_eᵀ δ) = −½ uᵀ K u (J), the potential of f when K is symmetric.
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const std::vector<Mat3>& edge_tensors() const { return tensors_; }
    [[nodiscard]] double lambda() const { return lambda_; }
    [[nodiscard]] double mu() const { return mu_; }
    /// How the product's loop over the edges is split on threads (OrderedScatter::kMinElements
    /// or more, more than one thread: chunks and deferred terms; else none).
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_.edge_scatter(); }

private:
    const MeshTopology* topology_;
    double lambda_ = 0.0;
    double mu_ = 0.0;
    std::vector<Mat3> tensors_;  ///< D_e per edge of the topology
    std::vector<Vec3> rest_;     ///< x⁰ (SOFA's _initialPoints)
    double energy_ = 0.0;
    mutable detail::EdgeTriangleScatter scatter_;  ///< the loops on threads
};

}  // namespace penalty
