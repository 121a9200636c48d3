#pragma once
/// @file
/// SOFA's TriangularBiquadraticSpringsForceField: springs on the squared edge lengths of a
/// triangle mesh, coupled per triangle ("angular springs"), plus an area term against
/// compression. With λ = E ν / (1 − ν²), μ = E (1 − ν) / (1 − ν²) (updateLameCoefficients), per
/// triangle t of rest area A and rest squared lengths ℓ_j² (edge opposite t_j), cot_j as in
/// TriangularTensorMassForceField (applyTriangleCreation):
///   γ_j = (2 cot_k cot_l (λ+μ) − μ) / (16 A),  s_j = (2 cot_j² (λ+μ) + μ) / (16 A)  (k, l = j+1, j+2)
/// and each edge's stiffness k_e = Σ s_j over the triangles holding it. With Δ_e = |x_v0 − x_v1|²
/// − ℓ_e² (+ dampingRatio·(v_v0 − v_v1)·(x_v0 − x_v1)/|x_v0 − x_v1|², addForce), the energy is
///   E = ¼ Σ_e k_e Δ_e² + ½ Σ_t Σ_j γ_j Δ_{e(k)} Δ_{e(l)} + Σ_{t: J<1} 3(λ+μ) A (J − 1)⁴ / 4
/// with J = area / A (the last term only with `compressible`, the last two only with
/// `useAngularSprings`). The stiffness is SOFA's addDForce matrices DfDx[k] per triangle and
/// vertex pair (t_{k+1}, t_{k+2}): exact for the spring terms; for a compressed triangle SOFA adds
/// a regularised approximation of the area term's Hessian (kept as SOFA's). Quirk kept: without
/// angular springs SOFA never updates the per-triangle edge vectors, so the stiffness keeps only
/// −s_k Δ I (the edge vectors stay zero).

#include "penalty/mechanics/edge_triangle_scatter.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <array>
#include <vector>

namespace penalty {

/// TriangularBiquadraticSpringsForceField's data (SOFA's defaults).
struct BiquadraticSpringParameters {
    double young_modulus = 1000.0;  ///< E (Pa)
    double poisson_ratio = 0.3;     ///< ν, ν² ≠ 1
    double damping_ratio = 0.0;     ///< s: damping / stiffness (explicit only)
    bool use_angular_springs = true;
    bool compressible = true;  ///< the area term of compressed triangles
};

class TriangularBiquadraticSpringsForceField final : public ForceField<Vec3Types> {
public:
    /// `topology` must outlive the force field; throws std::invalid_argument on bad parameters.
    TriangularBiquadraticSpringsForceField(Vec3Object& state, const MeshTopology& topology,
                                           BiquadraticSpringParameters parameters);

    /// Rest quantities from the state's rest positions.
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// E of the file comment at the last add_force (J); SOFA does not implement it.
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] double lambda() const { return lambda_; }
    [[nodiscard]] double mu() const { return mu_; }
    /// k_e per edge (N/m³).
    [[nodiscard]] const std::vector<double>& edge_stiffness() const { return edge_stiffness_; }
    /// ℓ_e² per edge (m²).
    [[nodiscard]] const std::vector<double>& rest_square_lengths() const { return rest_square_length_; }
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
        std::array<double, 3> gamma{};                                       ///< γ_j
        std::array<double, 3> stiffness{};                                   ///< s_j
        std::array<Mat3, 3> dfdx{Mat3::Zero(), Mat3::Zero(), Mat3::Zero()};  ///< SOFA's DfDx[k]
        std::array<Vec3, 3> dp{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};    ///< x_{j+2} − x_{j+1}
        std::array<Vec3, 3> area_vector{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
        Vec3 normal = Vec3::Zero();
        Vec3 last_valid_normal = Vec3::Zero();
        double rest_area = 0.0;
        double area = 0.0;
        double j = 0.0;  ///< area / rest area
    };
    void update_stiffness();
    void create_edge(std::size_t e);
    void create_triangle(std::size_t ti);

    const MeshTopology* topology_;
    BiquadraticSpringParameters parameters_;
    double lambda_ = 0.0;
    double mu_ = 0.0;
    std::vector<double> rest_square_length_;  ///< ℓ_e² per edge
    std::vector<double> edge_stiffness_;      ///< k_e
    std::vector<double> square_length_;       ///< current |x_v0 − x_v1|²
    std::vector<double> delta_;               ///< Δ_e
    std::vector<TriangleData> triangles_;
    double energy_ = 0.0;
    mutable detail::EdgeTriangleScatter scatter_;  ///< the loops on threads
    mutable detail::EdgeBlockProduct product_;     ///< the one-thread product's blocks
    KernelPath kernel_path_ = best_kernel_path();
};

}  // namespace penalty
