// Mesh loaders on small files written for these tests, SOFA's loader post-processing, and every
// malformed case with its exact message.

#include "io_test_util.hpp"

#include "penalty/io/mesh.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penalty::io {
namespace {

using test::data_dir;
using test::mesh_file;
using test::message_of;
using test::write_temp;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// ---------------------------------------------------------------------------------------------
// OBJ

TEST(ObjLoader, ReadsPointsFacesQuadsPolygonsAndLines) {
    const MeshData m = load_obj(mesh_file("tetra.obj"));
    ASSERT_EQ(m.positions.size(), 5u);
    EXPECT_EQ(m.positions[1], Vec3(1, 0, 0));
    EXPECT_EQ(m.positions[4], Vec3(1, 1, 1));  // the 4th coordinate (w) is ignored
    // triangle, then the pentagon given with negative indices -5 -3 -2 -1 -4 = 0 2 3 4 1 as a fan
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}, Triangle{0, 2, 3}, Triangle{0, 3, 4}, Triangle{0, 4, 1}));
    EXPECT_THAT(m.quads, ElementsAre(Quad{0, 1, 3, 4}));
    EXPECT_THAT(m.edges, ElementsAre(Edge{1, 2}));  // "l 3 2", stored sorted
    EXPECT_TRUE(m.tetrahedra.empty());
    EXPECT_TRUE(m.radii.empty());
}

TEST(ObjLoader, TriangulateFansQuadsInFileOrder) {
    const MeshData m = load_obj(mesh_file("tetra.obj"), /*triangulate=*/true);
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}, Triangle{0, 1, 3}, Triangle{0, 3, 4}, Triangle{0, 2, 3},
                                         Triangle{0, 3, 4}, Triangle{0, 4, 1}));
    EXPECT_TRUE(m.quads.empty());
}

TEST(ObjLoader, IndicesMayReferToLaterVertices) {
    const auto p = write_temp("forward.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    const MeshData m = load_obj(p);
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}));
}

TEST(ObjLoader, MissingFile) {
    const auto p = data_dir() / "mesh" / "no_such_file.obj";
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }), p.string() + ": cannot read: the path does not exist");
}

TEST(ObjLoader, BadNumber) {
    const auto p = write_temp("bad_number.obj", "v 0 0 0\nv 1 abc 0\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":2: expected a vertex coordinate (a number), found 'abc'");
}

TEST(ObjLoader, NotFiniteNumber) {
    const auto p = write_temp("nan.obj", "v 0 nan 0\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":1: expected a vertex coordinate (a number), found 'nan'");
}

TEST(ObjLoader, TruncatedVertex) {
    const auto p = write_temp("short_vertex.obj", "# c\nv 0 0");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":2: vertex needs 3 coordinates, found 2");
}

TEST(ObjLoader, FaceIndexOutOfRange) {
    const auto p = write_temp("out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":4: vertex index 7 out of range (3 vertices)");
}

TEST(ObjLoader, FaceIndexZero) {
    const auto p = write_temp("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":4: vertex index 0 is invalid (OBJ indices start at 1)");
}

TEST(ObjLoader, RelativeIndexBeforeFirstVertex) {
    const auto p = write_temp("relative.obj", "v 0 0 0\nf -1 -2 -3\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":2: relative vertex index -2 goes before the first vertex");
}

TEST(ObjLoader, BadFaceToken) {
    const auto p = write_temp("bad_face.obj", "v 0 0 0\nf 1 x/2 3\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":2: expected a vertex index, found 'x/2'");
}

TEST(ObjLoader, FaceWithOneVertex) {
    const auto p = write_temp("one.obj", "v 0 0 0\nf 1\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_obj(p); }),
              p.string() + ":2: face needs at least 2 vertices, found 1");
}

// ---------------------------------------------------------------------------------------------
// SPH

TEST(SphLoader, ReadsCentersAndRadii) {
    const MeshData m = load_sph(mesh_file("spheres.sph"));
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_EQ(m.positions[2], Vec3(0, 2, 0));
    EXPECT_THAT(m.radii, ElementsAre(0.5, 0.25, 1.0));
}

TEST(SphLoader, BadHeader) {
    const auto p = write_temp("bad_header.sph", "spheres 1.0\nsphe 1 0 0 0 1\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_sph(p); }),
              p.string() + ":1: not a sphere file (first line must be 'sph 1.0')");
}

TEST(SphLoader, BadRadius) {
    const auto p = write_temp("bad_radius.sph", "sph 1.0\nnums 1\nsphe 1 0 0 0 big\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_sph(p); }),
              p.string() + ":3: expected sphere radius (a number), found 'big'");
}

TEST(SphLoader, NegativeRadius) {
    const auto p = write_temp("negative_radius.sph", "sph 1.0\nsphe 1 0 0 0 -0.5\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_sph(p); }), p.string() + ":2: negative sphere radius -0.5");
}

TEST(SphLoader, TruncatedRecord) {
    const auto p = write_temp("truncated.sph", "sph 1.0\nsphe 1 0 0");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_sph(p); }),
              p.string() + ":2: unexpected end of file (expected sphere center coordinate)");
}

TEST(SphLoader, HugeCount) {
    const auto p = write_temp("huge.sph", "sph 1.0\nnums 1000000000000\nsphe 1 0 0 0 1\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_sph(p); }),
              p.string() + ":2: sphere count 1000000000000 exceeds what the file can hold");
}

// ---------------------------------------------------------------------------------------------
// legacy VTK

TEST(VtkLoader, PolyData) {
    const MeshData m = load_vtk_legacy(mesh_file("poly.vtk"));
    ASSERT_EQ(m.positions.size(), 5u);
    EXPECT_EQ(m.positions[4], Vec3(0.5, 0.5, 1));
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 4}));
    EXPECT_THAT(m.quads, ElementsAre(Quad{0, 1, 2, 3}));
    EXPECT_THAT(m.edges, ElementsAre(Edge{0, 1}, Edge{1, 2}));
}

