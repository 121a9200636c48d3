// XML VTK meshes (.vtu: <VTKFile type="UnstructuredGrid">), read as SOFA's MeshVTKLoader reads
// them (XMLVTKReader::loadUnstructuredGrid, then MeshVTKLoader::doLoad's cell loop): the points of
// each Piece as doubles whatever the DataArray's type (SOFA forces Float64), the cells from the
// connectivity, offsets and types arrays. ASCII DataArrays only.
#include "penalty/io/mesh.hpp"

#include "io/text.hpp"
#include "io/vtk_cells.hpp"

#include <tinyxml2.h>

#include <string>

namespace penalty::io {

using detail::fail;

namespace {

/// The numbers of an ASCII DataArray, at least `expected` of them when `expected` > 0.
std::vector<double> data_array(const tinyxml2::XMLElement& array, const std::filesystem::path& path,
                               std::size_t expected, std::string_view what) {
    const int line = array.GetLineNum();
    const char* format = array.Attribute("format");
    if (format == nullptr) format = array.Attribute("Format");
    if (format == nullptr || std::string_view(format) != "ascii")
        fail(path, line,
             std::string(what) + ": only ASCII DataArrays are read (format=\"" + (format != nullptr ? format : "") +
                 "\")");
    std::vector<double> values;
    const char* text = array.GetText();
    for (std::string_view word : detail::split_blanks(text != nullptr ? text : "")) {
        const auto v = detail::parse_double(word);
        if (!v) fail(path, line, std::string(what) + ": expected a number, found '" + std::string(word) + "'");
        values.push_back(*v);
    }
    if (values.size() < expected)
        fail(path, line,
             std::string(what) + ": expected " + std::to_string(expected) + " numbers, found " +
                 std::to_string(values.size()));
    return values;
}

/// A count or an index read as a double: a non-negative integer below `limit`.
std::int64_t whole(double v, std::int64_t limit, const std::filesystem::path& path, int line, std::string_view what) {
    if (!(v >= 0 && v < double(limit)) || v != double(std::int64_t(v)))
        fail(path, line,
             std::string(what) + " " + std::to_string(v) + " is not an integer in [0, " + std::to_string(limit) + ")");
    return std::int64_t(v);
}

const tinyxml2::XMLElement* named_array(const tinyxml2::XMLElement& parent, std::string_view name) {
    for (const tinyxml2::XMLElement* a = parent.FirstChildElement("DataArray"); a != nullptr;
         a = a->NextSiblingElement("DataArray"))
        if (const char* n = a->Attribute("Name"); n != nullptr && name == n) return a;
    return nullptr;
}

void read_piece(const tinyxml2::XMLElement& piece, const std::filesystem::path& path, MeshData& mesh) {
    const int line = piece.GetLineNum();
    const std::int64_t points = piece.Int64Attribute("NumberOfPoints", -1);
    const std::int64_t cells = piece.Int64Attribute("NumberOfCells", -1);
    if (points < 0 || cells < 0) fail(path, line, "Piece needs NumberOfPoints and NumberOfCells");
    const auto first_point = static_cast<std::int64_t>(mesh.positions.size());
    const tinyxml2::XMLElement* point_node = piece.FirstChildElement("Points");
    const tinyxml2::XMLElement* point_array =
        point_node != nullptr ? point_node->FirstChildElement("DataArray") : nullptr;
    if (point_array == nullptr) fail(path, line, "Piece without Points");
    const std::vector<double> xyz = data_array(*point_array, path, std::size_t(3 * points), "Points");
    for (std::int64_t i = 0; i < points; ++i)
        mesh.positions.emplace_back(xyz[std::size_t(3 * i)], xyz[std::size_t(3 * i + 1)], xyz[std::size_t(3 * i + 2)]);
    if (cells == 0) return;
    const tinyxml2::XMLElement* cell_node = piece.FirstChildElement("Cells");
    if (cell_node == nullptr) fail(path, line, "Piece with cells but no Cells");
    const tinyxml2::XMLElement* connectivity = named_array(*cell_node, "connectivity");
    const tinyxml2::XMLElement* offsets = named_array(*cell_node, "offsets");
    const tinyxml2::XMLElement* types = named_array(*cell_node, "types");
    if (connectivity == nullptr || offsets == nullptr || types == nullptr)
        fail(path, cell_node->GetLineNum(), "Cells needs the DataArrays connectivity, offsets and types");
    const std::vector<double> ids = data_array(*connectivity, path, 0, "connectivity");
    const std::vector<double> ends = data_array(*offsets, path, std::size_t(cells), "offsets");
    const std::vector<double> kinds = data_array(*types, path, std::size_t(cells), "types");
    std::int64_t begin = 0;
    std::vector<PointId> p;
    for (std::int64_t c = 0; c < cells; ++c) {
        const std::int64_t end =
            whole(ends[std::size_t(c)], std::int64_t(ids.size()) + 1, path, offsets->GetLineNum(), "offset");
        if (end < begin) fail(path, offsets->GetLineNum(), "offsets decrease at cell " + std::to_string(c));
        p.clear();
        for (std::int64_t k = begin; k < end; ++k)
            p.push_back(PointId(first_point +
                                whole(ids[std::size_t(k)], points, path, connectivity->GetLineNum(), "point index")));
        const std::int64_t type = whole(kinds[std::size_t(c)], 256, path, types->GetLineNum(), "cell type");
        add_vtk_cell(mesh, type, p, path, connectivity->GetLineNum(), types->GetLineNum());
        begin = end;
    }
}

}  // namespace

MeshData parse_vtk_xml(std::string_view text, const std::filesystem::path& path) {
    tinyxml2::XMLDocument doc(true, tinyxml2::COLLAPSE_WHITESPACE);
    if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
        fail(path, doc.ErrorLineNum(), std::string("XML error: ") + doc.ErrorStr());
    const tinyxml2::XMLElement* root = doc.FirstChildElement("VTKFile");
    if (root == nullptr) fail(path, 1, "not a VTK XML file (no <VTKFile> element)");
    const char* type = root->Attribute("type");
    if (type == nullptr || std::string_view(type) != "UnstructuredGrid")
        fail(
            path, root->GetLineNum(),
            std::string("VTK XML dataset '") + (type != nullptr ? type : "") + "' is not supported (UnstructuredGrid)");
    const tinyxml2::XMLElement* grid = root->FirstChildElement("UnstructuredGrid");
    if (grid == nullptr || grid->FirstChildElement("Piece") == nullptr)
        fail(path, root->GetLineNum(), "no <UnstructuredGrid><Piece>");
    const tinyxml2::XMLElement* piece = grid->FirstChildElement("Piece");
    if (piece->NextSiblingElement("Piece") != nullptr)
        fail(path, piece->NextSiblingElement("Piece")->GetLineNum(),
             "more than one Piece (SOFA keeps only the last one's)");
    MeshData mesh;
    read_piece(*piece, path, mesh);
    if (mesh.positions.empty()) fail(path, grid->GetLineNum(), "no points");
    return mesh;
}

MeshData load_vtk_xml(const std::filesystem::path& path) { return parse_vtk_xml(detail::read_file(path), path); }

MeshData load_vtk(const std::filesystem::path& path) {
    const std::string text = detail::read_file(path);
    const std::string_view start = detail::trim(std::string_view(text).substr(0, text.find('\n')));
    if (start.substr(0, 5) == "<?xml" || start.substr(0, 8) == "<VTKFile") return parse_vtk_xml(text, path);
    return parse_vtk_legacy(text, path);
}

}  // namespace penalty::io
