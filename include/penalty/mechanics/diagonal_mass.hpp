#pragma once
/// @file
/// SOFA's DiagonalMass for Vec3d: a lumped mass per vertex computed from the topology's elements
/// (spec §10.4's UniformMass interface; see docs/components/mass.md).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <optional>
#include <span>
#include <vector>

namespace penalty {

/// The element kind DiagonalMass lumps (SOFA's DiagonalMass::checkTopology): the first of
/// hexahedra, tetrahedra, quads, triangles, edges that the topology has.
enum class LumpedElementKind { hexahedron, tetrahedron, quad, triangle, edge };

/// The kind used for `topology`; throws std::invalid_argument when it has no element.
[[nodiscard]] LumpedElementKind lumped_element_kind(const MeshTopology& topology);
[[nodiscard]] const char* lumped_element_name(LumpedElementKind kind);
/// The topology element type of `kind` (the type its topological changes name).
[[nodiscard]] ElementType element_type_of(LumpedElementKind kind);

/// SOFA's DiagonalMass::computeVertexMass: each element of `kind` gives density × its measure
/// (length, area, volume) / (its vertex count) to each of its vertices. `masses` is resized to
/// `num_points` and overwritten; returns the sum of the shares in SOFA's order (element order,
/// then vertex order). Measures: edge length; triangle ½|ab × ac|; quad = triangles (0,1,2) +
/// (0,2,3); tetrahedron |(ab × ac)·ad| / 6; hexahedron = six tetrahedra (SOFA's
/// geometry::Hexahedron::volume split).
double lump_vertex_masses(const MeshTopology& topology, LumpedElementKind kind, std::span<const Vec3> positions,
                          double density, std::size_t num_points, std::vector<double>& masses);

/// The measure of one element of `kind` (its N vertices' positions): what lump_vertex_masses
/// shares, ρ·measure/N to each vertex.
[[nodiscard]] double lumped_element_measure(LumpedElementKind kind, std::span<const Vec3> vertices);

/// DiagonalMass<Vec3d>: M = diag(m_i I₃). The masses come, in SOFA's order of priority
/// (DiagonalMass::massInitialization), from
///  - `totalMass` M: lumped with density 1, then every m_i scaled by ρ = M / Σ;
///  - `massDensity` ρ: lumped with ρ;
///  - `vertexMass` (a list; a shorter list is padded with its last value to the DOF count);
///  - nothing: totalMass = 1 kg.
/// Lumping uses the rest positions (SOFA's computeMassOnRest, default true).
class DiagonalMass final : public BaseMass {
public:
    DiagonalMass(Vec3Object& state, const MeshTopology& topology) : state_(&state), topology_(&topology) {}

    /// Mass density (kg/m³, kg/m² or kg/m for volumes, surfaces, edges); finite and >= 0.
    void set_mass_density(double density);
    /// Total mass (kg); finite and >= 0.
    void set_total_mass(double total);
    /// Mass of each vertex (kg); each finite and >= 0.
    void set_vertex_masses(std::vector<double> masses);

    /// Computes the vertex masses (throws std::invalid_argument for an empty topology or a
    /// vertexMass list longer than the state).
    void init() override;

    [[nodiscard]] const std::vector<double>& vertex_masses() const { return masses_; }
    /// ρ after init (given, or deduced from totalMass / vertexMass as SOFA does).
    [[nodiscard]] double mass_density() const { return density_; }
    [[nodiscard]] LumpedElementKind element_kind() const { return kind_; }

    void add_gravity_force(const Vec3& gravity) override;
    void add_mdx(double factor) override;
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const override;
    void add_mass_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double kinetic_energy() const override;
    [[nodiscard]] double gravity_potential_energy(const Vec3& gravity) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] double total_mass() const override { return total_; }

    /// SOFA's DiagonalMass topology callbacks (src/mechanics/topology/diagonal_mass_changes.cpp):
    /// a new point gets 0, a removed point's mass leaves the total (then swap-and-pop); an added
    /// or removed element of the lumped kind adds or subtracts ρ·measure/N at each vertex (from
    /// the rest positions), element by element: the masses follow by sums, not by a new lumping.
    void handle_topology_changes(const class TopologyContainer& container, std::span<const TopologyChange> changes);
    /// SOFA's DiagonalMass::doUpdateInternal at the step's UpdateInternalDataVisitor, after the
    /// changes of AnimateBeginEvent: when a point event edited the vertex masses after the
    /// callbacks (TopologyData's swap-and-pop, append, renumbering), initFromVertexMass takes
    /// totalMass = Σ m_i and ρ = totalMass / Σ(shares at ρ = 1) again (the masses stay); a later
    /// element change uses that ρ.
    void update_internal_data();

private:
    bool vertex_masses_edited_ = false;  ///< d_vertexMass dirty for SOFA's data tracker
    Vec3Object* state_;
    const MeshTopology* topology_;
    std::optional<double> given_density_;
    std::optional<double> given_total_;
    std::optional<std::vector<double>> given_masses_;
    LumpedElementKind kind_ = LumpedElementKind::edge;
    std::vector<double> masses_;
    double density_ = 1.0;
    double total_ = 0.0;
};

}  // namespace penalty
