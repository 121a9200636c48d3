#pragma once
/// @file
/// SOFA's NonUniformHexahedronFEMForceFieldAndMass: a hexahedral FEM with mass on a sparse grid
/// built with virtual finer levels (SparseGridTopology nbVirtualFinerLevels, sparse_grid_topology.hpp),
/// whose element stiffness and mass matrices are condensed from the finest level's
/// (NonUniformHexahedronFEMForceFieldAndMass::computeMechanicalMatricesByCondensation):
///   - at the finest level used (the force field's nbVirtualFinerLevels below the grid), each cell
///     has the classical hexahedron stiffness K_f of its corners (times the mechanical state's
///     scale) with the isotropic material (computeMaterialStiffness: E, ν of element 0) times the
///     cell's coefficient c, and SOFA's element mass M_f (HexahedronFEMForceFieldAndMass::
///     computeElementMass: every 3×3 block m·I, m = V·(8/27 summed as SOFA)·ρ, V = |e01||e03||e04|)
///     times c (computeClassicalMechanicalMatrices uses the stiffness coefficient for both);
///   - one level up, a cell's matrix is Σ over its children i of T_iᵀ K_i T_i with T_i SOFA's
///     FINE_TO_COARSE trilinear interpolation of the child's corners from the parent's
///     (addFineToCoarse, its sums in SOFA's order), up to the grid's own cells.
/// The force field is HexahedronFEMForceField with these K (set_element_stiffness), SOFA's own; the mass
/// applies M per element in world axes (HexahedronFEMForceFieldAndMass::addMDx), or their
/// absolute row sums when lumped; gravity acts on particle masses Σ_e ρ·c_e·V_e/8 of the grid's
/// own cells (c_e: the cell's mass coefficient, V_e from the state's rest positions).

#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/sparse_grid_topology.hpp"

#include <vector>

namespace penalty {

using HexahedronMatrix = Eigen::Matrix<double, 24, 24>;

struct CondensedHexahedra {
    std::vector<HexahedronMatrix> stiffness;  ///< per cell of the grid (N/m)
    std::vector<HexahedronMatrix> mass;       ///< per cell of the grid (kg)
};

/// The condensed matrices of every cell of `grid`, from `levels` levels below it (1 ≤ levels ≤
/// grid.finer_levels()); `scale`: the mechanical state's scale3d applied to the finest corners.
[[nodiscard]] CondensedHexahedra condense_hexahedra(const SparseGridTopology& grid, int levels, double young_modulus,
                                                    double poisson_ratio, double density, bool fill_weighted,
                                                    const Vec3& scale = Vec3::Ones());

/// The mass of NonUniformHexahedronFEMForceFieldAndMass: element matrices M_e (world axes),
/// lumped or not, and particle masses for gravity. With `use_mass` false (SOFA's useMass), the
/// mass is diagonal: every particle has totalMass / (number of elements).
class HexahedronMatrixMass final : public BaseMass {
public:
    struct Parameters {
        double density = 1;
        bool lumped = false;
        bool use_mass = true;
        double total_mass = 0;  ///< with use_mass false
    };
    HexahedronMatrixMass(Vec3Object& state, std::vector<Hexahedron> hexahedra,
                         std::vector<HexahedronMatrix> element_mass, std::vector<double> mass_coefficients,
                         Parameters p);
    void init() override;
    void add_gravity_force(const Vec3& gravity) override;
    void add_mdx(double factor) override;
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const override;
    void add_mass_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double kinetic_energy() const override;
    [[nodiscard]] double gravity_potential_energy(const Vec3& gravity) const override;
    [[nodiscard]] double total_mass() const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] const std::vector<double>& particle_masses() const { return particle_masses_; }

private:
    /// y += factor·M·x.
    void multiply_add(std::span<Vec3> y, std::span<const Vec3> x, double factor) const;
    Vec3Object* state_;
    std::vector<Hexahedron> hexahedra_;
    std::vector<HexahedronMatrix> element_mass_;
    std::vector<double> mass_coefficients_;
    Parameters p_;
    std::vector<double> particle_masses_;
    std::vector<Vec3> lumped_;  ///< per DOF and direction, when lumped
};

}  // namespace penalty
