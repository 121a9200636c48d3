#include "penalty/io/mesh.hpp"

#include "io/text.hpp"
#include "io/vtk_cells.hpp"
#include "penalty/core/vertex_list_hash.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace penalty::io {

using detail::fail;
using detail::parse_double;
using detail::parse_int;
using detail::quoted;
using detail::Token;
using detail::Tokenizer;

namespace {

constexpr std::int64_t kMaxPointId = std::numeric_limits<PointId>::max();

std::string tok_text_of(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

// ---------------------------------------------------------------------------------------------
// OBJ

struct ObjRecord {
    std::vector<std::int64_t> nodes;
    /// (texture coordinate, normal) index of each corner, 0-based, −1 when absent (handleSeams)
    std::vector<std::pair<std::int64_t, std::int64_t>> attributes;
    int line = 0;
};

/// The `vt` or `vn` index of an OBJ corner field (1-based, negative: relative to the `count`
/// defined so far); −1 when empty, zero or not a number, as SOFA's MeshOBJLoader::readOBJ.
std::int64_t obj_attribute_index(std::string_view field, std::int64_t count) {
    if (field.empty()) return -1;
    const auto index = parse_int(field);
    if (!index || *index == 0) return -1;
    return *index > 0 ? *index - 1 : count + *index;
}

}  // namespace

MeshData load_obj(const std::filesystem::path& path, bool triangulate, bool handle_seams) {
    return parse_obj(detail::read_file(path), path, triangulate, handle_seams);
}

MeshData parse_obj(std::string_view text, const std::filesystem::path& path, bool triangulate, bool handle_seams) {
    text = detail::skip_byte_order_mark(text);
    MeshData mesh;
    std::vector<ObjRecord> records;
    std::int64_t texture_coordinates = 0, normals = 0;  // vt and vn lines so far

    std::size_t pos = 0;
    int line_number = 0;
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find('\n', pos), text.size());
        const std::string_view line(text.data() + pos, end - pos);
        pos = end + 1;
        ++line_number;
        const auto tokens = detail::split_blanks(line);
        if (tokens.empty()) continue;
        const std::string_view key = tokens[0];
        if (key == "v") {
            if (tokens.size() < 4) {
                fail(path, line_number, "vertex needs 3 coordinates, found " + std::to_string(tokens.size() - 1));
            }
            Vec3 p;
            for (int k = 0; k < 3; ++k) {
                const auto value = parse_double(tokens[static_cast<std::size_t>(k) + 1]);
                if (!value) {
                    fail(path, line_number,
                         "expected a vertex coordinate (a number), found " +
                             quoted(tokens[static_cast<std::size_t>(k) + 1]));
                }
                if (const auto problem = detail::magnitude_problem(*value))
                    fail(path, line_number,
                         "vertex coordinate " + quoted(tokens[static_cast<std::size_t>(k) + 1]) + ": " + *problem);
                p[k] = *value;
            }
            mesh.positions.push_back(p);
        } else if (key == "vt") {
            ++texture_coordinates;
        } else if (key == "vn") {
            ++normals;
        } else if (key == "f" || key == "l") {
            ObjRecord record;
            record.line = line_number;
            for (std::size_t t = 1; t < tokens.size(); ++t) {
                const std::string_view token = tokens[t];
                const std::string_view first = token.substr(0, token.find('/'));
                const auto index = parse_int(first);
                if (!index) fail(path, line_number, "expected a vertex index, found " + quoted(token));
                if (*index == 0) fail(path, line_number, "vertex index 0 is invalid (OBJ indices start at 1)");
                // positive: 1-based; negative: relative to the points defined so far
                const std::int64_t resolved =
                    *index > 0 ? *index - 1 : static_cast<std::int64_t>(mesh.positions.size()) + *index;
                if (resolved < 0) {
                    fail(path, line_number,
                         "relative vertex index " + std::to_string(*index) + " goes before the first vertex");
                }
                record.nodes.push_back(resolved);
                if (handle_seams) {
                    const std::size_t slash = token.find('/');
                    const std::string_view rest =
                        slash == std::string_view::npos ? std::string_view() : token.substr(slash + 1);
                    const std::size_t slash2 = rest.find('/');
                    const std::string_view normal =
                        slash2 == std::string_view::npos ? std::string_view() : rest.substr(slash2 + 1);
                    record.attributes.emplace_back(obj_attribute_index(rest.substr(0, slash2), texture_coordinates),
                                                   obj_attribute_index(normal.substr(0, normal.find('/')), normals));
                }
            }
            if (record.nodes.size() < 2) {
                fail(path, line_number,
                     std::string(key == "f" ? "face" : "line") + " needs at least 2 vertices, found " +
                         std::to_string(record.nodes.size()));
            }
            records.push_back(std::move(record));
        }
        // comments, vn, vt, g, o, s, usemtl, mtllib and unknown keywords are ignored
    }

    if (mesh.positions.empty()) fail(path, 0, "no vertices (an empty file, or not a Wavefront OBJ file: no 'v' line)");
    // indices may refer to points defined later in the file (SOFA resolves them at the end)
    const auto n = static_cast<std::int64_t>(mesh.positions.size());
    for (const ObjRecord& r : records) {
        for (const std::int64_t v : r.nodes) {
            if (v >= n || v > kMaxPointId) {
                fail(path, r.line,
                     "vertex index " + std::to_string(v + 1) + " out of range (" + std::to_string(n) + " vertices)");
            }
        }
    }
    if (handle_seams) {
        // MeshOBJLoader::readOBJ with handleSeams: point i becomes one vertex per distinct
        // (texture coordinate, normal) pair its corners use, in increasing pair order; points no
        // face or line uses are dropped. Elements are renumbered accordingly.
        std::vector<std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t>> split(mesh.positions.size());
        for (const ObjRecord& r : records)
            for (std::size_t k = 0; k < r.nodes.size(); ++k) split[std::size_t(r.nodes[k])][r.attributes[k]] = 0;
        std::vector<Vec3> positions;
        for (std::size_t i = 0; i < split.size(); ++i)
            for (auto& [pair, id] : split[i]) {
                id = static_cast<std::int64_t>(positions.size());
                positions.push_back(mesh.positions[i]);
            }
        if (positions.size() > std::size_t(kMaxPointId)) fail(path, 0, "too many vertices after splitting the seams");
        for (ObjRecord& r : records)
            for (std::size_t k = 0; k < r.nodes.size(); ++k)
                r.nodes[k] = split[std::size_t(r.nodes[k])].at(r.attributes[k]);
        mesh.positions = std::move(positions);
    }
    for (const ObjRecord& r : records) {
        const auto id = [&](std::size_t k) { return static_cast<PointId>(r.nodes[k]); };
        if (r.nodes.size() == 2) {
            mesh.edges.push_back(Edge{std::min(id(0), id(1)), std::max(id(0), id(1))});
        } else if (r.nodes.size() == 4 && !triangulate) {
            mesh.quads.push_back(Quad{id(0), id(1), id(2), id(3)});
        } else {
            for (std::size_t j = 2; j < r.nodes.size(); ++j) {
                mesh.triangles.push_back(Triangle{id(0), id(j - 1), id(j)});
            }
        }
    }
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// SPH

