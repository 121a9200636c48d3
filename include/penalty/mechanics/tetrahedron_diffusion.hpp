#pragma once
/// @file
/// SOFA's TetrahedronDiffusionFEMForceField<Vec1d>: diffusion of a scalar (a temperature) over a
/// tetrahedral mesh whose geometry is another, Vec3d, state (docs/components/diffusion.md).
///
/// At init (TetrahedronDiffusionFEMForceField::computeEdgeDiffusionCoefficient), each tetrahedron
/// t of points p0..p3 with signed 6·volume w = ((p1−p0)×(p2−p0))·(p0−p3) has shape vectors
/// s_j = ±((p_{j+2}−p_{j+1})×(p_{j+3}−p_{j+1}))/w (− for even j; indices mod 4), and each of its
/// edges (k, l) (SOFA's local edge order) receives
///   c_e += D_t·|w|/6 · s_k·s_l                                  (isotropic, ratio r = 1), or
///   c_e += D_t·|w|/6 · s_k·(s_l + a·(r − 1)·(a·s_l))             (transverse anisotropy along a),
/// with D_t the tetrahedron's diffusion coefficient (m²/s; `constantDiffusionCoefficient` for
/// all when none is given per tetrahedron). SOFA leaves a unnormalised (its `direction.norm()` is
/// discarded): so does penalty. Then, per edge e = (v0, v1) in the topology's edge order,
///   f[v1] += c_e·(x[v1] − x[v0]),  f[v0] −= c_e·(x[v1] − x[v0])
/// (c_e < 0 for the usual non-obtuse tetrahedra: heat flows down the gradient), so that
/// K = ∂f/∂x has K[v,v] = Σ c_e over the edges at v and K[v0,v1] = −c_e: the negative of the
/// P1 Laplacian ∫D∇Nᵢ·∇Nⱼ, negative semi-definite; E = −½ Σ c_e (x[v1] − x[v0])² gives f = −∂E/∂x.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <vector>

namespace penalty {

class TetrahedronDiffusionFEMForceField final : public ForceField<Vec1Types> {
public:
    /// `topology`: the tetrahedra and edges (kept by reference, alive for the field's life).
    TetrahedronDiffusionFEMForceField(Vec1Object& state, const MeshTopology& topology);

    /// One coefficient for every tetrahedron (SOFA's `constantDiffusionCoefficient`, default 1).
    void set_constant_coefficient(double d) { constant_ = d; }
    /// One coefficient per tetrahedron (`tetraDiffusionCoefficient`; its count is checked at init).
    void set_tetrahedron_coefficients(std::vector<double> d) { per_tetrahedron_ = std::move(d); }
    /// SOFA's `anisotropyRatio` r (1: isotropic) and `transverseAnisotropyArray` (one direction per
    /// tetrahedron, used when r ≠ 1).
    void set_anisotropy(double ratio, std::vector<Vec3> directions);
    /// The Vec3d positions of the mesh's points (SOFA reads the tagged MechanicalObject's position).
    void set_geometry(std::vector<Vec3> positions) { geometry_ = std::move(positions); }

    /// Computes the edge coefficients. std::invalid_argument: a geometry or a state with fewer
    /// points than the topology, a coefficient list of the wrong size, a direction list too short
    /// for an anisotropic field, a degenerate tetrahedron (zero volume: SOFA would divide by 0).
    void init() override;

    void add_force(std::span<double> f, std::span<const double> x, std::span<const double> v) override;
    void add_dforce(std::span<double> df, std::span<const double> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// −½ Σ c_e (x[v1] − x[v0])² at the last add_force (J; SOFA's getPotentialEnergy returns 0).
    [[nodiscard]] double potential_energy() const override { return energy_; }

    /// c_e per edge of the topology (after init).
    [[nodiscard]] const std::vector<double>& edge_coefficients() const { return edge_coefficients_; }
    /// D per tetrahedron (after init).
    [[nodiscard]] const std::vector<double>& tetrahedron_coefficients() const { return coefficients_; }

private:
    const MeshTopology* topology_;
    double constant_ = 1.0;
    std::vector<double> per_tetrahedron_;
    double ratio_ = 1.0;
    std::vector<Vec3> directions_;
    std::vector<Vec3> geometry_;
    std::vector<double> coefficients_;
    std::vector<double> edge_coefficients_;
    double energy_ = 0.0;
};

}  // namespace penalty
