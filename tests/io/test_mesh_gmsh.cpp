// The Gmsh loader (io/mesh_gmsh.cpp) on small files written for these tests: versions 1, 2 and 4,
// ASCII and binary, element kinds, and every malformed case with its exact message.

#include "io_test_util.hpp"

#include "penalty/io/mesh.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penalty::io {
namespace {

using test::mesh_file;
using test::message_of;
using test::write_temp;
using ::testing::ElementsAre;

TEST(GmshLoader, Version1MapsNodeNumbersAndKeepsElementTypes) {
    const MeshData m = load_gmsh(mesh_file("two_tets_v1.msh"));
    ASSERT_EQ(m.positions.size(), 5u);
    EXPECT_EQ(m.positions[3], Vec3(0, 0, 1));
    EXPECT_THAT(m.edges, ElementsAre(Edge{0, 1}));
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}));
    EXPECT_THAT(m.tetrahedra, ElementsAre(Tetrahedron{0, 1, 2, 3}, Tetrahedron{1, 2, 3, 4}));
}

TEST(GmshLoader, SubelementsAsSofaMeshLoader) {
    MeshData m = load_gmsh(mesh_file("two_tets_v1.msh"));
    create_subelements(m);
    // missing faces of the tetrahedra, in SOFA's face order, after the file's triangle
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}, Triangle{0, 1, 3}, Triangle{0, 3, 2}, Triangle{1, 2, 3},
                                         Triangle{1, 2, 4}, Triangle{1, 4, 3}, Triangle{2, 3, 4}));
    // missing edges of the triangles (e[j+1], e[j+2]), after the file's edge: every pair but (0,4)
    EXPECT_THAT(m.edges, ElementsAre(Edge{0, 1}, Edge{1, 2}, Edge{2, 0}, Edge{1, 3}, Edge{3, 0}, Edge{3, 2}, Edge{2, 4},
                                     Edge{4, 1}, Edge{4, 3}));
}

TEST(GmshLoader, Version2WithHexahedronAndQuad) {
    MeshData m = load_gmsh(mesh_file("hex_v2.msh"));
    ASSERT_EQ(m.positions.size(), 8u);
    EXPECT_THAT(m.quads, ElementsAre(Quad{0, 1, 2, 3}));
    EXPECT_THAT(m.hexahedra, ElementsAre(Hexahedron{0, 1, 2, 3, 4, 5, 6, 7}));
    create_subelements(m);
    EXPECT_THAT(m.quads, ElementsAre(Quad{0, 1, 2, 3}, Quad{4, 5, 6, 7}, Quad{0, 1, 5, 4}, Quad{1, 2, 6, 5},
                                     Quad{2, 3, 7, 6}, Quad{3, 0, 4, 7}));
    ASSERT_EQ(m.edges.size(), 12u);
    EXPECT_EQ(m.edges[0], (Edge{1, 2}));
    EXPECT_EQ(m.edges[4], (Edge{5, 6}));
    EXPECT_EQ(m.edges[8], (Edge{1, 5}));
    EXPECT_EQ(m.edges[11], (Edge{3, 7}));
    EXPECT_TRUE(m.triangles.empty());
}

