#pragma once
/// @file
/// The browser viewer of a run (`penalty run --view DIR`, `penalty view DIR`): a page (index.html,
/// viewer.js, the vendored three.js) and the run's data in a compact binary form. The writer
/// observes the run like the VTK writer: the runner calls write_frame between steps.
///
/// Files in DIR (all little-endian; see docs/viewer.md):
///   index.html, viewer.js, three.module.min.js, OrbitControls.js, THREE_LICENSE   the page
///   positions.f32   per frame, per state in the writer's order: Vec3 n·3 floats (x y z, m),
///                   Rigid3 n·7 floats (x y z qx qy qz qw); `frame_floats` floats per frame
///   contacts.f32    per frame, per contact 10 floats: point1 (3, m), point2 (3, m),
///                   normal (3, unit, side 1 → 2), normal force f·n (1, N, > 0 pushes apart)
///   topology.u32    the shapes' element indices (uint32), once
///   crossings.f32   with the tunnelling guard, per frame, per crossing 3 floats: where the
///                   features met (m); made at the first frame with one (docs/no-tunnelling.md)
///   run.json        the manifest: states, shapes, per-frame time, contact count and energies
/// run.json is written by finish() (and by the destructor when finish() was not called, e.g.
/// when the run stopped on divergence), so the frames written so far stay viewable.

#include "penalty/output/state_record.hpp"
#include "penalty/output/vtk_writer.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::output {

namespace detail {
class OutputFolder;
class CreatedFile;
}  // namespace detail

/// How a collision model is drawn.
enum class ViewerShapeKind : std::uint8_t {
    triangles,  ///< indices: 3 per triangle (DOFs of a Vec3 state)
    lines,      ///< indices: 2 per edge
    points,     ///< indices: 1 per point
    spheres,    ///< indices: 1 per sphere (centre DOF, Vec3 or Rigid3 state); radius per sphere
    cylinders,  ///< indices: 1 per cylinder (Rigid3 DOF); radius, height, local axis per cylinder
};

/// "triangles", "lines", "points", "spheres", "cylinders".
[[nodiscard]] const char* viewer_shape_kind_name(ViewerShapeKind kind);

/// One collision model as the viewer draws it.
struct ViewerShape {
    std::string name;  ///< collision model name
    std::string type;  ///< SOFA-like model type ("Triangle", "RigidSphere", ...)
    ViewerShapeKind kind = ViewerShapeKind::points;
    std::size_t state = 0;               ///< index of its state in the writer's state list
    std::vector<std::uint32_t> indices;  ///< DOF indices, see ViewerShapeKind
    std::vector<double> radius;          ///< spheres, cylinders: one per element (m)
    std::vector<double> height;          ///< cylinders: full height (m)
    std::vector<Vec3> axis;              ///< cylinders: unit axis in the body frame
};

class ViewerWriter {
public:
    /// Creates DIR, writes the page files and topology.u32, starts new frame files. No file is
    /// written through a symbolic link: each is created anew and renamed onto its name
    /// (src/output/output_folder.hpp), so a link DIR/index.html -> elsewhere is replaced, and its
    /// target left alone.
    /// Throws std::invalid_argument for a null or unsupported state, a shape whose state index or
    /// DOF index is out of range, or per-element lists of the wrong size; std::runtime_error
    /// naming the path on I/O failure.
    ViewerWriter(std::filesystem::path directory, std::vector<const StateRecord*> states,
                 std::vector<ViewerShape> shapes, std::string title);
    /// Writes run.json if finish() was not called (errors are swallowed).
    ~ViewerWriter();
    ViewerWriter(const ViewerWriter&) = delete;
    ViewerWriter& operator=(const ViewerWriter&) = delete;

    /// Appends one frame: every state's positions and every contact segment of `contacts`, with
    /// the frame's statistics (time in s, kinetic energy in J; contact count, maximum
    /// penetration, stored and dissipated energy from the contacts as stats_csv.hpp computes
    /// them). A non-finite position or contact value throws NonFiniteValueError naming the state
    /// or contact and the time, and nothing of the frame is written. A non-finite kinetic energy
    /// (finite but huge velocities, the step before the runner reports divergence) is written as
    /// null in run.json.
    /// `crossings`: the tunnelling guard's crossings of the step that ended at `time` (where the
    /// features met), drawn as markers; run.json's frames gain a `crossings` count column once
    /// a frame has one.
    void write_frame(double time, std::span<const ContactRecord> contacts, double kinetic_energy,
                     std::span<const Vec3> crossings = {});

