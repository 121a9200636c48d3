#pragma once
/// @file
/// SOFA's pressure loads on the elements of a topology (Sofa.Component.MechanicalLoad), on a Vec3
/// state. docs/components/pressure_loads.md gives each formula with its SOFA source.
///
///  - TrianglePressureForceField: a pressure VECTOR P (N/m², a force per unit area, not along the
///    normal) on a list of triangles. Constant mode (useConstantForce, SOFA's default): per
///    triangle F = P·A₀ with A₀ = ½|(b⁰−a⁰)×(c⁰−a⁰)| the REST area, F/3 on each corner
///    (initTriangleInformation, addForce). Otherwise F = σ·((b−a)×(c−a))/6 on EACH corner, σ the
///    symmetric Cauchy stress, current positions. SOFA's addDForce adds nothing in both modes,
///    so K = 0 (a quirk in the second mode, where f depends on x).
///  - QuadPressureForceField: a pressure vector P (N/m²) on a list of quads (a, b, c, d): per quad
///    F = P·A₀ with A₀ = ½|(b⁰−a⁰)×(c⁰−a⁰)| + ½|(c⁰−a⁰)×(d⁰−a⁰)| the REST area (geometry::Quad::area:
///    the triangles (a, b, c) and (a, c, d)), F/4 on each corner (initQuadInformation, addForce);
///    K = 0 (addDForce adds nothing; the force does not depend on x).
///  - EdgePressureForceField: a pressure vector P (N/m) on a list of edges: per edge F = P·L₀
///    (rest length), F/2 on each end (initEdgeInformation, addForce); K = 0.
///  - SurfacePressureForceField: a scalar pressure p (Pa) along the normals of a closed surface:
///    per triangle (a, b, c) f = p/6·(b−a)×(c−a) on EACH corner (so Σ = p·area·n);
///    per quad (a, b, c, d) f₁ = p/6·(b−a)×(c−a), f₂ = p/6·(c−a)×(d−a), a and c get f₁ + f₂, b f₁,
///    d f₂ (addTriangleSurfacePressure, addQuadSurfacePressure). Tangent stiffness of the
///    triangle term only (non-symmetric; the quads and the mainDirection factor have none).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/mechanics/topology_change.hpp"

#include <optional>
#include <vector>

namespace penalty {

// ---- TrianglePressureForceField ------------------------------------------------------------
class TrianglePressureForceField final : public ForceField<Vec3Types> {
public:
    /// `triangles`: indices into topology.triangles(). `pressure`: N/m² (a vector).
    TrianglePressureForceField(Vec3Object& state, const MeshTopology& topology, std::vector<Index> triangles,
                               const Vec3& pressure);
    /// Constant mode (default true): F = P·A₀; false: F = σ·(b−a)×(c−a)/6 per corner.
    void set_use_constant_force(bool constant) { use_constant_force_ = constant; }
    /// σ (Pa), symmetric; used only when the force is not constant.
    void set_cauchy_stress(const Mat3& stress) { cauchy_stress_ = stress; }

