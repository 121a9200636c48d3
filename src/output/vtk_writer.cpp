#include "penalty/output/vtk_writer.hpp"

#include "output/file_io.hpp"
#include "penalty/core/error.hpp"
#include "penalty/output/format.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace penalty::output {

namespace {

std::string step_suffix(std::size_t step) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "_%06zu", step);
    return buffer;
}

/// Throws NonFiniteValueError unless every component of `v` is finite.
template <class Vector>
void check_finite(const Vector& v, const std::string& what, std::size_t item, const char* item_kind, double time) {
    for (Eigen::Index c = 0; c < v.size(); ++c)
        if (!std::isfinite(v[c]))
            throw NonFiniteValueError(what + ": " + item_kind + " " + std::to_string(item) +
                                      " has a non-finite value (" + format_number(v[c]) + ") at time " +
                                      format_number(time) + " (the simulation diverged)");
}

/// <DataArray ...> with `components` values per tuple, one tuple per line.
class XmlArray {
public:
    XmlArray(std::string& out, const char* type, const char* name, int components)
        : out_(out), components_(components) {
        out_ += "        <DataArray type=\"";
        out_ += type;
        out_ += '"';
        if (name != nullptr) {
            out_ += " Name=\"";
            out_ += name;
            out_ += '"';
        }
        out_ += " NumberOfComponents=\"" + std::to_string(components) + "\" format=\"ascii\">\n";
    }
    ~XmlArray() {
        if (count_ % components_ != 0) out_ += '\n';
        out_ += "        </DataArray>\n";
    }
    XmlArray(const XmlArray&) = delete;
    XmlArray& operator=(const XmlArray&) = delete;

    void add(double value) {
        begin_value();
        append_number(out_, value);
        end_value();
    }
    void add_integer(std::int64_t value) {
        begin_value();
        out_ += std::to_string(value);
        end_value();
    }
    template <class Vector>
    void add_vector(const Vector& v) {
        for (Eigen::Index c = 0; c < v.size(); ++c) add(v[c]);
    }

private:
    void begin_value() { out_ += count_ % components_ == 0 ? "          " : " "; }
    void end_value() {
        if (++count_ % components_ == 0) out_ += '\n';
    }
    std::string& out_;
    int components_;
    std::size_t count_ = 0;
};

void append_header(std::string& out, const char* type) {
    out += "<?xml version=\"1.0\"?>\n<VTKFile type=\"";
    out += type;
    out += "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <";
    out += type;
    out += ">\n";
}

void append_footer(std::string& out, const char* type) {
    out += "  </";
    out += type;
    out += ">\n</VTKFile>\n";
}

void append_time_field(std::string& out, double time) {
    out +=
        "    <FieldData>\n"
        "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">";
    append_number(out, time);
    out += "</DataArray>\n    </FieldData>\n";
}

void append_cells(std::string& out, const VtkCells& cells) {
    out += "      <Cells>\n";
    {
        XmlArray connectivity(out, "Int64", "connectivity", 1);
        for (std::int64_t v : cells.connectivity) connectivity.add_integer(v);
    }
    {
        XmlArray offsets(out, "Int64", "offsets", 1);
        for (std::int64_t v : cells.offsets) offsets.add_integer(v);
    }
    {
        XmlArray types(out, "UInt8", "types", 1);
        for (VtkCellType t : cells.types) types.add_integer(static_cast<std::int64_t>(t));
    }
    out += "      </Cells>\n";
}

/// Point data `radius` of a state covered by a sphere model (nothing when record.radius is empty).
void append_radius(std::string& out, const StateRecord& record, std::size_t n, const std::string& label) {
    if (record.radius.empty()) return;
    if (record.radius.size() != n) throw_invalid_argument(label, ": ", record.radius.size(), " radii for ", n, " DOFs");
    XmlArray radius(out, "Float64", "radius", 1);
    for (double r : record.radius) radius.add(r);
}

/// `<PointData ...>`: velocity is the vector field, radius (when present) the scalar field.
std::string point_data_open(const StateRecord& record) {
    return record.radius.empty() ? "      <PointData Vectors=\"velocity\">\n"
                                 : "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
}