MeshData load_sph(const std::filesystem::path& path) { return parse_sph(detail::read_file(path), path); }

MeshData parse_sph(std::string_view text, const std::filesystem::path& path) {
    Tokenizer tok(text, path);
    MeshData mesh;
    const auto header = tok.next();
    if (!header || header->text != "sph") {
        fail(path, header ? header->line : 1, "not a sphere file (first line must be 'sph 1.0')");
    }
    (void)tok.rest_of_line();
    while (auto key = tok.next()) {
        if (key->text == "nums") {
            const std::int64_t total = tok.expect_int("sphere count");
            tok.check_count(total, 6, "sphere");
            mesh.positions.reserve(static_cast<std::size_t>(total));
            mesh.radii.reserve(static_cast<std::size_t>(total));
        } else if (key->text == "sphe") {
            (void)tok.expect_int("sphere index");
            Vec3 c;
            for (int k = 0; k < 3; ++k) c[k] = tok.expect_double("sphere center coordinate");
            const double r = tok.expect_double("sphere radius");
            if (r < 0.0) fail(path, tok.line(), "negative sphere radius " + std::string(tok_text_of(r)));
            mesh.positions.push_back(c);
            mesh.radii.push_back(r);
        } else if (key->text.front() == '#') {
            (void)tok.rest_of_line();
        } else {
            (void)tok.rest_of_line();  // SOFA: unknown keyword, skip its line
        }
    }
    if (mesh.positions.empty()) fail(path, 0, "no spheres (no 'sphe' line)");
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// legacy VTK

namespace {

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

PointId vtk_index(Tokenizer& tok, std::int64_t npoints) {
    const std::int64_t v = tok.expect_int("point index");
    if (v < 0 || v >= npoints) {
        fail(tok.path(), tok.line(),
             "point index " + std::to_string(v) + " out of range (" + std::to_string(npoints) + " points)");
    }
    return static_cast<PointId>(v);
}

void add_polygon(MeshData& mesh, const std::vector<PointId>& p) {
    if (p.size() == 3) {
        mesh.triangles.push_back(Triangle{p[0], p[1], p[2]});
    } else if (p.size() == 4) {
        mesh.quads.push_back(Quad{p[0], p[1], p[2], p[3]});
    } else {
        for (std::size_t j = 2; j < p.size(); ++j) mesh.triangles.push_back(Triangle{p[0], p[j - 1], p[j]});
    }
}

}  // namespace

void add_vtk_cell(MeshData& mesh, std::int64_t type, const std::vector<PointId>& p, const std::filesystem::path& path,
                  int cell_line, int type_line) {
    const auto need = [&](std::size_t count) {
        if (p.size() != count) {
            fail(path, cell_line,
                 "cell of type " + std::to_string(type) + " needs " + std::to_string(count) + " points, found " +
                     std::to_string(p.size()));
        }
    };
    switch (type) {
        case 1:
            break;  // vertex
        case 3:
            need(2);
            mesh.edges.push_back(Edge{p[0], p[1]});
            break;
        case 4:
            for (std::size_t j = 1; j < p.size(); ++j) mesh.edges.push_back(Edge{p[j - 1], p[j]});
            break;
        case 5:
            need(3);
            mesh.triangles.push_back(Triangle{p[0], p[1], p[2]});
            break;
        case 7:
            if (p.size() < 3) fail(path, cell_line, "polygon with fewer than 3 points");
            add_polygon(mesh, p);
            break;
        case 8:
            need(4);
            mesh.quads.push_back(Quad{p[0], p[1], p[3], p[2]});
            break;
        case 9:
            need(4);
            mesh.quads.push_back(Quad{p[0], p[1], p[2], p[3]});
            break;
        case 10:
            need(4);
            mesh.tetrahedra.push_back(Tetrahedron{p[0], p[1], p[2], p[3]});
            break;
        case 11:
            need(8);
            mesh.hexahedra.push_back(Hexahedron{p[0], p[1], p[3], p[2], p[4], p[5], p[7], p[6]});
            break;
        case 12:
            need(8);
            mesh.hexahedra.push_back(Hexahedron{p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]});
            break;
        default:
            fail(path, type_line, "VTK cell type " + std::to_string(type) + " is not supported");
    }
}