    /// Rest areas and per-triangle forces from the state's rest positions (SOFA's init).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    /// K = 0 (SOFA's addDForce adds nothing).
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// Constant mode: −Σ f_i·x_i (the potential of a constant force) at the last add_force; else 0.
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const std::vector<Index>& triangles() const { return triangles_; }
    [[nodiscard]] const Vec3& pressure() const { return pressure_; }
    [[nodiscard]] bool use_constant_force() const { return use_constant_force_; }
    /// Σ A₀ of the selected triangles (m²), after init().
    [[nodiscard]] double total_rest_area() const;
    /// SOFA's TriangleSubsetData trianglePressureMap (src/mechanics/topology/pressure_changes.cpp):
    /// a removed triangle's entry leaves the list (the others keep their order, area and force);
    /// entries naming the topology's last triangle take the removed one's index, the last
    /// triangle being the count at init (plus the triangles added since) minus the triangles
    /// removed before it in this event; new triangles are not added.
    void handle_topology_changes(const class TopologyContainer& container, std::span<const TopologyChange> changes);
    /// SofaQuirkFixes::fix_subset_data_last_index: a removal renames the entries of the topology's
    /// current last element (as TopologySubsetIndices does), not those of SOFA's stale last index.
    void set_current_last_index(bool current) { current_last_index_ = current; }
    /// The entries naming an element past the topology's end, which SOFA's stale last index can
    /// leave (SOFA HEAD then reads past the topology and crashes): dropped, with their data.
    /// Returns how many.
    std::size_t drop_entries_past_end();

private:
    const MeshTopology* topology_;
    Index subset_last_ = -1;  ///< the TriangleSubsetData's last element index (init: count − 1)
    bool current_last_index_ = false;
    std::vector<Index> triangles_;
    Vec3 pressure_;
    bool use_constant_force_ = true;
    Mat3 cauchy_stress_ = Mat3::Zero();
    std::vector<double> rest_areas_;
    std::vector<Vec3> forces_;  ///< P·A₀ per triangle
    double energy_ = 0.0;
};

// ---- QuadPressureForceField ----------------------------------------------------------------
class QuadPressureForceField final : public ForceField<Vec3Types> {
public:
    /// `quads`: indices into topology.quads(). `pressure`: N/m² (a vector).
    QuadPressureForceField(Vec3Object& state, const MeshTopology& topology, std::vector<Index> quads,
                           const Vec3& pressure);
    /// Rest areas and per-quad forces from the state's rest positions (SOFA's init).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    /// K = 0 (constant force).
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// −Σ f_i·x_i (the potential of a constant force) at the last add_force.
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const std::vector<Index>& quads() const { return quads_; }
    [[nodiscard]] const Vec3& pressure() const { return pressure_; }
    /// Σ A₀ of the selected quads (m²), after init().
    [[nodiscard]] double total_rest_area() const;
    /// SOFA's QuadSubsetData quadPressureMap, as TrianglePressureForceField's trianglePressureMap
    /// (src/mechanics/topology/pressure_changes.cpp).
    void handle_topology_changes(const class TopologyContainer& container, std::span<const TopologyChange> changes);
    /// SofaQuirkFixes::fix_subset_data_last_index: a removal renames the entries of the topology's
    /// current last element (as TopologySubsetIndices does), not those of SOFA's stale last index.
    void set_current_last_index(bool current) { current_last_index_ = current; }
    /// The entries naming an element past the topology's end, which SOFA's stale last index can
    /// leave (SOFA HEAD then reads past the topology and crashes): dropped, with their data.
    /// Returns how many.
    std::size_t drop_entries_past_end();

private:
    const MeshTopology* topology_;
    Index subset_last_ = -1;  ///< the QuadSubsetData's last element index (init: count − 1)
    bool current_last_index_ = false;
    std::vector<Index> quads_;
    Vec3 pressure_;
    std::vector<double> rest_areas_;
    std::vector<Vec3> forces_;  ///< P·A₀ per quad
    double energy_ = 0.0;
};

/// SOFA's QuadPressureForceField::selectQuadsAlongPlane: the quads (indices, increasing) whose four
/// points p satisfy dmin < p·normal < dmax (strict; `normal` not normalised).
[[nodiscard]] std::vector<Index> quads_between_planes(const MeshTopology& topology, std::span<const Vec3> points,
                                                      const Vec3& normal, double dmin, double dmax);

// ---- EdgePressureForceField ----------------------------------------------------------------
class EdgePressureForceField final : public ForceField<Vec3Types> {
public:
    /// `edges`: indices into topology.edges(). `pressure`: N/m (a vector), non-zero.
    EdgePressureForceField(Vec3Object& state, const MeshTopology& topology, std::vector<Index> edges,
                           const Vec3& pressure);
    /// Rest lengths and per-edge forces from the state's rest positions (SOFA's init).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    /// K = 0 (constant force).
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// −Σ f_i·x_i at the last add_force.
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const std::vector<Index>& edges() const { return edges_; }
    [[nodiscard]] const Vec3& pressure() const { return pressure_; }
    /// SOFA's EdgeSubsetData edgePressureMap (src/mechanics/topology/pressure_changes.cpp): a
    /// removed edge leaves the list; entries naming the last edge take its index, the last edge
    /// being the count at construction minus the edges removed in this event (SOFA does not carry
    /// the count over from one removal to the next); the forces follow (P·L₀ of each edge, as
    /// addForce's initEdgeInformation computes them at every step).
    void handle_topology_changes(const class TopologyContainer& container, std::span<const TopologyChange> changes);
    /// Once the change is complete: the forces of the edges now listed.
    void topology_change_done();
    /// SofaQuirkFixes::fix_subset_data_last_index: a removal renames the entries of the topology's
    /// current last element (as TopologySubsetIndices does), not those of SOFA's stale last index.
    void set_current_last_index(bool current) { current_last_index_ = current; }
    /// The entries naming an element past the topology's end, which SOFA's stale last index can
    /// leave (SOFA HEAD then reads past the topology and crashes): dropped, with their data.
    /// Returns how many.
    std::size_t drop_entries_past_end();
    /// Σ L₀ of the selected edges (m), after init().
    [[nodiscard]] double total_rest_length() const;

private:
    const MeshTopology* topology_;
    std::vector<Index> edges_;
    Vec3 pressure_;
    std::vector<double> rest_lengths_;
    std::vector<Vec3> forces_;  ///< P·L₀ per edge
    double energy_ = 0.0;
    Index subset_last_ = -2;  ///< the EdgeSubsetData's last element index (-2: not set yet)
    bool current_last_index_ = false;
    bool pending_init_ = false;
};

/// SOFA's EdgePressureForceField::selectEdgesAlongPlane: the edges (indices, increasing) whose two
/// ends p satisfy dmin < p·normal < dmax (strict; `normal` not normalised).
[[nodiscard]] std::vector<Index> edges_between_planes(const MeshTopology& topology, std::span<const Vec3> points,
                                                      const Vec3& normal, double dmin, double dmax);

/// SOFA's EdgePressureForceField::selectEdgesFromEdgeList: for each given edge, the index of the
/// LAST topology edge with the same ends in the same order; 0 when there is none (as SOFA).
[[nodiscard]] std::vector<Index> edge_indices_of(const MeshTopology& topology, std::span<const Edge> edges);

// ---- SurfacePressureForceField -------------------------------------------------------------
struct SurfacePressureParameters {
    double pressure = 0.0;              ///< p (Pa); > 0 pushes along (b−a)×(c−a)
    bool pulse_mode = false;            ///< p ramps between the bounds at pressure_speed
    double pressure_lower_bound = 0.0;  ///< Pa (pulse mode)
    double pressure_speed = 0.0;        ///< Pa/s (pulse mode; 0 → |pressure|, as SOFA's init)
    bool volume_conservation = false;   ///< p·V_default/V (V from the surface, divergence theorem)
    bool use_tangent_stiffness = true;
    double default_volume = -1.0;        ///< m³; −1: the volume at the first add_force
    Vec3 main_direction = Vec3::Zero();  ///< ≠ 0: each triangle's force times |n̂·d|
    std::optional<Vec3> box_min;         ///< selection box (both unset or both zero: everything)
    std::optional<Vec3> box_max;
    std::vector<Index> triangle_indices;  ///< given: these triangles, no box test
    std::vector<Index> quad_indices;      ///< given: these quads, no box test
};

class SurfacePressureForceField final : public ForceField<Vec3Types> {
public:
    /// `dt`: the scene's time step (s), for the pulse mode's ramp.
    SurfacePressureForceField(Vec3Object& state, const MeshTopology& topology, SurfacePressureParameters parameters,
                              double dt);
    void init() override;
    /// Advances the pulse-mode pressure (once per call, as SOFA's addForce: one call per step).
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    /// The triangle term's derivative at the last add_force (p held fixed), when
    /// use_tangent_stiffness.
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// −p·V at the last add_force (the potential of a constant pressure on a closed surface with
    /// no quads, no box and no mainDirection); diagnostic otherwise.
    [[nodiscard]] double potential_energy() const override { return energy_; }