std::string vec3_piece(const StateRecord& record, const Vec3Object& state, double time) {
    const std::string label = "state " + state_label(record);
    for (std::size_t i = 0; i < state.position.size(); ++i)
        check_finite(state.position[i], label + " position", i, "DOF", time);
    for (std::size_t i = 0; i < state.velocity.size(); ++i)
        check_finite(state.velocity[i], label + " velocity", i, "DOF", time);
    const std::size_t n = state.position.size();
    const VtkCells cells = [&] {
        try {
            return vtk_cells(record.topology, n);
        } catch (const std::invalid_argument& error) {
            throw_invalid_argument(label, ": ", error.what());
        }
    }();

    std::string out;
    append_header(out, "UnstructuredGrid");
    append_time_field(out, time);
    out += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" +
           std::to_string(cells.types.size()) + "\">\n";
    out += point_data_open(record);
    {
        XmlArray velocity(out, "Float64", "velocity", 3);
        for (std::size_t i = 0; i < n; ++i)
            velocity.add_vector(i < state.velocity.size() ? state.velocity[i] : Vec3::Zero().eval());
    }
    append_radius(out, record, n, label);
    out += "      </PointData>\n      <Points>\n";
    {
        XmlArray points(out, "Float64", "position", 3);
        for (const Vec3& x : state.position) points.add_vector(x);
    }
    out += "      </Points>\n";
    append_cells(out, cells);
    out += "    </Piece>\n";
    append_footer(out, "UnstructuredGrid");
    return out;
}

std::string rigid_piece(const StateRecord& record, const Rigid3Object& state, double time) {
    const std::string label = "state " + state_label(record);
    const std::size_t n = state.position.size();
    for (std::size_t i = 0; i < n; ++i) {
        check_finite(state.position[i].center, label + " position", i, "DOF", time);
        check_finite(state.position[i].orientation.coeffs(), label + " orientation", i, "DOF", time);
    }
    for (std::size_t i = 0; i < state.velocity.size(); ++i) {
        check_finite(state.velocity[i].linear, label + " velocity", i, "DOF", time);
        check_finite(state.velocity[i].angular, label + " angular velocity", i, "DOF", time);
    }
    const RigidDeriv zero{};
    const auto velocity_of = [&](std::size_t i) -> const RigidDeriv& {
        return i < state.velocity.size() ? state.velocity[i] : zero;
    };
    const VtkCells cells = vtk_cells(nullptr, n);

    std::string out;
    append_header(out, "UnstructuredGrid");
    append_time_field(out, time);
    out += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" + std::to_string(n) + "\">\n";
    out += point_data_open(record);
    {
        XmlArray velocity(out, "Float64", "velocity", 3);
        for (std::size_t i = 0; i < n; ++i) velocity.add_vector(velocity_of(i).linear);
    }
    append_radius(out, record, n, label);
    {
        XmlArray angular(out, "Float64", "angular_velocity", 3);
        for (std::size_t i = 0; i < n; ++i) angular.add_vector(velocity_of(i).angular);
    }
    {
        XmlArray orientation(out, "Float64", "orientation", 4);  // qx qy qz qw
        for (const RigidFrame& frame : state.position) orientation.add_vector(frame.orientation.coeffs());
    }
    const char* axis_names[3] = {"axis_x", "axis_y", "axis_z"};
    for (int axis = 0; axis < 3; ++axis) {
        XmlArray array(out, "Float64", axis_names[axis], 3);
        for (const RigidFrame& frame : state.position) {
            const Vec3 column = frame.orientation.normalized().toRotationMatrix().col(axis);
            array.add_vector(column);
        }
    }
    out += "      </PointData>\n      <Points>\n";
    {
        XmlArray points(out, "Float64", "position", 3);
        for (const RigidFrame& frame : state.position) points.add_vector(frame.center);
    }
    out += "      </Points>\n";
    append_cells(out, cells);
    out += "    </Piece>\n";
    append_footer(out, "UnstructuredGrid");
    return out;
}

struct ExportedContact {
    ContactSegment segment;
    std::int64_t pair;
};