MeshData load_vtk_legacy(const std::filesystem::path& path) { return parse_vtk_legacy(detail::read_file(path), path); }

MeshData parse_vtk_legacy(std::string_view text, const std::filesystem::path& path) {
    Tokenizer tok(text, path);
    MeshData mesh;

    const std::string_view magic = tok.rest_of_line();
    if (magic.substr(0, 5) != "# vtk") fail(path, 1, "not a legacy VTK file (first line must start with '# vtk')");
    (void)tok.rest_of_line();  // title
    const std::string format = upper(tok.rest_of_line());
    if (format != "ASCII") fail(path, 3, "only ASCII legacy VTK files are supported, found '" + format + "'");
    const Token dataset = tok.expect("DATASET");
    if (upper(dataset.text) != "DATASET") fail(path, dataset.line, "expected DATASET, found " + quoted(dataset.text));
    const Token kind = tok.expect("dataset type");
    const std::string kind_name = upper(kind.text);
    const bool polydata = kind_name == "POLYDATA";
    if (!polydata && kind_name != "UNSTRUCTURED_GRID") {
        fail(path, kind.line,
             "VTK dataset " + std::string(kind.text) + " is not supported (POLYDATA or UNSTRUCTURED_GRID)");
    }

    std::int64_t npoints = -1;
    std::vector<std::vector<PointId>> cells;
    std::vector<int> cell_lines;
    bool have_types = false;
    while (auto section = tok.next()) {
        const std::string name = upper(section->text);
        if (name == "POINTS") {
            npoints = tok.expect_int("number of points");
            tok.check_count(npoints, 3, "point");
            (void)tok.expect("point data type");
            mesh.positions.reserve(static_cast<std::size_t>(npoints));
            for (std::int64_t i = 0; i < npoints; ++i) {
                Vec3 p;
                for (int k = 0; k < 3; ++k) p[k] = tok.expect_double("point coordinate");
                mesh.positions.push_back(p);
            }
        } else if (name == "POLYGONS" || name == "LINES" || name == "VERTICES" || name == "CELLS" ||
                   name == "TRIANGLE_STRIPS") {
            if (npoints < 0) fail(path, section->line, name + " before POINTS");
            if (name == "TRIANGLE_STRIPS") fail(path, section->line, "TRIANGLE_STRIPS are not supported");
            if (name == "CELLS" && polydata) fail(path, section->line, "CELLS in a POLYDATA dataset");
            if (name != "CELLS" && !polydata) fail(path, section->line, name + " in an UNSTRUCTURED_GRID dataset");
            const std::int64_t n = tok.expect_int("number of cells");
            const std::int64_t size = tok.expect_int("cell list size");
            tok.check_count(size, 1, "cell list size");
            tok.check_count(n, 2, name + " cell");
            std::int64_t read = 0;
            std::vector<PointId> p;
            for (std::int64_t c = 0; c < n; ++c) {
                const std::int64_t k = tok.expect_int("cell point count");
                const int line = tok.line();
                if (k < 0 || k > size) fail(path, line, "bad cell point count " + std::to_string(k));
                p.clear();
                for (std::int64_t j = 0; j < k; ++j) p.push_back(vtk_index(tok, npoints));
                read += k + 1;
                if (name == "LINES") {
                    for (std::size_t j = 1; j < p.size(); ++j) mesh.edges.push_back(Edge{p[j - 1], p[j]});
                } else if (name == "POLYGONS") {
                    if (p.size() < 3) fail(path, line, "polygon with fewer than 3 points");
                    add_polygon(mesh, p);
                } else if (name == "CELLS") {
                    cells.push_back(p);
                    cell_lines.push_back(line);
                }
            }
            if (read != size) {
                fail(path, section->line,
                     name + " list size " + std::to_string(size) + " does not match its content (" +
                         std::to_string(read) + " numbers)");
            }
        } else if (name == "OFFSETS" || name == "CONNECTIVITY") {
            fail(path, section->line, "the VTK 5 OFFSETS/CONNECTIVITY layout is not supported");
        } else if (name == "CELL_TYPES") {
            const std::int64_t n = tok.expect_int("number of cell types");
            if (n != static_cast<std::int64_t>(cells.size())) {
                fail(path, section->line,
                     "CELL_TYPES count " + std::to_string(n) + " does not match CELLS count " +
                         std::to_string(cells.size()));
            }
            for (std::size_t c = 0; c < cells.size(); ++c) {
                const std::int64_t type = tok.expect_int("cell type");
                add_vtk_cell(mesh, type, cells[c], path, cell_lines[c], tok.line());
            }
            have_types = true;
        } else if (name == "POINT_DATA" || name == "CELL_DATA" || name == "FIELD" || name == "METADATA") {
            break;  // attributes: not geometry
        } else {
            fail(path, section->line, "unexpected VTK keyword " + quoted(section->text));
        }
    }
    if (npoints < 0) fail(path, tok.line(), "no POINTS section");
    if (npoints == 0) fail(path, tok.line(), "no vertices (POINTS 0)");
    if (!cells.empty() && !have_types) fail(path, tok.line(), "CELLS without CELL_TYPES");
    return mesh;
}

