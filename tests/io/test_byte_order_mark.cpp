// Text files as editors on Windows write them: a UTF-8 byte-order mark (EF BB BF) at the start
// and CRLF line ends. Every mesh format and the scene file read them as the same file without
// (before the fix, an OBJ file's first line "\xEF\xBB\xBFv 0 0 0" was an unknown keyword: the
// first vertex was lost and every face pointed at the next one).

#include "io_test_util.hpp"

#include "penalty/io/mesh.hpp"
#include "penalty/io/scene_file.hpp"

#include <gtest/gtest.h>

#include <string>

namespace penalty::io {
namespace {

constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

std::string with_crlf(const std::string& text) {
    std::string out;
    for (const char c : text) {
        if (c == '\n') out += '\r';
        out += c;
    }
    return out;
}

/// The four spellings of one file: as written, with a BOM, with CRLF, with both.
std::vector<std::pair<std::string, std::string>> spellings(const std::string& text) {
    return {{"LF", text},
            {"BOM + LF", std::string(kByteOrderMark) + text},
            {"CRLF", with_crlf(text)},
            {"BOM + CRLF", std::string(kByteOrderMark) + with_crlf(text)}};
}

void expect_same_mesh(const MeshData& a, const MeshData& b, const std::string& what) {
    EXPECT_EQ(a.positions, b.positions) << what;
    EXPECT_EQ(a.edges, b.edges) << what;
    EXPECT_EQ(a.triangles, b.triangles) << what;
    EXPECT_EQ(a.quads, b.quads) << what;
    EXPECT_EQ(a.tetrahedra, b.tetrahedra) << what;
    EXPECT_EQ(a.hexahedra, b.hexahedra) << what;
    EXPECT_EQ(a.radii, b.radii) << what;
}

struct Format {
    const char* extension;
    std::string text;
    std::size_t points;  ///< what the plain file holds (the reference is not empty)
};

std::vector<Format> formats() {
    return {
        {".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n", 4},
        {".msh",
         "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
         "$Elements\n1\n1 4 2 0 1 1 2 3 4\n$EndElements\n",
         4},
        {".sph", "sph 1.0\nnums 2\nsphe 1 0 0 0 0.5\nsphe 2 1 0 0 0.25\n", 2},
        {".vtk",
         "# vtk DataFile Version 2.0\ntest\nASCII\nDATASET POLYDATA\nPOINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\n"
         "POLYGONS 2 8\n3 0 1 2\n3 0 1 3\n",
         4},
        {".off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n", 4},
        {".trian", "4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n2\n0 1 2 -1 -1 -1\n0 1 3 -1 -1 -1\n", 4},
    };
}

TEST(ByteOrderMark, EveryMeshFormatReadsTheSameMeshWithABomAndWithCrlf) {
    for (const Format& f : formats()) {
        const MeshData reference = load_mesh_file(test::write_temp(std::string("plain") + f.extension, f.text));
        ASSERT_EQ(reference.positions.size(), f.points) << f.extension;
        ASSERT_EQ(reference.positions.front(), Vec3(0, 0, 0)) << f.extension;
        int k = 0;
        for (const auto& [name, text] : spellings(f.text)) {
            const std::string what = std::string(f.extension) + " with " + name;
            const auto path = test::write_temp("spelling" + std::to_string(k++) + f.extension, text);
            MeshData read;
            ASSERT_NO_THROW(read = load_mesh_file(path)) << what;
            expect_same_mesh(read, reference, what);
        }
    }
}

TEST(ByteOrderMark, ObjFirstVertexIsKept) {
    // The case of the report: the BOM glued to the first keyword.
    const MeshData m = parse_obj(std::string(kByteOrderMark) + "v 5 6 7\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bom.obj");
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_EQ(m.positions[0], Vec3(5, 6, 7));
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
}

TEST(ByteOrderMark, SceneFileWithBomAndCrlfParsesAsWithout) {
    const std::string scene =
        "<?xml version=\"1.0\"?>\n<Node name=\"root\" dt=\"0.02\">\n  <Node name=\"A\">\n"
        "    <MechanicalObject name=\"dofs\" position=\"1 2 3\"/>\n  </Node>\n</Node>\n";
    int k = 0;
    for (const auto& [name, text] : spellings(scene)) {
        const SceneFile f = parse_scene_file(test::write_temp("bom" + std::to_string(k++) + ".scn", text), {});
        ASSERT_TRUE(f.root) << name;
        ASSERT_EQ(f.root->children.size(), 1u) << name;
        const SceneNode& a = *f.root->children[0];
        ASSERT_EQ(a.components.size(), 1u) << name;
        EXPECT_EQ(a.components[0]->line, 4) << name;  // lines are counted as without the BOM
        EXPECT_EQ(get_string(*a.components[0], "position").value_or(""), "1 2 3") << name;
    }
}

}  // namespace
}  // namespace penalty::io
