#pragma once
/// @file
/// SOFA's MeshMatrixMass<Vec1d, Vec3d>: the mass matrix of a tetrahedral (or other) mesh on a
/// scalar state (a temperature), its element measures taken from a Vec3d geometry state
/// (`geometryState`). The masses are MeshMatrixMass<Vec3d>'s for that geometry and the same Data
/// (mesh_matrix_mass.hpp: a mass per vertex and per edge, or the lumped diagonal); the matrix is
/// their 1×1 version: m_v on the diagonal, m_e at both places of each edge. Gravity acts through
/// its x component alone (SOFA's DataTypes::set of a Vec1 from (g_x, g_y, g_z) keeps g_x).

#include "penalty/mechanics/mesh_matrix_mass.hpp"

#include <memory>

namespace penalty {

class ScalarMeshMatrixMass final : public BaseMass {
public:
    /// `geometry`: the Vec3d state whose positions measure the elements (read at init).
    ScalarMeshMatrixMass(Vec1Object& state, Vec3Object& geometry, const MeshTopology& topology);

    /// The Data of MeshMatrixMass (measured on the geometry).
    [[nodiscard]] MeshMatrixMass& masses() { return *masses_; }
    [[nodiscard]] const MeshMatrixMass& masses() const { return *masses_; }

    /// Computes the masses (std::invalid_argument: as MeshMatrixMass::init, or a geometry with
    /// another number of points than the state).
    void init() override;

    void add_gravity_force(const Vec3& gravity) override;
    void add_mdx(double factor) override;
    /// Lumped only (as MeshMatrixMass).
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const override;
    void add_mass_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double kinetic_energy() const override;
    [[nodiscard]] double gravity_potential_energy(const Vec3& gravity) const override;
    [[nodiscard]] double total_mass() const override { return masses_->total_mass(); }
    [[nodiscard]] BaseState* state() const override { return state_; }

private:
    Vec1Object* state_;
    Vec3Object* geometry_;
    std::unique_ptr<MeshMatrixMass> masses_;  ///< MeshMatrixMass<Vec3d> over the geometry
};

}  // namespace penalty