MeshData load_mesh_file(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".obj") return load_obj(path);
    if (ext == ".msh") return load_gmsh(path);
    if (ext == ".sph") return load_sph(path);
    if (ext == ".vtk" || ext == ".vtu") return load_vtk(path);
    if (ext == ".off") return load_off(path);
    if (ext == ".trian") return load_trian(path);
    fail(path, 0, "unknown mesh file extension '" + ext + "' (expected .obj, .msh, .sph, .vtk, .vtu, .off or .trian)");
}

// ---------------------------------------------------------------------------------------------
// OFF and Trian

namespace {

/// Point index read from a mesh file: 0 ≤ i < point_count.
PointId checked_point(Tokenizer& tok, std::size_t point_count, std::string_view what) {
    const std::int64_t i = tok.expect_int(what);
    if (i < 0 || i >= static_cast<std::int64_t>(point_count))
        fail(tok.path(), tok.line(),
             std::string(what) + " " + std::to_string(i) + " is not one of the " + std::to_string(point_count) +
                 " points");
    return static_cast<PointId>(i);
}

/// Skips blank lines and `#` comment lines (SOFA's MeshOffLoader::readOFF reads line by line).
void skip_off_comments(Tokenizer& tok, std::string_view text) {
    for (;;) {
        const std::size_t at = text.size() - tok.remaining();
        std::size_t i = at;
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r' || text[i] == '\n')) ++i;
        if (i >= text.size() || text[i] != '#') return;
        (void)tok.next();          // the comment's first token
        (void)tok.rest_of_line();  // and the rest of its line
    }
}

}  // namespace

