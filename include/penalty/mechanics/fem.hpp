#pragma once
/// @file
/// Linear-elastic finite elements: TetrahedronFEMForceField (4-node linear tetrahedra) and
/// HexahedronFEMForceField (8-node trilinear hexahedra, 2×2×2 Gauss quadrature), each with
/// method "small" (linear elasticity in the world frame) or "large" (corotational, SOFA's
/// default). Isotropic material: Young's modulus E (Pa) > 0, Poisson's ratio ν ∈ (−1, 0.5).
///
/// Corotational ("large") as SOFA: each element gets a rotation R (rows = local axes) built from
/// its edges — tetrahedron: x̂ along p1−p0, ẑ ⟂ (p1−p0, p2−p0), ŷ = ẑ × x̂; hexahedron: x̂ along
/// the mean of the four edges 0→1, ŷ from the mean of the edges 0→3 made orthogonal. With rest
/// local coordinates r_i = R₀(x⁰_i − x⁰_0) and current ones d_i = R(x_i − x_0):
///   f_i = −Rᵀ Σ_j K^e_ij (d_j − r_j),  K = ∂f/∂x ≈ −Rᵀ K^e R  (rotation derivative ignored, as
/// SOFA: exact at stress-free configurations). Energy ½ uᵀ K^e u with u = d − r.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <Eigen/Core>

#include <array>
#include <limits>
#include <mutex>
#include <span>
#include <variant>

namespace penalty {

/// Small: linear, world frame. Large: corotational, rotation from the element's edges. Polar
/// (tetrahedra only): corotational, rotation = orthogonal polar factor of the edge matrix. Svd
/// (TetrahedronFEMForceField only): as polar, except for an inverted or flat element (see
/// TetrahedronFEMForceField).
enum class FemMethod { Small, Large, Polar, Svd };

/// The orthogonal factor Q of M = Q·S (S symmetric positive semi-definite), by the scaled Newton
/// iteration SOFA uses (helper::Decompose::polarDecomposition: iterate on Mᵀ, X ← γ/2·X +
/// 1/(2γ det X)·cof X, γ from the 1- and ∞-norms, until ‖ΔX‖₁ ≤ 1e-8·‖X‖₁). A reflection when
/// det M < 0; M itself when det M = 0.
Mat3 polar_rotation(const Mat3& m);

/// SOFA's helper::Decompose::polarDecomposition_stable (SVD_stable, then Q = U·Vᵀ): V from the
/// eigenvectors of FᵀF (a reflection made a rotation by negating its first column), singular
/// values below 1e-8 (squared) treated as zero and the missing columns of U = F·V·S⁻¹ rebuilt
/// (one zero: cross product of the two others; two: an orthonormal completion, with SOFA's mixed
/// indices; three: identity); an inverted U has its column of the smallest value negated. The
/// eigenvectors come from Eigen's solver, not SOFA's iteration (rotation equal up to rounding).
Mat3 stable_polar_rotation(const Mat3& f);

/// Rows (x̂, ŷ, ẑ) of a hexahedron's corotational frame (SOFA vertex order): x̂ along the mean of
/// the four edges 0→1, ŷ from the mean of the four edges 0→3 made orthogonal, ẑ = x̂ × ŷ
/// (HexahedronFEMForceField::computeRotationLarge, HexahedralFEMForceField::initLarge).
Mat3 hexahedron_edge_frame(const std::array<Vec3, 8>& p);

/// A hexahedron's corotational frame for method polar: polar_rotation of the matrix whose rows are
/// the means of the four edges along x (0→1), y (0→3) and z (0→4)
/// (HexahedronFEMForceField::computeRotationPolar, HexahedralFEMForceField::computeRotationPolar).
Mat3 hexahedron_polar_frame(const std::array<Vec3, 8>& p);

/// Isotropic material stiffness in Voigt notation (εxx, εyy, εzz, γxy, γyz, γzx), Pa.
Eigen::Matrix<double, 6, 6> isotropic_elasticity(double young_modulus, double poisson_ratio);

/// Stiffness of a linear tetrahedron, scale·BᵀDB (12×12): B (6×12, Voigt with engineering shear)
/// from the gradients g_k of the four shape functions (any common scaling, compensated by `scale`).
Eigen::Matrix<double, 12, 12> tetrahedron_stiffness_from_gradients(const std::array<Vec3, 4>& gradients,
                                                                   const Eigen::Matrix<double, 6, 6>& d, double scale);

/// Corotational frame of a tetrahedron p (rows = local axes), SOFA's computeRotationLarge of
/// TetrahedronFEMForceField and TetrahedralCorotationalFEMForceField: x̂ along p1−p0, ẑ ⟂ (p1−p0,
/// p2−p0), ŷ = ẑ × x̂; method Polar: polar_rotation of the matrix whose rows are p1−p0, p2−p0, p3−p0
/// (accumulateForcePolar of both). Small: identity.
Mat3 tetrahedron_rotation(const std::array<Vec3, 4>& p, FemMethod method);

template <int N>
class LinearElementForceField : public ForceField<Vec3Types> {
public:
    using Element = std::array<PointId, N>;
    using ElementMatrix = Eigen::Matrix<double, 3 * N, 3 * N>;

