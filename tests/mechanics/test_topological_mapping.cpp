// SOFA's static topological mappings: the output elements in SOFA's order and orientation
// (Tetra2Triangle, Hexa2Quad, Triangle2Edge, Quad2Triangle, Hexa2Tetra ...TopologicalMapping::init).
#include "penalty/mechanics/topological_mapping.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace {

using namespace penalty;
using ::testing::ElementsAre;

/// Unit cube, SOFA's hexahedron numbering (0..3 bottom counter-clockwise seen from +z, 4..7 above).
const std::vector<Vec3> kCube{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

double signed_volume(const std::vector<Vec3>& x, const Tetrahedron& t) {
    const Vec3 &a = x[std::size_t(t[0])], &b = x[std::size_t(t[1])], &c = x[std::size_t(t[2])],
               &d = x[std::size_t(t[3])];
    return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

TEST(TopologicalMapping, Tetra2TriangleKeepsTheBorderInTheInputTriangleOrder) {
    MeshTopology tetras;
    tetras.set_tetrahedra({{0, 1, 2, 3}, {1, 2, 3, 4}});
    // Input triangles (derived): (1,2,3) (0,3,2) (0,1,3) (0,2,1) (2,3,4) (1,4,3) (1,2,4);
    // (1,2,3) is shared by both tetrahedra.
    EXPECT_THAT(border_triangles(tetras, false), ElementsAre(Triangle{0, 3, 2}, Triangle{0, 1, 3}, Triangle{0, 2, 1},
                                                             Triangle{2, 3, 4}, Triangle{1, 4, 3}, Triangle{1, 2, 4}));
    EXPECT_THAT(border_triangles(tetras, true), ElementsAre(Triangle{0, 2, 3}, Triangle{0, 3, 1}, Triangle{0, 1, 2},
                                                            Triangle{2, 4, 3}, Triangle{1, 3, 4}, Triangle{1, 4, 2}));
}

TEST(TopologicalMapping, Tetra2TriangleBorderFacesPointOutward) {
    // Positive tetrahedron (0,1,2,3) at the unit corner: each border face's normal points away
    // from the opposite vertex.
    const std::vector<Vec3> x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    MeshTopology tetra;
    tetra.set_tetrahedra({{0, 1, 2, 3}});
    const Vec3 centre = (x[0] + x[1] + x[2] + x[3]) / 4.0;
    const auto faces = border_triangles(tetra, false);
    ASSERT_EQ(faces.size(), 4u);
    for (const Triangle& f : faces) {
        const Vec3 n = (x[std::size_t(f[1])] - x[std::size_t(f[0])]).cross(x[std::size_t(f[2])] - x[std::size_t(f[0])]);
        EXPECT_GT(n.dot(x[std::size_t(f[0])] - centre), 0.0);
    }
}

TEST(TopologicalMapping, Hexa2QuadKeepsTheBorderInTheInputQuadOrder) {
    // Two cubes sharing the face (1,2,6,5); quads of the second: (1,2,9,8) (5,10,11,6) (1,8,10,5)
    // (8,9,11,10) (2,6,11,9), its face (1,5,6,2) being the first's (1,2,6,5) reversed.
    MeshTopology hexas;
    hexas.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}, {1, 8, 9, 2, 5, 10, 11, 6}});
    EXPECT_THAT(
        border_quads(hexas, false),
        ElementsAre(Quad{0, 3, 2, 1}, Quad{4, 5, 6, 7}, Quad{0, 1, 5, 4}, Quad{2, 3, 7, 6}, Quad{0, 4, 7, 3},
                    Quad{1, 2, 9, 8}, Quad{5, 10, 11, 6}, Quad{1, 8, 10, 5}, Quad{8, 9, 11, 10}, Quad{2, 6, 11, 9}));
    EXPECT_EQ(border_quads(hexas, true).front(), (Quad{1, 2, 3, 0}));
}

