#pragma once
/// @file
/// SOFA's FastTetrahedralCorotationalForceField: linear-elastic tetrahedra in a corotational frame,
/// with the stiffness stored per edge (docs/components/fast_tetrahedral_corotational.md).
/// Per tetrahedron (vertices p0..p3, rest volume V = −signedVolume, Lamé λ, μ scaled by |V|):
///   shape vectors s_j = ±(p_{j+2} − p_{j+1}) × (p_{j+3} − p_{j+1}) / (6V) (indices mod 4, + for
///   even j), the gradients of the barycentric coordinates;
///   for each of the six local edges j = (k, l) (SOFA's edgesInTetrahedronArray) the block
///   L_j = λ s_l s_kᵀ + μ s_k s_lᵀ + μ (s_l·s_k) I (N/m), and for each vertex the block
///   D_i = (λ + μ) s_i s_iᵀ + μ |s_i|² I;
///   the rotation R (method qr/large: frame of edges 01 and 02, now against at rest; polar: polar
///   factor of the deformation gradient; polar2: polar factor of the edge matrix, now against at
///   rest; none/linear/small: identity) and the rest-frame edge displacement
///   u_j = Rᵀ(x_l − x_k) − (p_l − p_k);
///   force (N) f_l += R L_j u_j, f_k −= R L_jᵀ u_j.
/// add_dforce: df_l += E_e (dx_l − dx_k)·k, df_k −= E_eᵀ (dx_l − dx_k)·k over the topology's edges e,
/// with E_e = Σ R L_j Rᵀ over the tetrahedra sharing e (transposed when the tetrahedron's local edge
/// runs against the global edge); the rotation's change is not differentiated (exact when the
/// element is unstrained). The assembled K has off-diagonal blocks −E_e (row l) and −E_eᵀ (row k)
/// and diagonal blocks −Σ R D_i Rᵀ. No potential energy (SOFA's getPotentialEnergy returns 0).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <vector>

namespace penalty {

/// SOFA's RotationDecompositionMethod (the `method` Data).
enum class FastTetrahedralRotation { qr, polar, polar_modified, linear };

struct FastTetrahedralCorotationalParameters {
    std::vector<double> young_modulus{5000};  ///< Pa, one per tetrahedron or the first for all
    std::vector<double> poisson_ratio{0.45};  ///< one per tetrahedron or the first for all
    FastTetrahedralRotation rotation = FastTetrahedralRotation::qr;
};

class FastTetrahedralCorotationalForceField final : public ForceField<Vec3Types> {
public:
    /// SOFA's TetrahedronRestInformation plus the tetrahedron's global edges.
    struct RestTetrahedron {
        std::array<Vec3, 4> shape_vector{};        ///< ∇ of the barycentric coordinates, 1/m
        double rest_volume = 0;                    ///< −signedVolume, m³
        std::array<Vec3, 6> rest_edge{};           ///< p_l − p_k per local edge, m
        std::array<Mat3, 4> vertex_block{};        ///< D_i, N/m
        std::array<Mat3, 6> edge_block{};          ///< L_j, N/m
        Mat3 rest_rotation = Mat3::Identity();     ///< qr and polar2 only
        Mat3 rotation = Mat3::Identity();          ///< Rᵀ: deformed to rest (last add_force)
        std::array<std::int32_t, 6> edge{};        ///< global edge of each local edge
        std::array<double, 6> edge_orientation{};  ///< +1 when the local edge runs as the global one
    };

    FastTetrahedralCorotationalForceField(Vec3Object& state, const MeshTopology& topology,
                                          FastTetrahedralCorotationalParameters p);

    /// Rest information of every tetrahedron from the state's rest positions, the topology's
    /// edges (FastTetrahedralCorotationalForceField::init, createTetrahedronRestInformation,
    /// updateTopologyInformation). Also what a topology follower calls after a change.
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;

    [[nodiscard]] const std::vector<RestTetrahedron>& rest_tetrahedra() const { return rest_; }
    /// E_e per global edge, built from the rotations of the last add_force.
    [[nodiscard]] const std::vector<Mat3>& edge_stiffness() const { return edge_dfdx_; }
    [[nodiscard]] FastTetrahedralRotation rotation_method() const { return p_.rotation; }
    /// The force's split of the tetrahedra (for their vertices; the same chunks for their edges'
    /// E_e) and the product's of the edges, as the last force and product on threads made them
    /// (chunk_count() 0 before one ran).
    [[nodiscard]] const detail::OrderedScatter& force_scatter() const { return force_scatter_; }
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return product_scatter_; }

private:
    [[nodiscard]] RestTetrahedron rest_information(std::size_t t) const;
    [[nodiscard]] Mat3 rotation_of(const RestTetrahedron& r, const std::array<Vec3, 6>& edge) const;
    /// The force over tetrahedra [first, end) (each one's rotation into rest_), the terms
    /// `deferred` marks stored instead of added (detail::NoDeferredTerms on one thread), and
    /// edge_term(t, j, term) with each tetrahedron's term of E_e for its local edge j, after its
    /// force.
    template <class Deferred, class EdgeTerm>
    void force_range(std::size_t first, std::size_t end, std::span<Vec3> f, std::span<const Vec3> x,
                     const Deferred& deferred, const EdgeTerm& edge_term);

    const MeshTopology* topology_;
    FastTetrahedralCorotationalParameters p_;
    std::vector<RestTetrahedron> rest_;
    std::vector<Mat3> edge_dfdx_;  ///< SOFA's edgeInfo
    /// From OrderedScatter::kMinElements tetrahedra (edges) on several threads, the force and
    /// E_e (the product) run on TBB's threads with the bits of one thread: the tetrahedra's
    /// split for their vertices, the same chunks' split for their edges with its stored terms,
    /// and the edges' split (init clears them).
    detail::OrderedScatter force_scatter_;
    detail::OrderedScatter edge_scatter_;
    std::vector<Mat3> deferred_edge_terms_;  ///< at edge_scatter_.deferred_slot
    mutable detail::OrderedScatter product_scatter_;
};

}  // namespace penalty
