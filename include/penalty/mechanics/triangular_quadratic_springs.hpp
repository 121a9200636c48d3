#pragma once
/// @file
/// SOFA's TriangularQuadraticSpringsForceField: springs on the edge lengths of a triangle mesh,
/// coupled per triangle ("angular springs"). With λ, μ as TriangularTensorMassForceField's, per
/// triangle t of rest area A, rest lengths ℓ_j (edge opposite t_j) and cot_j
/// (TriangularQuadraticSpringsForceField::applyTriangleCreation):
///   γ_j = ℓ_k ℓ_l (2 cot_k cot_l (λ+μ) − μ) / (8 A),  s_j = ℓ_j² (2 cot_j² (λ+μ) + μ) / (8 A)
/// (k, l = j+1, j+2), each edge's stiffness k_e = Σ s_j over its triangles. With
/// δ_e = |x_v0 − x_v1| − ℓ_e (+ dampingRatio·(v_v0 − v_v1)·(x_v0 − x_v1)/|x_v0 − x_v1|, addForce):
///   E = ½ Σ_e k_e δ_e² + Σ_t Σ_j γ_j δ_{e(k)} δ_{e(l)}   (the second sum with useAngularSprings).
/// The stiffness is SOFA's addDForce matrices DfDx[k] per triangle and vertex pair
/// (t_{k+1}, t_{k+2}), from the positions and lengths of the last add_force: the exact Hessian
/// without angular springs; with them SOFA's is off by one term (exact_angular_stiffness).

#include "penalty/mechanics/edge_triangle_scatter.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <array>
#include <vector>

namespace penalty {

/// TriangularQuadraticSpringsForceField's data (SOFA's defaults).
struct QuadraticSpringParameters {
    double young_modulus = 1000.0;  ///< E (Pa)
    double poisson_ratio = 0.3;     ///< ν, ν² ≠ 1
    double damping_ratio = 0.0;     ///< damping / stiffness (s), explicit only
    bool use_angular_springs = true;
    /// SOFA's addDForce with angular springs writes the U Uᵀ coefficient of pair k as
    /// (c − s_k ℓ_k)/L³ (c = s_k δ_k + γ_i δ_j + γ_j δ_i) where the Hessian has (c − s_k L_k)/L³:
    /// its matrix is off by s_k δ_k/L U Uᵀ. false (default): SOFA's matrix; true: the exact one.
    bool exact_angular_stiffness = false;
};

class TriangularQuadraticSpringsForceField final : public ForceField<Vec3Types> {
public:
    /// `topology` must outlive the force field; throws std::invalid_argument on bad parameters.
    TriangularQuadraticSpringsForceField(Vec3Object& state, const MeshTopology& topology,
                                         QuadraticSpringParameters parameters);

    /// Rest quantities from the state's rest positions.
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// E of the file comment at the last add_force (J); SOFA does not implement it.
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] double lambda() const { return lambda_; }
    [[nodiscard]] double mu() const { return mu_; }
    /// k_e per edge (N/m).
    [[nodiscard]] const std::vector<double>& edge_stiffness() const { return edge_stiffness_; }
    /// ℓ_e per edge (m).
    [[nodiscard]] const std::vector<double>& rest_lengths() const { return rest_length_; }
    /// SOFA's TopologyData callbacks of edgeInfo and triangleInfo, event by event
    /// (src/mechanics/topology/biquadratic_springs_changes.cpp).
    void handle_topology_changes(const class TopologyContainer& container, std::span<const TopologyChange> changes);
    /// How the product's loop over the triangles is split on threads (OrderedScatter::kMinElements
    /// or more, more than one thread: chunks and deferred terms; else none).
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_.triangle_scatter(); }
    /// Instructions of the one-thread product (detail::triangle_edge_dforce; default
    /// best_kernel_path(), every path the same bits). Throws std::invalid_argument if this machine
    /// cannot run `path`, or for avx512 (no such path here).
    void set_kernel_path(KernelPath path);
    [[nodiscard]] KernelPath kernel_path() const { return kernel_path_; }

private:
    struct TriangleData {
        std::array<double, 3> gamma{};
        std::array<double, 3> stiffness{};
        std::array<Mat3, 3> dfdx{Mat3::Zero(), Mat3::Zero(), Mat3::Zero()};
    };
    void create_edge(std::size_t e);
    void create_triangle(std::size_t ti);

    const MeshTopology* topology_;
    QuadraticSpringParameters parameters_;
    double lambda_ = 0.0;
    double mu_ = 0.0;
    std::vector<double> rest_length_;     ///< ℓ_e
    std::vector<double> edge_stiffness_;  ///< k_e
    std::vector<double> length_;          ///< current |x_v0 − x_v1|
    std::vector<double> delta_;           ///< δ_e
    std::vector<TriangleData> triangles_;
    double energy_ = 0.0;
    mutable detail::EdgeTriangleScatter scatter_;  ///< the loops on threads
    mutable detail::EdgeBlockProduct product_;     ///< the one-thread product's blocks
    KernelPath kernel_path_ = best_kernel_path();
};

}  // namespace penalty
