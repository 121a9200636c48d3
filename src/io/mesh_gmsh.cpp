#include "penalty/io/mesh.hpp"

#include "io/text.hpp"

#include <set>
#include <string>
#include <unordered_map>

namespace penalty::io {

using detail::fail;
using detail::parse_double;
using detail::parse_int;
using detail::quoted;
using detail::Token;
using detail::Tokenizer;

// ---------------------------------------------------------------------------------------------
// Gmsh

namespace {

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// Number of nodes of a v2 element type; -1 when the type is unknown.
int gmsh_node_count(std::int64_t type) {
    switch (type) {
        case 15:
            return 1;
        case 1:
            return 2;
        case 2:
            return 3;
        case 3:
            return 4;
        case 4:
            return 4;
        case 5:
            return 8;
        case 8:
            return 3;
        case 9:
            return 6;
        case 11:
            return 10;
        default:
            return -1;
    }
}

/// Appends one Gmsh element of `type` with point indices `nodes` (SOFA's MeshGmsh::readGmsh):
/// lines (1, 8), triangles (2, 9), quads (3), tetrahedra (4, 11), hexahedra (5); for the
/// second-order 9 and 11 also their corner pairs as edges, each pair once per `seen` set.
void add_gmsh_element(MeshData& mesh, std::int64_t type, const std::vector<PointId>& nodes,
                      std::set<std::pair<PointId, PointId>>& seen) {
    switch (type) {
        case 1:
        case 8:
            mesh.edges.push_back(Edge{nodes[0], nodes[1]});
            break;
        case 2:
        case 9:
            mesh.triangles.push_back(Triangle{nodes[0], nodes[1], nodes[2]});
            break;
        case 3:
            mesh.quads.push_back(Quad{nodes[0], nodes[1], nodes[2], nodes[3]});
            break;
        case 4:
        case 11:
            mesh.tetrahedra.push_back(Tetrahedron{nodes[0], nodes[1], nodes[2], nodes[3]});
            break;
        case 5:
            mesh.hexahedra.push_back(
                Hexahedron{nodes[0], nodes[1], nodes[2], nodes[3], nodes[4], nodes[5], nodes[6], nodes[7]});
            break;
        default:
            break;  // points and unknown types are skipped
    }
    // second-order elements: SOFA also adds their edges (corner pairs) for the mid nodes
    if (type == 9 || type == 11) {
        static constexpr int tri_edges[3][2] = {{0, 1}, {1, 2}, {2, 0}};
        static constexpr int tet_edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
        const int count = type == 9 ? 3 : 6;
        for (int j = 0; j < count; ++j) {
            const auto& ab = type == 9 ? tri_edges[j] : tet_edges[j];
            const PointId a = std::min(nodes[static_cast<std::size_t>(ab[0])], nodes[static_cast<std::size_t>(ab[1])]);
            const PointId b = std::max(nodes[static_cast<std::size_t>(ab[0])], nodes[static_cast<std::size_t>(ab[1])]);
            if (seen.insert({a, b}).second) mesh.edges.push_back(Edge{a, b});
        }
    }
}

/// The $Nodes and $Elements sections of a Gmsh 4 ASCII file, as SOFA's MeshGmsh::readGmsh reads
/// them: nodes in block order (their tags are not used: an element's node n is point n − 1), one
/// line per node tag and per coordinate (parametric coordinates ignored); elements of types 1, 2,
/// 3, 4, 5 and the second-order 8, 9, 11 (corner nodes, and for 9 and 11 the corner pairs as edges,
/// each pair once over the whole file); points (15), prisms (6) and unknown types are skipped.
MeshData parse_gmsh4_sections(Tokenizer& tok, const std::filesystem::path& path) {
    MeshData mesh;
    const std::int64_t node_blocks = tok.expect_int("number of node blocks");
    const std::int64_t npoints = tok.expect_int("number of nodes");
    (void)tok.expect_int("minimum node tag");
    (void)tok.expect_int("maximum node tag");
    tok.check_count(node_blocks, 4, "node block");
    tok.check_count(npoints, 4, "node");
    (void)tok.rest_of_line();
    mesh.positions.reserve(static_cast<std::size_t>(npoints));
    for (std::int64_t b = 0; b < node_blocks; ++b) {
        (void)tok.expect_int("entity dimension");
        (void)tok.expect_int("entity tag");
        (void)tok.expect_int("parametric flag");
        const std::int64_t count = tok.expect_int("number of nodes in block");
        tok.check_count(count, 4, "node");
        (void)tok.rest_of_line();
        for (std::int64_t i = 0; i < count; ++i) {
            (void)tok.expect_int("node tag");
            (void)tok.rest_of_line();
        }
        for (std::int64_t i = 0; i < count; ++i) {
            Vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = tok.expect_double("node coordinate");
            (void)tok.rest_of_line();
            mesh.positions.push_back(p);
        }
    }
    if (mesh.positions.empty()) fail(path, tok.line(), "no nodes (node count 0)");
    const Token end_nodes = tok.expect("$EndNodes");
    if (!starts_with(end_nodes.text, "$EndNodes"))
        fail(path, end_nodes.line, "expected $EndNodes, found " + quoted(end_nodes.text));
    const Token elements = tok.expect("$Elements");
    if (!starts_with(elements.text, "$Elements"))
        fail(path, elements.line, "expected $Elements, found " + quoted(elements.text));
    const std::int64_t element_blocks = tok.expect_int("number of element blocks");
    (void)tok.expect_int("number of elements");
    (void)tok.expect_int("minimum element tag");
    (void)tok.expect_int("maximum element tag");
    tok.check_count(element_blocks, 4, "element block");
    (void)tok.rest_of_line();
    std::vector<PointId> nodes;
    std::set<std::pair<PointId, PointId>> second_order_edges;  // one set for the file (SOFA's v4 reader)
    for (std::int64_t b = 0; b < element_blocks; ++b) {
        (void)tok.expect_int("entity dimension");
        (void)tok.expect_int("entity tag");
        const std::int64_t type = tok.expect_int("element type");
        const std::int64_t count = tok.expect_int("number of elements in block");
        tok.check_count(count, 1, "element");
        (void)tok.rest_of_line();
        const int nnodes = type == 6 ? 6 : std::max(gmsh_node_count(type), 0);
        for (std::int64_t e = 0; e < count; ++e) {
            (void)tok.expect_int("element tag");
            nodes.clear();
            for (int k = 0; k < nnodes; ++k) {
                const std::int64_t tag = tok.expect_int("element node");
                if (tag < 1 || tag > static_cast<std::int64_t>(mesh.positions.size()))
                    fail(path, tok.line(),
                         "element node " + std::to_string(tag) + " is not one of the " +
                             std::to_string(mesh.positions.size()) + " nodes (Gmsh 4: node n is the n-th node read)");
                nodes.push_back(static_cast<PointId>(tag - 1));
            }
            (void)tok.rest_of_line();
            add_gmsh_element(mesh, type, nodes, second_order_edges);
        }
    }
    const Token end_elements = tok.expect("$EndElements");
    if (!starts_with(end_elements.text, "$EndElements"))
        fail(path, end_elements.line, "expected $EndElements, found " + quoted(end_elements.text));
    return mesh;
}

}  // namespace

MeshData load_gmsh(const std::filesystem::path& path) { return parse_gmsh(detail::read_file(path), path); }

MeshData parse_gmsh(std::string_view text, const std::filesystem::path& path) {
    Tokenizer tok(text, path);
    MeshData mesh;

    int format = 0;
    const auto first = tok.next();
    if (!first) fail(path, 1, "empty file (expected $MeshFormat or $NOD)");
    if (starts_with(first->text, "$MeshFormat")) {
        const Token version = tok.expect("format version");
        const auto v = parse_double(version.text);
        if (!v) fail(path, version.line, "expected a format version, found " + quoted(version.text));
        // Versions 2.x and 4.x (SOFA's MeshGmsh::readGmsh reads both); checked on the double,
        // before the narrowing cast.
        if (!((*v >= 2.0 && *v < 3.0) || (*v >= 4.0 && *v < 5.0))) {
            fail(path, version.line,
                 "Gmsh format " + std::string(version.text) + " is not supported (only 1, 2 and 4 ASCII)");
        }
        format = static_cast<int>(*v);
        const Token file_type = tok.expect("file type");
        if (file_type.text != "0") fail(path, file_type.line, "binary Gmsh files are not supported");
        (void)tok.expect("data size");
        const Token end = tok.expect("$EndMeshFormat");
        if (!starts_with(end.text, "$EndMeshFormat")) {
            fail(path, end.line, "expected $EndMeshFormat, found " + quoted(end.text));
        }
        // skip other sections until $Nodes
        for (;;) {
            const Token t = tok.expect("$Nodes");
            if (starts_with(t.text, "$Nodes")) break;
        }
    } else if (starts_with(first->text, "$NOD")) {
        format = 1;
    } else {
        fail(path, first->line, "not a Gmsh file (first line must be $MeshFormat or $NOD)");
    }

    if (format == 4) return parse_gmsh4_sections(tok, path);

    // nodes: "number x y z"
    const std::int64_t npoints = tok.expect_int("number of nodes");
    tok.check_count(npoints, 4, "node");
    if (npoints == 0) fail(path, tok.line(), "no nodes (node count 0)");
    mesh.positions.reserve(static_cast<std::size_t>(npoints));
    std::unordered_map<std::int64_t, std::int64_t> number_to_index;  // node number -> position index
    for (std::int64_t i = 0; i < npoints; ++i) {
        const std::int64_t number = tok.expect_int("node number");
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = tok.expect_double("node coordinate");
        number_to_index[number] = i;  // a repeated number: the last definition wins (as SOFA)
        mesh.positions.push_back(p);
    }
    const Token end_nodes = tok.expect(format == 1 ? "$ENDNOD" : "$EndNodes");
    if (!starts_with(end_nodes.text, "$ENDNOD") && !starts_with(end_nodes.text, "$EndNodes")) {
        fail(path, end_nodes.line,
             std::string("expected ") + (format == 1 ? "$ENDNOD" : "$EndNodes") + ", found " + quoted(end_nodes.text));
    }
    const Token elements = tok.expect(format == 1 ? "$ELM" : "$Elements");
    if (!starts_with(elements.text, "$ELM") && !starts_with(elements.text, "$Elements")) {
        fail(path, elements.line,
             std::string("expected ") + (format == 1 ? "$ELM" : "$Elements") + ", found " + quoted(elements.text));
    }

    const std::int64_t nelems = tok.expect_int("number of elements");
    tok.check_count(nelems, 4, "element");
    std::vector<PointId> nodes;
    for (std::int64_t e = 0; e < nelems; ++e) {
        (void)tok.expect_int("element number");
        const int element_line = tok.line();
        const std::int64_t type = tok.expect_int("element type");
        std::int64_t nnodes = 0;
        if (format == 1) {
            (void)tok.expect_int("physical region");
            (void)tok.expect_int("elementary region");
            nnodes = tok.expect_int("number of element nodes");
            const int expected = gmsh_node_count(type);
            if (nnodes < 0 || nnodes > 1000 || (expected >= 0 && nnodes != expected)) {
                fail(path, element_line,
                     "element of type " + std::to_string(type) + " has " + std::to_string(nnodes) + " nodes" +
                         (expected >= 0 ? " (expected " + std::to_string(expected) + ")" : ""));
            }
        } else {
            const std::int64_t ntags = tok.expect_int("number of tags");
            tok.check_count(ntags, 1, "tag");
            for (std::int64_t t = 0; t < ntags; ++t) (void)tok.expect_int("tag");
            nnodes = gmsh_node_count(type);
            if (nnodes < 0) {
                // SOFA warns and skips the rest of the line
                (void)tok.rest_of_line();
                continue;
            }
        }
        nodes.clear();
        for (std::int64_t k = 0; k < nnodes; ++k) {
            const std::int64_t number = tok.expect_int("element node");
            const auto found = number_to_index.find(number);
            if (found == number_to_index.end()) {
                fail(path, tok.line(), "element node " + std::to_string(number) + " is not a defined node");
            }
            nodes.push_back(static_cast<PointId>(found->second));
        }
        // SOFA's v1/v2 reader keeps the set of second-order edges per element
        std::set<std::pair<PointId, PointId>> second_order_edges;
        add_gmsh_element(mesh, type, nodes, second_order_edges);
    }
    const Token end_elements = tok.expect(format == 1 ? "$ENDELM" : "$EndElements");
    if (!starts_with(end_elements.text, "$ENDELM") && !starts_with(end_elements.text, "$EndElements")) {
        fail(path, end_elements.line,
             std::string("expected ") + (format == 1 ? "$ENDELM" : "$EndElements") + ", found " +
                 quoted(end_elements.text));
    }
    return mesh;
}

}  // namespace penalty::io
