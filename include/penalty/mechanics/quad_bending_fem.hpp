#pragma once
/// @file
/// SOFA's QuadBendingFEMForceField ("small" method, the only one SOFA implements): each quad
/// (0, 1, 2, 3) is a Mindlin plate of five DOFs per node (u, v, w, θx, θy) whose rotations are
/// held at zero, so only the translations act:
///   - element stiffness K (20×20) from the CURRENT positions at each use
///     (computeElementStiffness): half sizes l = |x1 − x0|/2, h = |x3 − x0|/2 in world units (the
///     quad is taken as the rectangle [−l, l]×[−h, h] in its node coordinates, which SOFA never
///     rotates: the element's x, y, z are the world axes); bending/membrane part with 2×2 Gauss
///     points (±1/√3, weight 1) and C_b = E t/(1 − ν²)[[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]];
///     transverse shear with one Gauss point (weight 2, so ·4) and C_s = (5/6) E t/(2 + 2ν);
///   - displacement D = (x0_k − c0) − (x_k − c) per node, c the current centroid (x0 + x2)/2 and
///     c0 the rest one; force F = K·D on the translations only (SOFA's computeForce sums its
///     non-zero terms), f_k += F_k;
///   - add_dforce: df_k −= k·(K·dx)_k with K at the current positions (applyStiffnessSmall).
/// E = ½ Dᵀ F (J), whose gradient is f when K is held. SOFA's assembled matrix
/// (buildStiffnessMatrix) reads K in 3×3 blocks of the 5-DOF layout, a different matrix from
/// its own addDForce; penalty assembles the matrix of add_dforce (docs/differences-from-sofa.md).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <vector>

namespace penalty {

struct QuadBendingParameters {
    std::vector<double> young_modulus{1000};  ///< Pa, one per quad or one for all
    std::vector<double> poisson_ratio{0.45};
    double thickness = 1;  ///< m
};

class QuadBendingFEMForceField final : public ForceField<Vec3Types> {
public:
    using Stiffness = Eigen::Matrix<double, 20, 20>;
    QuadBendingFEMForceField(Vec3Object& state, const MeshTopology& topology, QuadBendingParameters p)
        : ForceField(state), topology_(&topology), p_(std::move(p)) {}
    /// Rest offsets from the centroid and the material matrices (reinit, initSmall).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }
    /// SOFA's computeElementStiffness of quad `q` at positions x.
    [[nodiscard]] Stiffness element_stiffness(std::size_t q, std::span<const Vec3> x) const;
    /// How the loops over the quads are split on threads (OrderedScatter::kMinElements or more,
    /// more than one thread: chunks and deferred terms; else none).
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }

private:
    struct Material {
        double cb00, cb01, cb11, cb22;              ///< bending (membrane) matrix entries
        double cs33, cs34, cs44, cs55, cs66, cs77;  ///< shear matrix entries
    };
    /// F = K·D on the translations (computeForce's sums), D of 20 entries.
    static std::array<double, 20> force_of(const Stiffness& k, const std::array<double, 20>& d);
    const MeshTopology* topology_;
    QuadBendingParameters p_;
    std::vector<Material> material_;
    std::vector<std::array<Vec3, 4>> rest_offsets_;  ///< x0_k − c0
    /// K of each quad at the positions of the last add_force (SOFA recomputes it from the same
    /// positions at each addDForce: the same numbers).
    std::vector<Stiffness> stiffness_;
    /// K of quad q: the stored one, or, before the first add_force, made at the state's positions
    /// into `scratch`.
    [[nodiscard]] const Stiffness& stiffness_at(std::size_t q, Stiffness& scratch) const;
    double energy_ = 0;
    mutable detail::OrderedScatter scatter_;  ///< the loops on threads
    /// add_force on threads: each quad's twelve energy terms, summed in the loop's order after
    std::vector<std::array<double, 12>> energy_terms_;
};

}  // namespace penalty
