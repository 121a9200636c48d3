#pragma once
/// @file
/// SOFA's TriangularFEMForceField: a membrane of linear triangles (plane stress, unit thickness)
/// on a Vec3 state, method "large" (co-rotational, SOFA's default) or "small".
///
/// Per triangle (a, b, c), as SOFA's TriangularFEMForceField and TriangleFEMUtils:
///   - material (computeMaterialStiffness): Dₐ = E/(1−ν²)·A₀·[[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]]
///     with A₀ the rest area (Pa·m² = N/m for a unit thickness);
///   - large (initLarge, accumulateForceLarge): frame R (rows = local axes) with x̂ along b − a,
///     ẑ ⟂ (b − a, c − a), ŷ = ẑ × x̂ (computeRotationLarge); rest local coordinates
///     r_b = R₀(b⁰ − a⁰), r_c = R₀(c⁰ − a⁰); current ones d_b = R(b − a), d_c = R(c − a);
///     displacement D = (0, 0, r_bx − d_bx, 0, r_cx − d_cx, r_cy − d_cy) (computeDisplacementLarge);
///     J (6×3, strain-displacement of the CURRENT local triangle, computeStrainDisplacementLocal);
///     ε = Jᵀ D, σ = Dₐ ε, F = J σ, f_i += Rᵀ (F_2i, F_2i+1, 0);
///   - small (initSmall, accumulateForceSmall): no frame: world x, y of b − a and c − a, J from
///     the current world triangle (computeStrainDisplacementGlobal, 1/|(b−a)×(c−a)|), forces
///     (F_2i, F_2i+1, 0) — world z is ignored, as SOFA;
///   - stiffness (applyStiffnessLarge / applyStiffnessSmall, buildStiffnessMatrix):
///     K_e = −Rᵀ [J Dₐ Jᵀ]_xy R with R and J of the last add_force (their derivatives ignored, as
///     SOFA: exact at a stress-free configuration).
/// SOFA does not implement its potential energy; potential_energy() here returns Σ ½ ε·σ at the
/// last add_force (a diagnostic: f is not exactly its gradient, since J follows the deformation).
///
/// The older TriangleFEMForceField (flavor TriangleFEM) is the same element with three differences
/// (TriangleFEMForceField::computeMaterialStiffnesses, accumulateForceSmall, init):
///   - material Dₐ times thickness·A₀ with A₀ = ½|(b⁰−a⁰)×(c⁰−a⁰)|, and optionally plane strain
///     E/((1+ν)(1−2ν))·[[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, ½−ν]];
///   - method small: J by the local formula (det = b_x·c_y) applied to the world b − a, c − a;
///   - a topology without triangles but with quads is split, quad q → (q0, q1, q2), (q0, q2, q3).

#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace penalty {

class TopologyContainer;

namespace detail {

/// The method-large product's data of four triangles, packed for it (src/kernels/mechanics/
/// triangle_fem_large.hpp): triangle 4b + l in lane l of block b, made from the frames, J and Dₐ
/// of the last force evaluation (or init, or a topological change) before the next product.
struct TriangleFemLargeBlock {
    static constexpr std::size_t kWidth = 4;
    using Lanes = std::array<double, kWidth>;
    /// J's entries the product reads, in this order (the others are zero in a local J)
    enum JEntry : std::uint8_t { j00, j20, j11, j31, j51, j02, j12, j22, j32, j42, kJEntries };
    /// Dₐ's entries the product reads
    enum MaterialEntry : std::uint8_t { d00, d01, d10, d11, d22, kMaterialEntries };
    alignas(32) std::array<Lanes, 9> frame{};                    ///< Rᵀ(r, c) at 3r + c
    alignas(32) std::array<Lanes, kJEntries> j{};                ///< J (6×3, strain-displacement)
    alignas(32) std::array<Lanes, kMaterialEntries> material{};  ///< Dₐ (N/m)
    std::array<std::array<std::int32_t, kWidth>, 3> vertex{};    ///< the triangle's vertices a, b, c
};

}  // namespace detail

/// Which SOFA component the element follows (see the file comment).
enum class TriangleFemFlavor { TriangularFEM, TriangleFEM };