    [[nodiscard]] const SurfacePressureParameters& parameters() const { return params_; }
    /// p applied at the last add_force (Pa).
    [[nodiscard]] double last_pressure() const { return last_pressure_; }
    /// (1/6)·Σ (a×b)·c over the triangles and the quads' two triangles (m³): SOFA's computeMeshVolume.
    [[nodiscard]] double mesh_volume(std::span<const Vec3> x) const;
    /// After a topological change: SOFA's addForce reads the topology's current triangles and
    /// quads (no topology data); the tangent stiffness of the last add_force, on elements that may
    /// be gone, is dropped until the next add_force. triangleIndices and quadIndices are plain Data
    /// in SOFA (no TopologySubsetData): they stay as given, each index naming the element now in
    /// that slot (after a swap-and-pop, the moved last element). An index past the topology's end
    /// (SOFA's getTriangle / getQuad return InvalidID and addForce reads x[InvalidID]: SOFA HEAD
    /// crashes) presses nothing until an addition brings its slot back. Returns how many listed
    /// indices are past the end now.
    std::size_t topology_changed();

private:
    bool in_box(const Vec3& p) const;
    double next_pulse_pressure();

    const MeshTopology* topology_;
    SurfacePressureParameters params_;
    double dt_;
    bool increasing_ = true;
    double pulse_pressure_ = 0.0;
    double last_pressure_ = 0.0;
    double energy_ = 0.0;
    /// Triangles pressed at the last add_force with p/6 (their tangent stiffness).
    std::vector<Index> pressed_triangles_;
    double stiffness_scale_ = 0.0;  ///< p/6 of the last add_force
    std::vector<Vec3> last_x_;
};

}  // namespace penalty