    LinearElementForceField(Vec3Object& state, std::vector<Element> elements, double young_modulus,
                            double poisson_ratio, FemMethod method, const char* component);

    /// Precomputes rest frames and element stiffness from the state's rest positions.
    void init() override;
    /// Replaces the elements (a topology follower, then init()).
    void set_elements(std::vector<Element> elements) { elements_ = std::move(elements); }
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }
    /// Each element's K^e (3N×3N; empty before init()). Made at init when the products read it;
    /// TetrahedronFEMForceField's products read its lane blocks instead, and it makes K^e when
    /// first asked for (here or by add_stiffness_triplets: a direct solver), from the rest
    /// coordinates init kept for it: the same matrices, without their 1 152 bytes a tetrahedron
    /// in a scene that never assembles them.
    [[nodiscard]] const std::vector<ElementMatrix>& element_stiffness() const;
    /// From OrderedScatter::kMinElements elements on several threads, the force and the product
    /// run on TBB's threads with the bits of one thread; their split as the last of them made it
    /// (chunk_count() 0 before one ran or when they ran on one thread).
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return product_scatter_; }

protected:
    /// detail::scatter_in_order and detail::force_in_order over the elements (on threads from
    /// OrderedScatter::kMinElements elements, with the bits of one thread).
    template <bool Add, class Pass>
    void scatter_in_order(std::span<Vec3> out, std::size_t alignment, const Pass& pass) const {
        detail::scatter_in_order<Add>(product_scatter_, std::span<const Element>(elements_), out, alignment, pass);
    }
    template <bool Add, class Pass>
    double force_in_order(std::span<Vec3> f, std::size_t alignment, const Pass& pass) {
        return detail::force_in_order<Add>(product_scatter_, std::span<const Element>(elements_), f, alignment,
                                           element_energies_, pass);
    }
    /// init() for elements [first, size): the others keep their data (topological changes).
    void init_from(std::size_t first);
    /// Element stiffness K^e (SPD, 3N×3N) from local rest coordinates.
    [[nodiscard]] virtual ElementMatrix compute_stiffness(const std::array<Vec3, N>& rest_local,
                                                          const Eigen::Matrix<double, 6, 6>& d,
                                                          std::size_t e) const = 0;
    /// Rotation (rows = local axes) of an element with vertex positions p.
    [[nodiscard]] virtual Mat3 element_rotation(const std::array<Vec3, N>& p) const = 0;
    /// The rotation of element `e` at positions p (element_rotation unless a field needs the
    /// element's rest data).
    [[nodiscard]] virtual Mat3 element_rotation_of(const std::array<Vec3, N>& p, std::size_t) const {
        return element_rotation(p);
    }

    /// Whether rotation_ holds each element's R (TetrahedronFEMForceField's method large keeps R
    /// in its lane blocks instead, and rotation_ stays empty).
    [[nodiscard]] virtual bool keeps_rotations() const { return true; }
    /// Whether init makes ke_ (the products read it); else element_stiffness() makes it.
    [[nodiscard]] virtual bool element_stiffness_at_init() const { return true; }
    /// Where K^e is made on demand: compute_stiffness's checks of an element's rest coordinates
    /// (a degenerate element raised at init all the same).
    virtual void check_rest_element(const std::array<Vec3, N>& /*rest_local*/, std::size_t /*e*/) const {}
    /// Element e's −factor·Rᵀ K^e R blocks, with R = `r`, into `triplets`.
    void add_element_triplets(TripletList& triplets, Index offset, double factor, std::size_t e, const Mat3& r) const;

    std::vector<Element> elements_;
    double young_, poisson_;
    FemMethod method_;
    const char* component_;
    /// K^e per element: made at init, or when first asked for (element_stiffness_at_init()
    /// false: empty until then, and emptied by an init)
    mutable std::vector<ElementMatrix> ke_;
    /// K^e's rest coordinates, when made on demand (init's, which a subclass may overwrite in
    /// rest_local_ with its own)
    std::vector<std::array<Vec3, N>> stiffness_rest_;
    mutable std::mutex stiffness_mutex_;  ///< element_stiffness()'s making of ke_
    std::vector<std::array<Vec3, N>> rest_local_;
    std::vector<Mat3> rotation_;  ///< R per element at the last add_force (identity for small; see keeps_rotations)
    double energy_ = 0.0;
    /// scatter_in_order's split and stored terms, made again when the chunk count or the element
    /// count changes (a field whose elements change in place clears it).
    mutable detail::OrderedScatter product_scatter_;
    std::vector<double> element_energies_;  ///< force_in_order's, summed in element order after
};

