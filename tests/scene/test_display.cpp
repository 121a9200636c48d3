// The formatting of `penalty info`'s lines (scene/display.cpp): numbers to six significant digits,
// vectors, node paths of the graph and of the file, counted nouns and element counts (the kinds
// present, in a fixed order).
#include "../../src/scene/display.hpp"

#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/topology.hpp"
#include "penalty/simulation/node.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace {

using namespace penalty;
namespace display = penalty::scene::display;

TEST(Display, NumbersHaveSixSignificantDigits) {
    EXPECT_EQ(display::number(0.0), "0");
    EXPECT_EQ(display::number(1.0), "1");
    EXPECT_EQ(display::number(-2.5), "-2.5");
    EXPECT_EQ(display::number(0.1 + 0.2), "0.3");
    EXPECT_EQ(display::number(1234567.0), "1.23457e+06");
    EXPECT_EQ(display::number(0.000012345678), "1.23457e-05");
    EXPECT_EQ(display::number(123456.0), "123456");
    EXPECT_EQ(display::number(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(display::number(-std::numeric_limits<double>::max()), "-1.79769e+308");
    EXPECT_EQ(display::vector(Vec3(1, -0.5, 1e-7)), "(1, -0.5, 1e-07)");
}

TEST(Display, NodePathsAreSofasForTheGraphAndTheFile) {
    Node root("root");
    Node& a = root.add_child("A");
    Node& b = a.add_child("B");
    EXPECT_EQ(display::node_path(root), "/");
    EXPECT_EQ(display::node_path(a), "/A");
    EXPECT_EQ(display::node_path(b), "/A/B");
    const io::SceneFile file =
        io::parse_scene_string("<Node name=\"root\"><Node name=\"A\"><Node name=\"B\"/></Node></Node>", "d.scn");
    EXPECT_EQ(display::node_path(*file.root), "/");
    EXPECT_EQ(display::node_path(*file.root->children[0]), "/A");
    EXPECT_EQ(display::node_path(*file.root->children[0]->children[0]), "/A/B");
}

TEST(Display, CountedNounsAndElementCountsNameTheKindsPresent) {
    EXPECT_EQ(display::counted(0, "DOF", "DOFs"), "0 DOFs");
    EXPECT_EQ(display::counted(1, "DOF", "DOFs"), "1 DOF");
    EXPECT_EQ(display::counted(2, "tetrahedron", "tetrahedra"), "2 tetrahedra");
    MeshTopology t;
    t.set_num_points(8);
    EXPECT_EQ(display::element_counts(8, t), "8 points");
    t.set_triangles({{0, 1, 2}});
    t.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
    // the derived edges and quads too (the hexahedron's 12 edges and 6 faces: the edges come from
    // the volumes when there are some), in the order edges, triangles, quads, tetrahedra, hexahedra
    EXPECT_EQ(display::element_counts(1, t), "1 point, 12 edges, 1 triangle, 6 quads, 1 hexahedron");
    io::MeshData m;
    m.positions.resize(5);
    EXPECT_EQ(display::mesh_counts(m), "5 points");
    m.edges = {{0, 1}, {1, 2}};
    m.quads = {{0, 1, 2, 3}};
    m.tetrahedra = {{0, 1, 2, 4}, {0, 2, 3, 4}, {1, 2, 3, 4}};
    EXPECT_EQ(display::mesh_counts(m), "5 points, 2 edges, 1 quad, 3 tetrahedra");
}

}  // namespace
