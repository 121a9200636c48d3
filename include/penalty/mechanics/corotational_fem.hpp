#pragma once
/// @file
/// SOFA's TetrahedralCorotationalFEMForceField (Nesme, Payan, Faure 2005): linear tetrahedra,
/// methods small, large (default) and polar. With its default options it computes what
/// TetrahedronFEMForceField computes (same frame, same rest stiffness, same −Rᵀ K^e R for
/// add_dforce); it differs by its options:
///  - localStiffnessFactor (M values for N elements): element e's Young's modulus is multiplied by
///    factor[e·M/N] (computeMaterialStiffness);
///  - updateStiffnessMatrix (large and polar): each add_force rebuilds the strain-displacement
///    matrix J from the current shape in the element frame, keeping the rest volume:
///    K^e = J D Jᵀ / (36 V⁰) (accumulateForceLarge / accumulateForcePolar);
///  - computeGlobalMatrix (alias assembling) with method polar: SOFA only logs an error and adds no
///    force (the rotation and K^e are still updated for add_dforce); reproduced.
/// Elements are the topology's tetrahedra only (hexahedra are not split, unlike TetrahedronFEM).

#include "penalty/mechanics/fem.hpp"

namespace penalty {

struct CorotationalFemOptions {
    FemMethod method = FemMethod::Large;
    std::vector<double> local_stiffness_factors = {};  ///< empty: 1 for every element
    bool update_stiffness = false;
    bool assembling = false;  ///< computeGlobalMatrix: storage only, except the polar quirk above
};

class TetrahedralCorotationalFEMForceField final : public LinearElementForceField<4> {
public:
    TetrahedralCorotationalFEMForceField(Vec3Object& state, std::vector<Tetrahedron> tetrahedra, double young_modulus,
                                         double poisson_ratio, CorotationalFemOptions options = {});

    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] const std::vector<Element>& tetrahedra() const { return elements_; }
    /// Instructions of the loops of SOFA's operations (TetrahedronFEMForceField::set_kernel_path's:
    /// default best_fem_kernel_path(), every path the same bits). Throws std::invalid_argument if
    /// this machine cannot run `path`.
    void set_kernel_path(KernelPath path);
    [[nodiscard]] KernelPath kernel_path() const { return kernel_path_; }
    [[nodiscard]] const CorotationalFemOptions& options() const { return options_; }
    /// Element e's factor on Young's modulus (localStiffnessFactor[e·M/N], or 1).
    [[nodiscard]] double stiffness_factor(std::size_t e) const;

protected:
    [[nodiscard]] ElementMatrix compute_stiffness(const std::array<Vec3, 4>& rest_local,
                                                  const Eigen::Matrix<double, 6, 6>& d, std::size_t e) const override;
    [[nodiscard]] Mat3 element_rotation(const std::array<Vec3, 4>& p) const override;
    /// SOFA's operations keep R in the lane blocks (blocks_), the common path in rotation_.
    [[nodiscard]] bool keeps_rotations() const override { return !sofa_operations(); }
    /// K^e at init for the common path's products; on SOFA's path only an assembling solver reads
    /// it (add_stiffness_triplets), which makes it when first asked for (element_stiffness()).
    [[nodiscard]] bool element_stiffness_at_init() const override { return !sofa_operations(); }
    /// A degenerate rest tetrahedron (volume ≤ 1e-12/6 of its longest edge cubed) is refused.
    void check_rest_element(const std::array<Vec3, 4>& rest_local, std::size_t e) const override;

private:
    /// K^e = factor · J D Jᵀ / (36 V⁰), J from the local coordinates `shape`, V⁰ the rest volume.
    [[nodiscard]] ElementMatrix stiffness_of_shape(const std::array<Vec3, 4>& shape, double rest_volume,
                                                   std::size_t e) const;

    /// Without computeGlobalMatrix, and for large and polar without updateStiffnessMatrix: SOFA's
    /// operations in SOFA's order, TetrahedronFEMForceField's (src/mechanics/tetrahedron_large_blocks.hpp),
    /// the same bits as SOFA.
    [[nodiscard]] bool sofa_operations() const;
    /// sofa_operations(): J of the rest coordinates (initSmall, initLarge or initPolar), D·factor/(36 V⁰)
    /// (computeMaterialStiffness) and R of the last add_force, per element in the lanes of the
    /// kernel path's blocks; empty otherwise.
    detail::TetrahedronLargeBlocks blocks_;
    KernelPath kernel_path_ = best_fem_kernel_path();

    CorotationalFemOptions options_;
    Eigen::Matrix<double, 6, 6> material_;  ///< isotropic_elasticity(E, ν), Pa
    std::vector<double> rest_volume_;       ///< V⁰ per element, m³
    std::vector<Vec3> scratch_force_;       ///< polar + assembling: the force SOFA computes and drops
};

}  // namespace penalty