class RegularGridTopology;
class TopologyContainer;

namespace detail {
/// TetrahedronFEMForceField's method-large data of W elements side by side: element e is lane
/// e % W of block e / W. The vertices are the field's element list. The last block's lanes past
/// the last element hold zero J and D (their vector results are never added).
template <std::size_t W>
struct alignas(8 * W) TetrahedronLargeLanes {
    static constexpr std::size_t kLanes = W;
    using Lanes = std::array<double, W>;
    std::array<Lanes, 9> rotation{};                 ///< R(i, j) at 3i + j, from the last add_force
    std::array<std::array<Lanes, 3>, 4> cofactor{};  ///< J's entries g_yz, g_xz, g_xy of each vertex
    std::array<Lanes, 9> material{};                 ///< D/(36V)(i, k), i, k < 3, at 3i + k
    std::array<Lanes, 3> shear{};                    ///< D/(36V)(i, i), i = 3 … 5
};
/// The one copy of the method-large data, in blocks of the kernel path's width: eight lanes for
/// avx512 (its product reads a block an instruction), four for avx (the same) and scalar (one
/// lane at a time).
using TetrahedronLargeBlocks =
    std::variant<std::vector<TetrahedronLargeLanes<4>>, std::vector<TetrahedronLargeLanes<8>>>;
}  // namespace detail

/// SOFA's TetrahedronFEMForceField (methods small, large, polar and svd). Polar
/// (TetrahedronFEMForceField::initPolar / accumulateForcePolar): R = polar_rotation(A) with A's
/// rows the edges p1−p0, p2−p0, p3−p0, rest coordinates R₀x⁰_k (each vertex rotated), the
/// element force and product as large's below, in SOFA's operations too. As SOFA, a topology without
/// tetrahedra but with hexahedra is split into 6 tetrahedra per hexahedron
/// (tetrahedra_from_hexahedra, with the grid's cell counts for a RegularGridTopology and SOFA's
/// fallback nx = 2, ny = 1 otherwise).
///
/// Method large follows SOFA's floating-point operations in SOFA's order, so that a scene matches
/// SOFA's trajectory to the last bit (initLarge, computeMaterialStiffness,
/// computeStrainDisplacement, accumulateForceLarge, computeForce, applyStiffnessCorotational):
/// the frame R from x̂ = (p1−p0)/|p1−p0|, ẑ = x̂ × (p2−p0) normalised, ŷ = ẑ × x̂; rest local
/// coordinates R₀x⁰_k − R₀x⁰_0; the element force J·(D/(36V))·Jᵀ·δ with J the 12×6
/// strain-displacement matrix of cofactors (6V times the shape-function gradients) and D SOFA's
/// material matrix, every product written over J's non-zero pattern. K^e (element_stiffness(),
/// add_stiffness_triplets) is the same matrix, computed by the common path.
class TetrahedronFEMForceField final : public LinearElementForceField<4> {
public:
    TetrahedronFEMForceField(Vec3Object& state, const MeshTopology& topology, double young_modulus,
                             double poisson_ratio, FemMethod method = FemMethod::Large);
    TetrahedronFEMForceField(Vec3Object& state, const RegularGridTopology& grid, double young_modulus,
                             double poisson_ratio, FemMethod method = FemMethod::Large);
    [[nodiscard]] const std::vector<Element>& tetrahedra() const { return elements_; }
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// Instructions of method large's loops (default best_fem_kernel_path(); every path gives
    /// the same bits; avx512 runs add_dforce in eight lanes and add_force in avx's four). The
    /// element data move to the path's block width. Throws std::invalid_argument if this machine
    /// cannot run `path`.
    void set_kernel_path(KernelPath path);
    [[nodiscard]] KernelPath kernel_path() const { return kernel_path_; }