struct TriangleFemParameters {
    double young_modulus = 5000.0;  ///< E (Pa), > 0
    double poisson_ratio = 0.45;    ///< ν ∈ (−1, 0.5)
    FemMethod method = FemMethod::Large;
    TriangleFemFlavor flavor = TriangleFemFlavor::TriangularFEM;
    double thickness = 1.0;     ///< m, > 0 (TriangleFEM flavor only)
    bool plane_strain = false;  ///< TriangleFEM flavor only
};

class TriangularFEMForceField final : public ForceField<Vec3Types> {
public:
    using StrainDisplacement = Eigen::Matrix<double, 6, 3>;

    /// The triangles of `topology` (in its order); E > 0 (Pa), ν ∈ (−1, 0.5).
    TriangularFEMForceField(Vec3Object& state, const MeshTopology& topology, double young_modulus, double poisson_ratio,
                            FemMethod method = FemMethod::Large);
    /// Either flavor; the TriangleFEM flavor splits the quads of a topology without triangles.
    TriangularFEMForceField(Vec3Object& state, const MeshTopology& topology, const TriangleFemParameters& parameters);

    /// Rest frames, rest local coordinates, areas and material matrices from the rest positions;
    /// throws std::invalid_argument for a degenerate (zero-area) triangle.
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const std::vector<Triangle>& triangles() const { return triangles_; }
    /// Replaces the triangles (a topology follower, then init()).
    void set_triangles(std::vector<Triangle> triangles) {
        triangles_ = std::move(triangles);
        blocks_current_ = false;
    }
    /// SOFA's TriangularFEMForceField triangleInfo, a TopologyData (init's createTopologyHandler,
    /// creation callback createTriangleInformation): a removed triangle's data is swapped with the
    /// last one's and popped (TopologyData::remove); a new triangle's data is computed when its
    /// addition event arrives, from the state's rest positions at that moment
    /// (initLarge/initSmall, computeMaterialStiffness); the other triangles keep theirs, also when
    /// a vertex moves (movePointsProcess: SOFA's TopologyData ignore it). The triangles' vertices
    /// follow the container (src/mechanics/topology/triangular_fem_changes.cpp).
    void handle_topology_changes(const TopologyContainer& container, std::span<const TopologyChange> changes);
    /// Once the operation is done: the vertices of the triangles a change touched from the container.
    void topology_change_done();
    /// SOFA's TriangleFEMForceField after a change (it keeps no topology data): the triangles become
    /// `triangles` (the topology's), each slot keeps the rest data it has; a slot past them gets its
    /// data from the current rest positions (SOFA reads past its vectors there). Returns how many
    /// slots got new data.
    std::size_t take_triangles_keeping_slot_data(const std::vector<Triangle>& triangles);
    /// Rest area A₀ of each triangle (m²), per slot (TriangleFEMForceField after a change: more
    /// slots than triangles).
    [[nodiscard]] const std::vector<double>& rest_areas() const { return area_; }
    [[nodiscard]] FemMethod method() const { return parameters_.method; }
    [[nodiscard]] const TriangleFemParameters& parameters() const { return parameters_; }
    /// From OrderedScatter::kMinElements triangles on several threads, the product runs on TBB's
    /// threads with the bits of one thread; its split as the last of them made it.
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }
    /// Instructions of the method-large product (default best_kernel_path(); every path gives the
    /// same bits). Throws std::invalid_argument if this machine cannot run `path`, or for avx512
    /// (no such path here).
    void set_kernel_path(KernelPath path);
    [[nodiscard]] KernelPath kernel_path() const { return kernel_path_; }