std::string contacts_piece_text(std::span<const ContactRecord> contacts, double time) {
    std::vector<ExportedContact> all;
    for (std::size_t p = 0; p < contacts.size(); ++p) {
        const ContactRecord& record = contacts[p];
        if (record.field == nullptr || record.state1 == nullptr || record.state2 == nullptr)
            throw_invalid_argument("VtkSeriesWriter::write_step: contact record ", p, " ('", record.name,
                                   "') has a null field or state");
        const std::string label = "contacts '" + record.name + "'";
        const std::vector<ContactSegment> segments =
            record.field->export_contacts(record.state1->position, record.state2->position);
        for (std::size_t c = 0; c < segments.size(); ++c) {
            const ContactSegment& s = segments[c];
            check_finite(s.point1, label + " point1", c, "contact", time);
            check_finite(s.point2, label + " point2", c, "contact", time);
            check_finite(s.force, label + " force", c, "contact", time);
            check_finite(s.normal, label + " normal", c, "contact", time);
            check_finite(Eigen::Matrix<double, 1, 1>(s.pen), label + " penetration", c, "contact", time);
            all.push_back({s, static_cast<std::int64_t>(p)});
        }
    }
    const std::size_t n = all.size();
    std::string out;
    append_header(out, "PolyData");
    append_time_field(out, time);
    out += "    <Piece NumberOfPoints=\"" + std::to_string(2 * n) + "\" NumberOfVerts=\"0\" NumberOfLines=\"" +
           std::to_string(n) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
    out += "      <CellData Scalars=\"penetration\" Vectors=\"force\">\n";
    {
        XmlArray force(out, "Float64", "force", 3);
        for (const ExportedContact& c : all) force.add_vector(c.segment.force);
    }
    {
        XmlArray normal(out, "Float64", "normal", 3);
        for (const ExportedContact& c : all) normal.add_vector(c.segment.normal);
    }
    {
        XmlArray penetration(out, "Float64", "penetration", 1);
        for (const ExportedContact& c : all) penetration.add(c.segment.pen);
    }
    {
        XmlArray age(out, "Int32", "age", 1);
        for (const ExportedContact& c : all) age.add_integer(c.segment.age);
    }
    {
        XmlArray pair(out, "Int32", "pair", 1);
        for (const ExportedContact& c : all) pair.add_integer(c.pair);
    }
    {
        XmlArray element1(out, "Int64", "element1", 1);
        for (const ExportedContact& c : all) element1.add_integer(c.segment.index1);
    }
    {
        XmlArray element2(out, "Int64", "element2", 1);
        for (const ExportedContact& c : all) element2.add_integer(c.segment.index2);
    }
    out += "      </CellData>\n      <Points>\n";
    {
        XmlArray points(out, "Float64", "position", 3);
        for (const ExportedContact& c : all) {
            points.add_vector(c.segment.point1);
            points.add_vector(c.segment.point2);
        }
    }
    out += "      </Points>\n      <Lines>\n";
    {
        XmlArray connectivity(out, "Int64", "connectivity", 1);
        for (std::size_t c = 0; c < n; ++c) {
            connectivity.add_integer(static_cast<std::int64_t>(2 * c));
            connectivity.add_integer(static_cast<std::int64_t>(2 * c + 1));
        }
    }
    {
        XmlArray offsets(out, "Int64", "offsets", 1);
        for (std::size_t c = 0; c < n; ++c) offsets.add_integer(static_cast<std::int64_t>(2 * c + 2));
    }
    out += "      </Lines>\n    </Piece>\n";
    append_footer(out, "PolyData");
    return out;
}

constexpr std::string_view kCollectionHeader =
    "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
    "  <Collection>\n";
constexpr std::string_view kCollectionFooter = "  </Collection>\n</VTKFile>\n";

std::string dataset_line(double time, const std::string& file_name) {
    std::string out = "    <DataSet timestep=\"";
    append_number(out, time);
    out += "\" group=\"\" part=\"0\" file=\"" + file_name + "\"/>\n";
    return out;
}

template <class Element>
void append_elements(VtkCells& cells, const std::vector<Element>& elements, VtkCellType type, std::size_t num_points,
                     const char* kind) {
    for (std::size_t e = 0; e < elements.size(); ++e) {
        for (PointId v : elements[e]) {
            if (v < 0 || static_cast<std::size_t>(v) >= num_points)
                throw_invalid_argument("vtk_cells: ", kind, " ", e, " uses point ", v, " but the state has ",
                                       num_points, " points");
            cells.connectivity.push_back(v);
        }
        cells.offsets.push_back(static_cast<std::int64_t>(cells.connectivity.size()));
        cells.types.push_back(type);
    }
}

}  // namespace