MeshData load_off(const std::filesystem::path& path) { return parse_off(detail::read_file(path), path); }

MeshData parse_off(std::string_view text, const std::filesystem::path& path) {
    Tokenizer tok(text, path);
    MeshData mesh;
    const auto header = tok.next();
    if (!header || header->text != "OFF")
        fail(path, header ? header->line : 1, "not an OFF file (the first word must be OFF)");
    (void)tok.rest_of_line();
    skip_off_comments(tok, text);
    const std::int64_t vertices = tok.expect_int("vertex count");
    const std::int64_t faces = tok.expect_int("face count");
    (void)tok.rest_of_line();  // the edge count, unused
    tok.check_count(vertices, 3, "vertex");
    tok.check_count(faces, 4, "face");
    mesh.positions.reserve(static_cast<std::size_t>(vertices));
    for (std::int64_t v = 0; v < vertices; ++v) {
        skip_off_comments(tok, text);
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = tok.expect_double("vertex coordinate");
        (void)tok.rest_of_line();
        mesh.positions.push_back(p);
    }
    for (std::int64_t f = 0; f < faces;) {
        skip_off_comments(tok, text);
        const std::int64_t n = tok.expect_int("face vertex count");
        if (n == 3) {
            Triangle t;
            for (auto& i : t) i = checked_point(tok, mesh.positions.size(), "face vertex");
            mesh.triangles.push_back(t);
        } else if (n == 4) {
            Quad q;
            for (auto& i : q) i = checked_point(tok, mesh.positions.size(), "face vertex");
            mesh.quads.push_back(q);
        }
        (void)tok.rest_of_line();
        if (n == 3 || n == 4) ++f;  // SOFA does not count a skipped face
        if (tok.remaining() == 0 && f < faces) fail(path, tok.line(), "unexpected end of file (expected a face)");
    }
    return mesh;
}

MeshData load_trian(const std::filesystem::path& path) { return parse_trian(detail::read_file(path), path); }