    /// Topological changes (docs/topological-changes.md): `revision` tells when the elements may
    /// have changed (a number that changes with them), `shapes` gives the shapes then. A frame
    /// whose revision or state sizes differ from the previous frame's starts a new layout: its
    /// shapes' indices are appended to topology.u32 and run.json lists the layouts and, per frame,
    /// its layout and the offset of its positions (format version 2; a run with one layout keeps
    /// version 1's files).
    void follow_topology(std::function<std::uint64_t()> revision, std::function<std::vector<ViewerShape>()> shapes);

    /// Writes run.json (may be called again after more frames).
    void finish();

    [[nodiscard]] std::size_t frame_count() const { return frames_.size(); }
    [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }
    /// Floats per frame in positions.f32 (Σ 3·n Vec3, 7·n Rigid3), of the first layout.
    [[nodiscard]] std::size_t frame_floats() const { return frame_floats_; }
    /// Layouts written so far (1 unless the elements or the state sizes changed).
    [[nodiscard]] std::size_t layout_count() const { return layouts_.size(); }

    /// Floats per contact in contacts.f32.
    static constexpr std::size_t kContactFloats = 10;

private:
    /// The states' sizes and the shapes' elements of a run of frames.
    struct Layout {
        std::vector<std::size_t> dofs;           ///< per state
        std::vector<std::size_t> state_offsets;  ///< first float of each state in a frame
        std::size_t floats = 0;                  ///< floats per frame
        std::vector<ViewerShape> shapes;         ///< indices dropped once written
        std::vector<std::size_t> index_offsets;  ///< first index of each shape in topology.u32
        std::vector<std::size_t> index_counts;
        std::uint64_t revision = 0;
    };
    /// Checks `shapes` against the state sizes `dofs` (throws std::invalid_argument) and returns
    /// the layout; its indices are appended to `topology` (uint32 bytes).
    [[nodiscard]] Layout make_layout(std::vector<ViewerShape> shapes, std::vector<std::size_t> dofs,
                                     std::uint64_t revision, std::string& topology) const;
    /// Appends `topology` to topology.u32 and the layout to the list.
    void append_layout(Layout layout, const std::string& topology);
    struct FrameStats {
        double time = 0.0;
        std::size_t layout = 0;
        std::size_t position_offset = 0;  ///< floats before this frame in positions.f32
        std::size_t contacts = 0;
        std::size_t active_contacts = 0;
        double max_penetration = 0.0;
        double contact_energy = 0.0;
        double kinetic_energy = 0.0;
        double dissipated_energy = 0.0;
        std::size_t crossings = 0;
    };
    std::filesystem::path directory_;
    std::vector<const StateRecord*> states_;
    std::string title_;
    std::size_t frame_floats_ = 0;
    std::vector<Layout> layouts_;
    std::size_t topology_size_ = 0;   ///< indices in topology.u32
    std::size_t positions_size_ = 0;  ///< floats in positions.f32
    std::function<std::uint64_t()> revision_;
    std::function<std::vector<ViewerShape>()> reshape_;
    std::vector<FrameStats> frames_;
    double max_normal_force_ = 0.0;
    std::unique_ptr<detail::OutputFolder> folder_;
    std::unique_ptr<detail::CreatedFile> topology_;
    std::unique_ptr<detail::CreatedFile> positions_;
    std::unique_ptr<detail::CreatedFile> contacts_;
    std::unique_ptr<detail::CreatedFile> crossings_;  ///< created at the first frame with a crossing
    std::vector<float> buffer_;
    bool finished_ = false;
};

/// The page files the writer puts in DIR (name, content), embedded in the library at build time
/// from viewer/ in the source tree.
struct ViewerAsset {
    const char* name;
    std::string_view content;
};
[[nodiscard]] std::span<const ViewerAsset> viewer_assets();

/// Writes the page files (viewer_assets()) into DIR, creating it; the data files are untouched
/// (`penalty view DIR` refreshes the page of a run written by an older binary). Each file is
/// written beside and renamed onto its name: never through a link, never seen half-written.
void write_viewer_page(const std::filesystem::path& directory);

}  // namespace penalty::output