private:
    /// f(v) for each per-triangle array (rest_local_, area_, material_, j_, rotation_): the data a
    /// topological change resizes, swaps or permutes with the triangles.
    template <class F>
    void for_each_element_array(F&& f) {
        f(rest_local_), f(area_), f(material_), f(j_), f(rotation_);
    }
    /// Triangle e's rest data (rest_local_, area_, material_, j_, rotation_) from the rest
    /// positions; throws std::invalid_argument for a degenerate triangle or a point past the state.
    void init_element(std::size_t e);
    /// One triangle's force at x: the terms f_k += terms[k] of its vertices, J and the frame Rᵀ
    /// the product reads, ½ ε·σ.
    struct ElementForce {
        std::array<Vec3, 3> terms;
        StrainDisplacement j;
        Mat3 to_world;
        double energy = 0.0;
    };
    /// Triangle e's force at x into `out`; false for a triangle degenerate now (`out` then holds
    /// nothing of it).
    bool element_terms(std::size_t e, std::span<const Vec3> x, ElementForce& out) const;
    /// TriangleFEMForceField, and TriangularFEMForceField "large": SOFA's TriangleFEMUtils operations.
    [[nodiscard]] bool uses_sofa_order() const;
    /// element_terms of those, with SOFA's operations in SOFA's order
    /// (src/mechanics/triangle_fem_sofa_order.hpp: the same bits as SOFA).
    bool element_terms_sofa_order(std::size_t e, std::span<const Vec3> x, ElementForce& out) const;
    /// add_force's loop on one thread, triangle by triangle, stopping at a degenerate one (SOFA's).
    void add_force_in_order(std::span<Vec3> f, std::span<const Vec3> x);
    /// add_dforce over triangles [first, end) of the TriangleFEM flavor with method small, with
    /// SOFA's operations in SOFA's order, the terms `deferred` marks stored instead of added
    /// (detail::DeferredTerms, or detail::NoDeferredTerms on one thread). Method large, either
    /// flavor: detail::triangle_fem_large_dforce on large_blocks_.
    template <class Deferred>
    void dforce_range_sofa_order(std::size_t first, std::size_t end, std::span<Vec3> df, std::span<const Vec3> dx,
                                 double k_factor, const Deferred& deferred) const;
    /// The same for the other triangles (TriangularFEMForceField small).
    template <class Deferred>
    void dforce_range(std::size_t first, std::size_t end, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                      const Deferred& deferred) const;
    /// −[J Dₐ Jᵀ] (6×6, local x, y per vertex) of triangle e at the last add_force.
    [[nodiscard]] Eigen::Matrix<double, 6, 6> local_stiffness(std::size_t e) const;

    std::vector<Triangle> triangles_;
    TriangleFemParameters parameters_;
    std::vector<std::array<Vec3, 2>> rest_local_;  ///< r_b, r_c (rotatedInitialElements 1, 2)
    std::vector<double> area_;
    std::vector<Mat3> material_;         ///< Dₐ (includes A₀)
    std::vector<StrainDisplacement> j_;  ///< J at the last add_force
    std::vector<Mat3> rotation_;         ///< Rᵀ (columns = local axes) at the last add_force
    double energy_ = 0.0;
    /// add_force on threads (from OrderedScatter::kMinElements triangles): J and the frames of
    /// the pass, swapped with j_ and rotation_ when no triangle was degenerate; f before the
    /// pass, for the loop on one thread when one was; each triangle's energy, summed in order.
    std::vector<StrainDisplacement> next_j_;
    std::vector<Mat3> next_rotation_;
    std::vector<Vec3> force_before_;
    std::vector<double> energies_;
    /// The product's split from OrderedScatter::kMinElements triangles on several threads (made
    /// again when the triangles change).
    mutable detail::OrderedScatter scatter_;
    /// Method large's product data packed in blocks (detail::TriangleFemLargeBlock), made by the
    /// first product after a change of the frames, J, Dₐ or triangles (blocks_current_ false:
    /// init, add_force, a topological change).
    mutable std::vector<detail::TriangleFemLargeBlock> large_blocks_;
    mutable bool blocks_current_ = false;
    KernelPath kernel_path_ = best_kernel_path();

    /// What handle_topology_changes leaves for topology_change_done.
    struct PendingTopologyChange {
        const TopologyContainer* container = nullptr;
        std::vector<std::size_t> slots;       ///< slots a swap filled
        std::vector<PointId> renamed_points;  ///< removed points' indices (the last points take them)
        bool all = false;                     ///< the points were renumbered: every triangle's vertices
    };
    PendingTopologyChange pending_;
};

}  // namespace penalty