TEST(GmshLoader, Truncated) {
    const auto p = write_temp("truncated.msh", "$NOD\n2\n1 0 0 0\n2 1.0000 0\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":4: unexpected end of file (expected node coordinate)");
}

TEST(GmshLoader, CountLargerThanTheFile) {
    const auto p = write_temp("short.msh", "$NOD\n3\n1 0 0 0\n2 1 0 0\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":2: node count 3 exceeds what the file can hold");
}

TEST(GmshLoader, TruncatedInElements) {
    const auto p = write_temp("truncated_elm.msh", "$NOD\n2\n1 0 0 0\n2 1 0 0\n$ENDNOD\n$ELM\n1\n1 1 0 0 2 1");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":8: unexpected end of file (expected element node)");
}

TEST(GmshLoader, HugeCountIsRejectedBeforeAllocating) {
    const auto p = write_temp("huge.msh", "$NOD\n99999999999\n1 0 0 0\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":2: node count 99999999999 exceeds what the file can hold");
}

TEST(GmshLoader, UndefinedNode) {
    const auto p =
        write_temp("undefined.msh", "$NOD\n2\n1 0 0 0\n2 1 0 0\n$ENDNOD\n$ELM\n1\n1 1 0 0 2 1 99\n$ENDELM\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":8: element node 99 is not a defined node");
}

TEST(GmshLoader, WrongNodeCountForType) {
    const auto p = write_temp("wrong_count.msh",
                              "$NOD\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$ENDNOD\n$ELM\n1\n1 4 0 0 3 1 2 3\n$ENDELM\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":9: element of type 4 has 3 nodes (expected 4)");
}

TEST(GmshLoader, BadCoordinate) {
    const auto p = write_temp("bad_coord.msh", "$NOD\n1\n1 0 x 0\n$ENDNOD\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":3: expected node coordinate (a number), found 'x'");
}

TEST(GmshLoader, NotGmsh) {
    const auto p = write_temp("not_gmsh.msh", "hello\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":1: not a Gmsh file (first line must be $MeshFormat or $NOD)");
}

TEST(GmshLoader, Version3Refused) {
    const auto p = write_temp("v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":2: Gmsh format 3.0 is not supported (only 1, 2 and 4 ASCII)");
}

// A Gmsh 4.1 file (made for this test): two node blocks (the second with a parametric coordinate),
// node tags not in order, a point element, two triangles, a prism (skipped), a second-order
// triangle whose corner edges come once over the file (SOFA's MeshGmsh::readGmsh, version 4).
constexpr const char* kGmsh4 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
1 0 0 0
1 0 0 0 0
$EndEntities
$Nodes
2 6 1 6
0 1 0 2
5
9
0 0 0
1 0 0
2 7 1 4
1
2
3
4
1 1 0 0.5
0 1 0 0.25
0 0 1 0.125
1 1 1 0.0625
$EndNodes
$Elements
5 6 1 6
0 1 15 1
1 1
2 7 2 2
2 1 2 3
3 1 3 4
3 1 6 1
4 1 2 3 4 5 6
2 8 9 1
5 1 2 3 4 5 6
2 9 9 1
6 2 1 3 5 6 4
$EndElements
)";

TEST(GmshLoader, Version4NodesInBlockOrderAndElementBlocks) {
    const auto p = write_temp("v4.msh", kGmsh4);
    const MeshData m = load_gmsh(p);
    ASSERT_EQ(m.positions.size(), 6u);
    EXPECT_EQ(m.positions[1], Vec3(1, 0, 0));
    EXPECT_EQ(m.positions[3], Vec3(0, 1, 0));  // parametric coordinate ignored
    EXPECT_EQ(m.positions[5], Vec3(1, 1, 1));
    // node n of an element is the n-th node read (tags 5 and 9 of the first block are not used)
    ASSERT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
    EXPECT_EQ(m.triangles[2], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.triangles[3], (Triangle{1, 0, 2}));
    // corner pairs of the two second-order triangles, each pair once: (0,1), (1,2), (0,2)
    EXPECT_EQ(m.edges, (std::vector<Edge>{{0, 1}, {1, 2}, {0, 2}}));
    EXPECT_TRUE(m.tetrahedra.empty());
}

TEST(GmshLoader, Version4NodeBeyondTheNodesRead) {
    std::string text = kGmsh4;
    text.replace(text.find("3 1 3 4"), 7, "3 1 3 7");
    const auto p = write_temp("v4_bad.msh", text);
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }),
              p.string() + ":31: element node 7 is not one of the 6 nodes (Gmsh 4: node n is the n-th node read)");
}

TEST(GmshLoader, MissingEndSection) {
    const auto p = write_temp("no_end.msh", "$NOD\n1\n1 0 0 0\n$ELM\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_gmsh(p); }), p.string() + ":4: expected $ENDNOD, found '$ELM'");
}

}  // namespace
}  // namespace penalty::io
