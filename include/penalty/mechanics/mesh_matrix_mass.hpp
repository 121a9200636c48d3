#pragma once
/// @file
/// SOFA's MeshMatrixMass for Vec3d: the mass matrix of a mesh, a mass per vertex and a mass per
/// edge (SOFA's consistent mass), or its lumped diagonal (docs/components/matrix_mass_and_rest_springs.md).

#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <optional>
#include <vector>

namespace penalty {

/// MeshMatrixMass<Vec3d>. The elements are the first of hexahedra, tetrahedra, quads, triangles
/// the topology has (MeshMatrixMass::checkTopology). Each element of measure |e| (area or volume)
/// and density ρ gives (MeshMatrixMass::applyVertexMass*Creation, applyEdgeMass*Creation)
///   - each of its vertices ρ|e|/d_v and each of its edges ρ|e|/d_e, with (d_v, d_e) =
///     triangle (6, 12), quad (8, 16), tetrahedron (10, 20), hexahedron (20, 40);
/// M has the block m_v·I₃ on the diagonal of each vertex and m_e·I₃ at both off-diagonal places
/// of each edge: the consistent matrix ∫ρ NᵢNⱼ of linear triangles and tetrahedra, and SOFA's own
/// approximation for quads and hexahedra (no coupling across a face or the body diagonal; row sums
/// and total are exact). Lumped (`lumping`): M = diag(c·m_v) with c = 2 (surfaces) or 2.5
/// (volumes), the row sums of the consistent matrix for triangles and tetrahedra. Gravity is
/// always g·c·m_v (the row sums), lumped or not (MeshMatrixMass::addForce).
///
/// Data by priority (MeshMatrixMass::massInitialization):
///  1. `totalMass` M: masses at ρ = 1 summed to Σ (vertices + 2 × edges, or c × vertices when
///     lumped); ρ = M/Σ (1 when Σ < ε); every mass × ρ;
///  2. `massDensity`: one value, or one per element; totalMass = the sum as above;
///  3. `vertexMass` (one per point) with `edgeMass` (one per edge), or with lumping alone:
///     taken as given; the lumped matrix is then c·vertexMass (SOFA's addMDx), while totalMass is
///     Σ vertexMass (+ Σ edgeMass);
///  4. none: totalMass = 1 kg.
/// SOFA has no element for an edge-only topology (computeMass creates no mass: every mass is 0);
/// `set_edge_elements(true)` (beyond SOFA) gives edges the linear bar's masses, (d_v, d_e) = (3, 6),
/// c = 1.5.
class MeshMatrixMass final : public BaseMass {
public:
    MeshMatrixMass(Vec3Object& state, const MeshTopology& topology) : state_(&state), topology_(&topology) {}

    /// One value (all elements) or one per element (kg/m³ or kg/m²); each finite and >= 0.
    void set_mass_density(std::vector<double> density);
    /// kg; finite and >= 0.
    void set_total_mass(double total);
    /// kg per point; each finite and >= 0 (the count is checked at init).
    void set_vertex_masses(std::vector<double> masses);
    /// kg per edge of the topology; each finite and >= 0.
    void set_edge_masses(std::vector<double> masses);
    void set_lumping(bool lumping) { lumping_ = lumping; }
    /// Measures from the rest positions (SOFA's computeMassOnRest) instead of the positions.
    void set_compute_mass_on_rest(bool on_rest) { on_rest_ = on_rest; }
    /// Beyond SOFA: masses on the edges of an edge-only topology (SOFA gives them none).
    void set_edge_elements(bool on) { edge_elements_ = on; }

    /// Computes the masses (std::invalid_argument: no element, a list of the wrong size, vertexMass
    /// without edgeMass nor lumping, an edge of an element missing from the topology's edges).
    void init() override;

    [[nodiscard]] bool lumping() const { return lumping_; }
    /// c: 2 (triangles, quads), 2.5 (tetrahedra, hexahedra), 1.5 (edges, beyond SOFA); 0 before init.
    [[nodiscard]] double lumping_coefficient() const { return lumping_coefficient_; }
    [[nodiscard]] LumpedElementKind element_kind() const { return kind_; }
    [[nodiscard]] const std::vector<double>& vertex_masses() const { return vertex_masses_; }
    /// One per edge of the topology (empty when lumped).
    [[nodiscard]] const std::vector<double>& edge_masses() const { return edge_masses_; }
    /// ρ per element after init.
    [[nodiscard]] const std::vector<double>& mass_density() const { return density_; }

    void add_gravity_force(const Vec3& gravity) override;
    void add_mdx(double factor) override;
    /// Lumped only: a = f / (c·m_v); the consistent matrix throws std::invalid_argument (SOFA's
    /// accFromF refuses it too; explicit solvers probe it at init).
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const override;
    /// True when apply_inverse works (lumped).
    [[nodiscard]] bool invertible() const { return lumping_; }
    void add_mass_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double kinetic_energy() const override;
    [[nodiscard]] double gravity_potential_energy(const Vec3& gravity) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] const MeshTopology& topology() const { return *topology_; }
    /// From OrderedScatter::kMinElements edges on several threads, add_mdx runs on TBB's threads
    /// with the bits of one thread; its split of the edges as the last of them made it.
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }
    /// SOFA's totalMass after init (and the topological changes since).
    [[nodiscard]] double total_mass() const override { return total_; }
    /// SOFA's topology callbacks of vertexMass and edgeMass, event by event (the .cpp's last part).
    void handle_topology_changes(const class TopologyContainer& container, std::span<const TopologyChange> changes);

private:
    /// MeshMatrixMass::computeMass with the current densities: masses from the elements; returns
    /// the total it accumulates (SOFA's d_totalMass increments).
    double compute_masses();
    /// Element count of the chosen kind.
    [[nodiscard]] std::size_t element_count() const;
    Vec3Object* state_;
    const MeshTopology* topology_;
    /// add_mdx's split of the edges on threads (init and topological changes clear it).
    detail::OrderedScatter scatter_;
    std::optional<std::vector<double>> given_density_;
    std::optional<double> given_total_;
    std::optional<std::vector<double>> given_vertex_masses_;
    std::optional<std::vector<double>> given_edge_masses_;
    bool lumping_ = false;
    bool on_rest_ = false;
    bool edge_elements_ = false;
    LumpedElementKind kind_ = LumpedElementKind::tetrahedron;
    double lumping_coefficient_ = 0.0;
    std::vector<double> density_;
    std::vector<double> vertex_masses_;
    std::vector<double> edge_masses_;
    double total_ = 0.0;
};

}  // namespace penalty
