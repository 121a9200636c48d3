#pragma once
/// @file
/// ParaView time series in VTK XML ASCII format (.vtu / .vtp pieces listed by .pvd collections).
///
/// Files in DIR, step index s counted from 0 by write_step, k the state's index in the writer's
/// list, <name> = sanitize_file_name(record name):
///   <k>_<name>_<s:06>.vtu   UnstructuredGrid of state k at step s
///   <k>_<name>.pvd          Collection of state k's pieces, one DataSet per step
///   contacts_<s:06>.vtp     PolyData of every contact at step s (valid, empty, when none)
///   contacts.pvd            Collection of the contact pieces
/// The .pvd files are created (empty, valid) by the constructor and brought up to date after
/// every step (the closing tags are rewritten after the new DataSet line), so a run killed between
/// steps is still viewable. Every piece carries its time in FieldData `TimeValue`.
/// See docs/output.md for the arrays.
///
/// Vec3 state pieces: points = positions (m); point data `velocity` (m/s, 3 components);
/// cells from the topology, the highest dimension it holds: tetrahedra (VTK_TETRA = 10) and
/// hexahedra (VTK_HEXAHEDRON = 12) if any; else triangles (VTK_TRIANGLE = 5) and quads
/// (VTK_QUAD = 9); else edges (VTK_LINE = 3); else (or without topology) one VTK_VERTEX (1) per
/// point. Lower-dimension elements of a volume mesh are not written: MeshTopology derives them
/// (faces, edges) and they would duplicate the volume's boundary. SOFA's tetrahedron and
/// hexahedron node orders are VTK's (hexahedron: bottom face 0 1 2 3 counter-clockwise seen
/// from the top face 4 5 6 7, vertex 4+j above vertex j), so connectivity is written unchanged.
///
/// Rigid3 state pieces: points = frame centres (m), one VTK_VERTEX per frame; point data
/// `velocity` (linear, m/s), `angular_velocity` (rad/s, world), `orientation` (quaternion
/// qx qy qz qw) and `axis_x`, `axis_y`, `axis_z` (the body axes in world coordinates, unit).
/// Both: point data `radius` (m, the active scalars) when StateRecord::radius is set (a sphere
/// collision model covers the state), for ParaView's Glyph filter (sphere, scale by radius,
/// scale factor 2: the glyph source has radius 0.5).
///
/// Errors: std::runtime_error naming the path on I/O failure; NonFiniteValueError naming the
/// state or contact, the DOF or contact index, and the time, before any file of the step is
/// written; std::invalid_argument for a null state / field, an unsupported state type, a
/// topology element referring to a point the state does not have, or a radius list whose size
/// is not the DOF count.

#include "penalty/output/state_record.hpp"
#include "penalty/response/penalty_force_field.hpp"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace penalty::output {

/// One contact force field with the two (contact-point) states its DOF indices refer to.
struct ContactRecord {
    std::string name;
    const PenaltyForceField* field = nullptr;
    const Vec3Object* state1 = nullptr;
    const Vec3Object* state2 = nullptr;
};

/// VTK cell type numbers used by the writer.
enum class VtkCellType : std::uint8_t {
    vertex = 1,
    line = 3,
    triangle = 5,
    quad = 9,
    tetra = 10,
    hexahedron = 12,
};

class VtkSeriesWriter {
public:
    /// Creates DIR. Throws std::invalid_argument for a null or unsupported state.
    VtkSeriesWriter(std::filesystem::path directory, std::vector<const StateRecord*> states);
    ~VtkSeriesWriter();
    VtkSeriesWriter(VtkSeriesWriter&&) noexcept;
    VtkSeriesWriter& operator=(VtkSeriesWriter&&) noexcept;

    /// Writes one .vtu per state and one contacts .vtp for this step, then rewrites every .pvd.
    /// Contact pieces: for each record (pair index p, in span order), for each contact c of
    /// field->export_contacts(state1->position, state2->position): points point1, point2 and one
    /// VTK_LINE cell point1 -> point2 with cell data force (N, on side 2), normal (side 1 -> 2),
    /// penetration (m, > 0 pushes), age (steps), pair (p), element1, element2.
    void write_step(double time, std::span<const ContactRecord> contacts);

    /// Number of steps written so far (the next step's index).
    [[nodiscard]] std::size_t step_count() const { return times_.size(); }
    [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }
    /// <k>_<name>.pvd of each state, in the writer's order.
    [[nodiscard]] const std::vector<std::filesystem::path>& state_collections() const { return state_collections_; }
    [[nodiscard]] std::filesystem::path contacts_collection() const { return directory_ / "contacts.pvd"; }
    /// The .vtu written for state k at step s (the name, whether or not written yet).
    [[nodiscard]] std::filesystem::path state_piece(std::size_t k, std::size_t step) const;
    /// The .vtp of the contacts at step s.
    [[nodiscard]] std::filesystem::path contacts_piece(std::size_t step) const;

private:
    std::filesystem::path directory_;
    std::vector<const StateRecord*> states_;
    std::vector<std::string> stems_;  ///< <k>_<name>
    std::vector<std::filesystem::path> state_collections_;
    std::vector<double> times_;
    class Collection;
    std::vector<std::unique_ptr<Collection>> collections_;  ///< one per state, then contacts.pvd
};

/// The cells the writer emits for a topology over `num_points` points (rule above):
/// connectivity, offsets (end of each cell in connectivity) and types.
struct VtkCells {
    std::vector<std::int64_t> connectivity;
    std::vector<std::int64_t> offsets;
    std::vector<VtkCellType> types;
};
[[nodiscard]] VtkCells vtk_cells(const MeshTopology* topology, std::size_t num_points);

}  // namespace penalty::output