    /// Topological changes of its container (docs/topological-changes.md; defined in
    /// src/mechanics/topology/fem_changes.cpp): the per-element data follow the removals
    /// (swap-and-pop), additions and point renumbering, equal to what init() computes on the
    /// changed mesh (SOFA's reinit()), in time proportional to the change.
    void handle_topology_changes(const TopologyContainer& container, std::span<const TopologyChange> changes);
    /// After the whole change: the new elements' data and the renumbered vertices.
    void topology_change_done();

    /// SOFA's plasticity (TetrahedronFEMForceField::computeForce, plasticMaxThreshold > 0): per
    /// element a plastic strain εp (Voigt), updated at each force evaluation from the total strain
    /// ε = Jᵀδ: with εe = ε − εp, εp += creep·εe when |εe|² > yield², then εp scaled back to |εp| =
    /// max when |εp|² > max²; the stress uses ε − εp. The stiffness products are elastic (SOFA's
    /// addDForce ignores the plastic strain). Method large only; the force runs its scalar loop
    /// (src/mechanics/tetrahedron_plasticity.cpp).
    struct Plasticity {
        double max_threshold = 0.0;                ///< plasticMaxThreshold; 0: no plasticity
        double yield_threshold = double(0.0001f);  ///< plasticYieldThreshold (SOFA's float default)
        double creep = double(0.9f);               ///< plasticCreep (SOFA's float default)
    };
    /// Before init(); throws std::invalid_argument for a method other than large, or bad values.
    void set_plasticity(const Plasticity& plasticity);
    [[nodiscard]] const Plasticity& plasticity() const { return plasticity_; }
    /// The plastic strain of element e (Voigt xx, yy, zz, xy, yz, zx).
    [[nodiscard]] const std::array<double, 6>& plastic_strain(std::size_t e) const { return plastic_strain_[e]; }
    /// SOFA's `localStiffnessFactor` (before init(); method large): element e's Young's modulus
    /// is factors[e·M/N]·E for M factors and N elements (TetrahedronFEMForceField::
    /// computeMaterialStiffness); empty: E for all.
    void set_young_factors(std::vector<double> factors) { young_factors_ = std::move(factors); }

protected:
    [[nodiscard]] ElementMatrix compute_stiffness(const std::array<Vec3, 4>& rest_local,
                                                  const Eigen::Matrix<double, 6, 6>& d, std::size_t e) const override;
    [[nodiscard]] Mat3 element_rotation(const std::array<Vec3, 4>& p) const override;
    /// Method svd (TetrahedronFEMForceField::initSVD / accumulateForceSVD): with A the rows
    /// p1−p0, p2−p0, p3−p0 and F = A·A₀⁻¹ (A₀ at rest), R = polar_rotation(A) when det F ≥ 1e-6,
    /// else R = stable_polar_rotation(F)·R₀ (R₀ = polar_rotation(A₀)).
    [[nodiscard]] Mat3 element_rotation_of(const std::array<Vec3, 4>& p, std::size_t e) const override;