TEST(VtkLoader, UnstructuredGrid) {
    const MeshData m = load_vtk_legacy(mesh_file("grid.vtk"));
    ASSERT_EQ(m.positions.size(), 9u);
    EXPECT_THAT(m.hexahedra, ElementsAre(Hexahedron{0, 1, 2, 3, 4, 5, 6, 7}));
    EXPECT_THAT(m.tetrahedra, ElementsAre(Tetrahedron{1, 8, 2, 5}));
    EXPECT_TRUE(m.triangles.empty());
}

const char* const kVtkHead =
    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n";

TEST(VtkLoader, IndexOutOfRange) {
    const auto p = write_temp("out_of_range.vtk", std::string(kVtkHead) + "POLYGONS 1 4\n3 0 1 7\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_vtk_legacy(p); }),
              p.string() + ":8: point index 7 out of range (3 points)");
}

TEST(VtkLoader, Binary) {
    const auto p = write_temp("binary.vtk", "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_vtk_legacy(p); }),
              p.string() + ":3: only ASCII legacy VTK files are supported, found 'BINARY'");
}

TEST(VtkLoader, SizeMismatch) {
    const auto p = write_temp("size.vtk", std::string(kVtkHead) + "POLYGONS 1 5\n3 0 1 2\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_vtk_legacy(p); }),
              p.string() + ":7: POLYGONS list size 5 does not match its content (4 numbers)");
}

TEST(VtkLoader, UnsupportedCellType) {
    const auto p = write_temp("wedge.vtk",
                              "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n"
                              "0 0 0 1 0 0 0 1 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n13\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_vtk_legacy(p); }),
              p.string() + ":10: VTK cell type 13 is not supported");
}

TEST(VtkLoader, Truncated) {
    const auto p = write_temp(
        "truncated.vtk",
        "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1.000000 0 0 0 1.0000\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_vtk_legacy(p); }),
              p.string() + ":6: unexpected end of file (expected point coordinate)");
}

TEST(MeshFile, DispatchesOnExtension) {
    EXPECT_EQ(load_mesh_file(mesh_file("spheres.sph")).radii.size(), 3u);
    EXPECT_EQ(load_mesh_file(mesh_file("grid.vtk")).hexahedra.size(), 1u);
    const auto p = write_temp("mesh.stl", "solid\n");
    EXPECT_EQ(
        message_of<LoadError>([&] { (void)load_mesh_file(p); }),
        p.string() + ": unknown mesh file extension '.stl' (expected .obj, .msh, .sph, .vtk, .vtu, .off or .trian)");
}

// ---------------------------------------------------------------------------------------------
// transforms

// SOFA's quaternion from Euler angles (default order), written from its formula, as a reference.
Mat3 sofa_reference_rotation(const Vec3& degrees) {
    const Vec3 a = degrees * (std::numbers::pi / 180.0);
    const double c1 = std::cos(a[0] / 2), c2 = std::cos(a[1] / 2), c3 = std::cos(a[2] / 2);
    const double s1 = std::sin(a[0] / 2), s2 = std::sin(a[1] / 2), s3 = std::sin(a[2] / 2);
    const Quat q(c1 * c2 * c3 + s1 * s2 * s3,   // w
                 s1 * c2 * c3 - c1 * s2 * s3,   // x
                 c1 * s2 * c3 + s1 * c2 * s3,   // y
                 c1 * c2 * s3 - s1 * s2 * c3);  // z
    return q.toRotationMatrix();
}