MeshData parse_trian(std::string_view text, const std::filesystem::path& path) {
    Tokenizer tok(text, path);
    MeshData mesh;
    const std::int64_t vertices = tok.expect_int("vertex count");
    tok.check_count(vertices, 3, "vertex");
    mesh.positions.reserve(static_cast<std::size_t>(vertices));
    for (std::int64_t v = 0; v < vertices; ++v) {
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = tok.expect_double("vertex coordinate");
        mesh.positions.push_back(p);
    }
    const std::int64_t triangles = tok.expect_int("triangle count");
    tok.check_count(triangles, 6, "triangle");
    mesh.triangles.reserve(static_cast<std::size_t>(triangles));
    for (std::int64_t t = 0; t < triangles; ++t) {
        Triangle tri;
        for (auto& i : tri) i = checked_point(tok, mesh.positions.size(), "triangle point");
        for (int k = 0; k < 3; ++k) (void)tok.expect_int("triangle neighbour");
        mesh.triangles.push_back(tri);
    }
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// post-processing

void apply_transform(std::vector<Vec3>& points, const Vec3& translation, const Vec3& rotation_degrees,
                     const Vec3& scale3d, LoaderKind kind) {
    place_loaded_points(points, translation, rotation_degrees, scale3d, kind);
}

void apply_transform(MeshData& mesh, const Vec3& translation, const Vec3& rotation_degrees, const Vec3& scale3d,
                     LoaderKind kind) {
    place_loaded_points(mesh.positions, translation, rotation_degrees, scale3d, kind);
}

namespace {

template <std::size_t N>
std::array<PointId, N> sorted(std::array<PointId, N> a) {
    std::sort(a.begin(), a.end());
    return a;
}

template <std::size_t N, class Elements, class Faces>
void add_missing(std::vector<std::array<PointId, N>>& target, const Elements& elements, const Faces& faces) {
    VertexListSet<PointId, N> known;  // (the first occurrence kept: SOFA's order)
    // (about half of a volume mesh's faces are new, a fifth of its triangles' edges; the set
    // grows when more are)
    known.reserve(target.size() + elements.size() * faces.size() / 4);
    for (const auto& t : target) known.insert(sorted(t));
    for (const auto& e : elements) {
        for (const auto& f : faces) {
            std::array<PointId, N> face{};
            for (std::size_t k = 0; k < N; ++k) face[k] = e[static_cast<std::size_t>(f[k])];
            if (known.insert(sorted(face))) target.push_back(face);
        }
    }
}

}  // namespace

void create_subelements(MeshData& mesh) {
    static constexpr std::array<std::array<int, 4>, 6> hexa_faces{
        {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
    static constexpr std::array<std::array<int, 3>, 4> tetra_faces{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
    static constexpr std::array<std::array<int, 2>, 4> quad_edges{{{1, 2}, {2, 3}, {3, 0}, {0, 1}}};
    static constexpr std::array<std::array<int, 2>, 3> triangle_edges{{{1, 2}, {2, 0}, {0, 1}}};
    if (!mesh.hexahedra.empty()) add_missing(mesh.quads, mesh.hexahedra, hexa_faces);
    if (!mesh.tetrahedra.empty()) add_missing(mesh.triangles, mesh.tetrahedra, tetra_faces);
    if (!mesh.quads.empty()) add_missing(mesh.edges, mesh.quads, quad_edges);
    if (!mesh.triangles.empty()) add_missing(mesh.edges, mesh.triangles, triangle_edges);
}

void triangulate_quads(MeshData& mesh) {
    for (const Quad& q : mesh.quads) {
        mesh.triangles.push_back(Triangle{q[0], q[1], q[2]});
        mesh.triangles.push_back(Triangle{q[0], q[2], q[3]});
    }
    mesh.quads.clear();
}

void flip_normals(MeshData& mesh) {
    for (Triangle& t : mesh.triangles) std::reverse(t.begin(), t.end());
    for (Quad& q : mesh.quads) std::reverse(q.begin(), q.end());
}

}  // namespace penalty::io