    [[nodiscard]] bool keeps_rotations() const override { return false; }
    /// K^e on demand, unless localStiffnessFactor scales it (made at init then, as SOFA's)
    [[nodiscard]] bool element_stiffness_at_init() const override { return !young_factors_.empty(); }
    void check_rest_element(const std::array<Vec3, 4>& rest_local, std::size_t e) const override;

private:
    /// J, D/(36V) and R of every element into the lane blocks (large_), by the method's init.
    void init_large(std::size_t first = 0);
    /// add_force of methods small, polar and svd (accumulateForceSmall, accumulateForcePolar,
    /// accumulateForceSVD) over elements [first, end), element by element, as large_force.
    double force_per_element(std::size_t first, std::size_t end, std::span<Vec3> f, std::span<const Vec3> x,
                             const detail::DeferredTerms& deferred, double* energies);
    /// Method small's product (applyStiffnessSmall) over elements [first, end), as large_dforce.
    void small_dforce(std::size_t first, std::size_t end, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                      const detail::DeferredTerms& deferred) const;
    /// init() for elements [first, size).
    void init_elements(std::size_t first);
    /// Method large's product df −= Rᵀ·F(R·dx, k) over elements [first, end), by the kernel path;
    /// the terms `deferred` marks stored instead of subtracted.
    void large_dforce(std::size_t first, std::size_t end, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                      const detail::DeferredTerms& deferred) const;
    /// Method large's addForce over elements [first, end): f += Rᵀ·F and each element's frame
    /// into its lane, the terms `deferred` marks stored instead of added; returns the energy
    /// summed in element order, or 0 with element e's into energies[e] (not null).
    double large_force(std::size_t first, std::size_t end, std::span<Vec3> f, std::span<const Vec3> x,
                       const detail::DeferredTerms& deferred, double* energies);
    /// What a topological change leaves to topology_change_done().
    struct PendingTopologyChange {
        const TopologyContainer* container = nullptr;
        std::vector<std::size_t> moved;   ///< elements given another's data (swap-and-pop)
        std::vector<PointId> renumbered;  ///< points that took the last point's index
        std::size_t first_new = std::numeric_limits<std::size_t>::max();
        bool rebuild = false;  ///< a renumbering: init() again
    };
    PendingTopologyChange pending_;

    std::vector<Mat3> rest_edges_inverse_;  ///< svd: A₀⁻¹ per element
    std::vector<Mat3> rest_rotation_;       ///< svd: R₀ per element
    /// J, D/(36V) and R of every element (R the identity for small), in blocks of the kernel path's width
    /// (lane e % W of block e / W), read and written by every path
    detail::TetrahedronLargeBlocks large_;
    /// Element e's R, from its lane.
    [[nodiscard]] Mat3 large_rotation(std::size_t e) const;
    /// Element `to`'s lane given element `from`'s data (swap-and-pop).
    void copy_large(std::size_t from, std::size_t to);
    /// Blocks of the kernel path's width for `count` elements; the lanes past the last element zeroed.
    void resize_large(std::size_t count);
    /// Whether large_ holds `count` elements' blocks of the kernel path's width.
    [[nodiscard]] bool large_fits(std::size_t count) const;
    KernelPath kernel_path_ = best_fem_kernel_path();
    /// add_force of method large with plasticity, SOFA's sums (tetrahedron_plasticity.cpp).
    void add_force_plastic(std::span<Vec3> f, std::span<const Vec3> x);
    Plasticity plasticity_;
    std::vector<double> young_factors_;  ///< localStiffnessFactor (set_young_factors)
    std::vector<std::array<double, 6>> plastic_strain_;
};

/// What SOFA's two hexahedron fields (HexahedronFEMForceField, HexahedralFEMForceField) share
/// beyond LinearElementForceField<8>: the instructions of their element products' K·d.
class HexahedronElementForceField : public LinearElementForceField<8> {
public:
    using LinearElementForceField<8>::LinearElementForceField;
    /// Instructions of the element products' K·d (detail::hexahedron_stiffness_times; default
    /// best_kernel_path(), every path the same bits). Throws std::invalid_argument if this machine
    /// cannot run `path`, or for avx512 (no such path here).
    void set_kernel_path(KernelPath path);
    [[nodiscard]] KernelPath kernel_path() const { return kernel_path_; }

protected:
    KernelPath kernel_path_ = best_kernel_path();
};