TEST(TopologicalMapping, Triangle2EdgeKeepsTheBorderEdgesAsStored) {
    MeshTopology square;
    square.set_triangles({{0, 1, 2}, {0, 2, 3}});
    // Edges (oriented, first occurrence): (1,2) (2,0) (0,1) (2,3) (3,0); (2,0) is shared.
    EXPECT_THAT(border_edges(square), ElementsAre(Edge{1, 2}, Edge{0, 1}, Edge{2, 3}, Edge{3, 0}));
}

TEST(TopologicalMapping, Quad2TriangleSplitsEachQuadAndAlternatesWithSwapping) {
    const std::vector<Quad> quads{{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}};
    EXPECT_THAT(triangles_of_quads(quads, false, 2, 1),
                ElementsAre(Triangle{1, 2, 0}, Triangle{3, 0, 2}, Triangle{5, 6, 4}, Triangle{7, 4, 6},
                            Triangle{9, 10, 8}, Triangle{11, 8, 10}));
    // scale 2: quad 0 (0 xor 0) keeps, quad 1 (1 xor 0) and quad 2 (0 xor 1) swap.
    EXPECT_THAT(triangles_of_quads(quads, true, 2, 1),
                ElementsAre(Triangle{1, 2, 0}, Triangle{3, 0, 2}, Triangle{4, 5, 7}, Triangle{6, 7, 5},
                            Triangle{8, 9, 11}, Triangle{10, 11, 9}));
    // scale = cells along y when there are none along x
    EXPECT_EQ(triangles_of_quads(quads, true, 0, 1)[2], (Triangle{4, 5, 7}));
    EXPECT_THROW((void)triangles_of_quads(quads, true, 0, 0), std::invalid_argument);
}

TEST(TopologicalMapping, Hexa2TetraFillsTheCubeWithSixPositiveTetrahedra) {
    const auto tetras = tetrahedra_of_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}}, false, 2, 1);
    EXPECT_THAT(tetras, ElementsAre(Tetrahedron{0, 5, 1, 6}, Tetrahedron{0, 1, 3, 6}, Tetrahedron{1, 3, 6, 2},
                                    Tetrahedron{6, 3, 0, 7}, Tetrahedron{6, 7, 0, 5}, Tetrahedron{7, 5, 4, 0}));
    double volume = 0.0;
    for (const Tetrahedron& t : tetras) {
        EXPECT_GT(signed_volume(kCube, t), 0.0);
        volume += signed_volume(kCube, t);
    }
    EXPECT_NEAR(volume, 1.0, 1e-15);
}

TEST(TopologicalMapping, Hexa2TetraSwappingMirrorsEvenCellsAlongX) {
    // Cell 0 of a grid with 2 cells along x: its x edges swap (h1 h0 h3 h2 h5 h4 h7 h6), one swap
    // selects the mirrored pattern (0,5,6,1) (0,1,6,3) (1,3,2,6) (6,3,7,0) (6,7,5,0) (7,5,0,4).
    const auto tetras = tetrahedra_of_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}}, true, 2, 1);
    EXPECT_THAT(tetras, ElementsAre(Tetrahedron{1, 4, 7, 0}, Tetrahedron{1, 0, 7, 2}, Tetrahedron{0, 2, 3, 7},
                                    Tetrahedron{7, 2, 6, 1}, Tetrahedron{7, 6, 4, 1}, Tetrahedron{6, 4, 1, 5}));
    double volume = 0.0;
    for (const Tetrahedron& t : tetras) {
        EXPECT_GT(signed_volume(kCube, t), 0.0);
        volume += signed_volume(kCube, t);
    }
    EXPECT_NEAR(volume, 1.0, 1e-15);
    // Cell 1 (odd along x) is not swapped.
    EXPECT_EQ(tetrahedra_of_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}, {0, 1, 2, 3, 4, 5, 6, 7}}, true, 2, 1)[6],
              (Tetrahedron{0, 5, 1, 6}));
    EXPECT_THROW((void)tetrahedra_of_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}}, true, 0, 1), std::invalid_argument);
}

}  // namespace