TEST(Transform, EulerAnglesFollowSofaOrder) {
    // x is applied first: (0,1,0) -Rx(90)-> (0,0,1) -Ry(90)-> (1,0,0)
    const auto rotated = [](const Vec3& angles, const Vec3& p) {
        std::vector<Vec3> points{p};
        apply_transform(points, Vec3::Zero(), angles, Vec3::Ones(), LoaderKind::sphere_loader);
        return points[0];
    };
    EXPECT_LT((rotated(Vec3(90, 90, 0), Vec3(0, 1, 0)) - Vec3(1, 0, 0)).norm(), 1e-15);
    for (const Vec3& angles : {Vec3(33, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 64), Vec3(180, 0, 0), Vec3(12, -47, 131)}) {
        const Mat3 reference = sofa_reference_rotation(angles);
        for (int c = 0; c < 3; ++c)
            EXPECT_LT((rotated(angles, Vec3::Unit(c)) - reference.col(c)).norm(), 1e-15) << angles.transpose();
    }
}

TEST(Transform, ScaleThenRotateThenTranslate) {
    MeshData m;
    m.positions = {Vec3(1, 1, 1), Vec3(0, 0, 0)};
    m.radii = {0.5, 0.5};
    apply_transform(m, Vec3(1, 1, 1), Vec3(0, 0, 90), Vec3(2, 3, 4));
    // (1,1,1) -scale-> (2,3,4) -Rz(90)-> (-3,2,4) -translate-> (-2,3,5)
    EXPECT_LT((m.positions[0] - Vec3(-2, 3, 5)).norm(), 1e-15);
    EXPECT_EQ(m.positions[1], Vec3(1, 1, 1));
    EXPECT_THAT(m.radii, ElementsAre(0.5, 0.5));  // radii are not scaled (as SOFA's SphereLoader)
}

TEST(Transform, IdentityLeavesPointsBitIdentical) {
    std::vector<Vec3> p{Vec3(0.1, 0.2, 0.3)};
    apply_transform(p, Vec3::Zero(), Vec3::Zero(), Vec3::Ones());
    EXPECT_EQ(p[0], Vec3(0.1, 0.2, 0.3));
}

TEST(PostProcessing, TriangulateAndFlip) {
    MeshData m;
    m.triangles = {Triangle{0, 1, 2}};
    m.quads = {Quad{3, 4, 5, 6}};
    flip_normals(m);
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{2, 1, 0}));
    EXPECT_THAT(m.quads, ElementsAre(Quad{6, 5, 4, 3}));
    triangulate_quads(m);
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{2, 1, 0}, Triangle{6, 5, 4}, Triangle{6, 4, 3}));
    EXPECT_TRUE(m.quads.empty());
}

// ---------------------------------------------------------------------------------------------
// OFF and Trian (SOFA's MeshOffLoader::readOFF, MeshTrianLoader::readTrian)

TEST(OffLoader, TrianglesQuadsCommentsAndSkippedFaces) {
    // a pentagon face (n = 5) is skipped and not counted: the 3 faces are the 3 others
    const auto p = write_temp("mesh.off",
                              "OFF\n# a comment\n\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n# inside\n0 1 0\n0.5 2 0\n"
                              "3 0 1 2\n5 0 1 2 3 4\n4 0 1 2 3\n3 2 4 3\n");
    const MeshData m = load_off(p);
    ASSERT_EQ(m.positions.size(), 5u);
    EXPECT_EQ(m.positions[4], Vec3(0.5, 2, 0));
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}, Triangle{2, 4, 3}));
    EXPECT_THAT(m.quads, ElementsAre(Quad{0, 1, 2, 3}));
}

TEST(OffLoader, Errors) {
    const auto not_off = write_temp("not.off", "COFF\n1 0 0\n0 0 0\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_off(not_off); }),
              not_off.string() + ":1: not an OFF file (the first word must be OFF)");
    const auto bad_index = write_temp("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_off(bad_index); }),
              bad_index.string() + ":6: face vertex 3 is not one of the 3 points");
    const auto short_file = write_temp("short.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_THAT(message_of<LoadError>([&] { (void)load_off(short_file); }),
                ::testing::HasSubstr("unexpected end of file"));
}

TEST(TrianLoader, PointsAndTrianglesNeighboursIgnored) {
    const auto p = write_temp("mesh.trian", "4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2\n0 1 2 -1 1 -1\n0 2 3 -1 -1 0\n");
    const MeshData m = load_trian(p);
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}, Triangle{0, 2, 3}));
    const auto bad = write_temp("bad.trian", "1\n0 0 0\n1\n0 0 1 -1 -1 -1\n");
    EXPECT_EQ(message_of<LoadError>([&] { (void)load_trian(bad); }),
              bad.string() + ":4: triangle point 1 is not one of the 1 points");
}

}  // namespace
}  // namespace penalty::io