/// SOFA's HexahedronFEMForceField (methods small, large and polar), SOFA vertex order (see
/// topology), in SOFA's operations and order: K^e from computeElementStiffness's eight Gauss
/// points on the rotated rest corners R₀·x⁰_w; the force D = R₀x⁰ − R·x, f += Rᵀ·K·D (small: R
/// the identity, f += K·(x⁰ − x)); the product df −= (Rᵀ·K·R·dx)·kFactor. R is
/// hexahedron_edge_frame (large) or hexahedron_polar_frame (polar) of the element.
class HexahedronFEMForceField final : public HexahedronElementForceField {
public:
    HexahedronFEMForceField(Vec3Object& state, const MeshTopology& topology, double young_modulus, double poisson_ratio,
                            FemMethod method = FemMethod::Large)
        : HexahedronElementForceField(state, topology.hexahedra(), young_modulus, poisson_ratio, method,
                                      "HexahedronFEMForceField") {}

    /// Per-element factors on the element stiffness (SOFA's SparseGridTopology::getStiffnessCoef:
    /// 0.5 for a sparse grid's boundary cells when fillWeighted); empty: 1 for every element.
    /// Set before init().
    void set_stiffness_factors(std::vector<double> factors) { stiffness_factors_ = std::move(factors); }
    [[nodiscard]] const std::vector<double>& stiffness_factors() const { return stiffness_factors_; }
    /// Element stiffness matrices given instead of computeElementStiffness's, one per hexahedron
    /// in its rotated rest frame: NonUniformHexahedronFEMForceFieldAndMass's, condensed from a
    /// sparse grid's finer levels (its init computes them in place of HexahedronFEMForceField's;
    /// the force and the product are HexahedronFEMForceField's). Set before init().
    void set_element_stiffness(std::vector<ElementMatrix> stiffness) { given_stiffness_ = std::move(stiffness); }

    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    /// R₀·x⁰_w of element e's corners (SOFA's _rotatedInitialElements), once init() ran.
    [[nodiscard]] const std::array<Vec3, 8>& rotated_rest(std::size_t e) const { return rest_local_.at(e); }
    [[nodiscard]] std::size_t rotated_rest_count() const { return rest_local_.size(); }

protected:
    /// SOFA's computeElementStiffness on the element's rotated rest corners (the first argument,
    /// the common path's local coordinates, is not used).
    [[nodiscard]] ElementMatrix compute_stiffness(const std::array<Vec3, 8>& rest_local,
                                                  const Eigen::Matrix<double, 6, 6>& d, std::size_t e) const override;
    [[nodiscard]] Mat3 element_rotation(const std::array<Vec3, 8>& p) const override;

private:
    /// R₀ of element e at rest (the identity for small).
    [[nodiscard]] Mat3 rest_rotation(std::size_t e) const;
    /// R₀·x⁰_w of element e's corners for its rest rotation r0 (SOFA's _rotatedInitialElements).
    [[nodiscard]] std::array<Vec3, 8> rotated_rest_corners(std::size_t e, const Mat3& r0) const;
    /// add_force over elements [first, end) (element e's frame into rotation_[e]), the terms
    /// `deferred` marks stored instead of added; returns the energy summed in element order, or 0
    /// with element e's into energies[e] (not null).
    double force_range(std::size_t first, std::size_t end, std::span<Vec3> f, std::span<const Vec3> x,
                       const detail::DeferredTerms& deferred, double* energies);
    /// add_dforce over elements [first, end), the terms `deferred` marks stored.
    void dforce_range(std::size_t first, std::size_t end, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                      const detail::DeferredTerms& deferred) const;
    std::vector<double> stiffness_factors_;
    std::vector<ElementMatrix> given_stiffness_;
};

extern template class LinearElementForceField<4>;
extern template class LinearElementForceField<8>;

}  // namespace penalty