VtkCells vtk_cells(const MeshTopology* topology, std::size_t num_points) {
    VtkCells cells;
    if (topology != nullptr) {
        if (!topology->tetrahedra().empty() || !topology->hexahedra().empty()) {
            append_elements(cells, topology->tetrahedra(), VtkCellType::tetra, num_points, "tetrahedron");
            append_elements(cells, topology->hexahedra(), VtkCellType::hexahedron, num_points, "hexahedron");
        } else if (!topology->triangles().empty() || !topology->quads().empty()) {
            append_elements(cells, topology->triangles(), VtkCellType::triangle, num_points, "triangle");
            append_elements(cells, topology->quads(), VtkCellType::quad, num_points, "quad");
        } else {
            append_elements(cells, topology->edges(), VtkCellType::line, num_points, "edge");
        }
    }
    if (cells.types.empty()) {
        for (std::size_t i = 0; i < num_points; ++i) {
            cells.connectivity.push_back(static_cast<std::int64_t>(i));
            cells.offsets.push_back(static_cast<std::int64_t>(i + 1));
            cells.types.push_back(VtkCellType::vertex);
        }
    }
    return cells;
}

/// A .pvd kept valid after every step: the footer is written after each DataSet line and the next
/// line overwrites it, so appending a step costs one line whatever the number of steps.
class VtkSeriesWriter::Collection {
public:
    explicit Collection(std::filesystem::path file)
        : file_(std::move(file)), stream_(detail::open_output_file(file_)), out_(*stream_) {
        out_ << kCollectionHeader;
        footer_position_ = out_.tellp();
        write_footer();
    }
    void append(double time, const std::string& piece_name) {
        out_.seekp(footer_position_);
        out_ << dataset_line(time, piece_name);
        footer_position_ = out_.tellp();
        write_footer();
    }

private:
    void write_footer() {
        out_ << kCollectionFooter;
        out_.flush();
        if (!out_) throw std::runtime_error("cannot write " + detail::quoted(file_));
    }
    std::filesystem::path file_;
    std::unique_ptr<std::ostream> stream_;
    std::ostream& out_;
    std::streampos footer_position_;
};

VtkSeriesWriter::VtkSeriesWriter(std::filesystem::path directory, std::vector<const StateRecord*> states)
    : directory_(std::move(directory)), states_(std::move(states)) {
    for (std::size_t k = 0; k < states_.size(); ++k) {
        if (states_[k] == nullptr || states_[k]->state == nullptr)
            throw_invalid_argument("VtkSeriesWriter: state record ", k, " has no state");
        (void)values_per_dof(*states_[k]->state);  // throws for an unsupported state type
        stems_.push_back(std::to_string(k) + "_" + sanitize_file_name(states_[k]->name));
        state_collections_.push_back(directory_ / (stems_.back() + ".pvd"));
    }
    detail::create_directory(directory_);
    for (const std::filesystem::path& file : state_collections_)
        collections_.push_back(std::make_unique<Collection>(file));
    collections_.push_back(std::make_unique<Collection>(contacts_collection()));
}

VtkSeriesWriter::~VtkSeriesWriter() = default;
VtkSeriesWriter::VtkSeriesWriter(VtkSeriesWriter&&) noexcept = default;
VtkSeriesWriter& VtkSeriesWriter::operator=(VtkSeriesWriter&&) noexcept = default;

std::filesystem::path VtkSeriesWriter::state_piece(std::size_t k, std::size_t step) const {
    return directory_ / (stems_.at(k) + step_suffix(step) + ".vtu");
}

std::filesystem::path VtkSeriesWriter::contacts_piece(std::size_t step) const {
    return directory_ / ("contacts" + step_suffix(step) + ".vtp");
}

void VtkSeriesWriter::write_step(double time, std::span<const ContactRecord> contacts) {
    if (!std::isfinite(time)) throw NonFiniteValueError("VtkSeriesWriter: time is " + format_number(time));
    // Build every file first: a non-finite value throws before anything of this step is written.
    std::vector<std::string> pieces;
    pieces.reserve(states_.size());
    for (const StateRecord* record : states_) {
        if (const auto* vec3 = dynamic_cast<const Vec3Object*>(record->state))
            pieces.push_back(vec3_piece(*record, *vec3, time));
        else pieces.push_back(rigid_piece(*record, dynamic_cast<const Rigid3Object&>(*record->state), time));
    }
    const std::string contacts_text = contacts_piece_text(contacts, time);

    const std::size_t step = times_.size();
    for (std::size_t k = 0; k < states_.size(); ++k) detail::write_file(state_piece(k, step), pieces[k]);
    detail::write_file(contacts_piece(step), contacts_text);
    times_.push_back(time);
    for (std::size_t k = 0; k < states_.size(); ++k)
        collections_[k]->append(time, state_piece(k, step).filename().string());
    collections_.back()->append(time, contacts_piece(step).filename().string());
}

}  // namespace penalty::output
