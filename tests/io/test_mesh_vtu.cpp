// The VTK XML UnstructuredGrid loader (io/mesh_vtu.cpp): cells read, binary DataArrays refused.

#include "io_test_util.hpp"

#include "penalty/io/mesh.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penalty::io {
namespace {

using test::message_of;
using test::vtu_text;
using test::write_temp;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(VtuLoader, ReadsPointsAndCellsOfAnUnstructuredGrid) {
    // a tetrahedron (10) and a triangle (5) on 4 points; points as doubles whatever their type
    const auto p =
        write_temp("cells.vtu", vtu_text("0 0 0  1 0 0  0 1 0  0 0 0.1", 4, "0 1 2 3  0 1 2", "4 7", "10 5", 2));
    const MeshData m = load_vtk(p);  // XML by the first line, as MeshVTKLoader::detectFileType
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.positions[3], Vec3(0, 0, 0.1));
    EXPECT_THAT(m.tetrahedra, ElementsAre(Tetrahedron{0, 1, 2, 3}));
    EXPECT_THAT(m.triangles, ElementsAre(Triangle{0, 1, 2}));
    EXPECT_EQ(load_mesh_file(p).tetrahedra.size(), 1u);
}

TEST(VtuLoader, ErrorsNameTheFileAndLine) {
    const auto binary = write_temp("binary.vtu", vtu_text("AAAA", 1, "", "", "", 0, "binary"));
    EXPECT_THAT(message_of<LoadError>([&] { (void)load_vtk(binary); }),
                HasSubstr("binary.vtu:5: Points: only ASCII DataArrays are read"));
    const auto out_of_range = write_temp("range.vtu", vtu_text("0 0 0  1 0 0  0 1 0", 3, "0 1 7", "3", "5", 1));
    EXPECT_THAT(message_of<LoadError>([&] { (void)load_vtk(out_of_range); }),
                HasSubstr("range.vtu:7: point index 7.000000 is not an integer in [0, 3)"));
    const auto short_points = write_temp("short.vtu", vtu_text("0 0 0  1 0", 2, "", "", "", 0));
    EXPECT_THAT(message_of<LoadError>([&] { (void)load_vtk(short_points); }),
                HasSubstr("short.vtu:5: Points: expected 6 numbers, found 5"));
    const auto not_grid = write_temp("poly.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"></VTKFile>\n");
    EXPECT_THAT(message_of<LoadError>([&] { (void)load_vtk(not_grid); }),
                HasSubstr("poly.vtu:2: VTK XML dataset 'PolyData' is not supported (UnstructuredGrid)"));
}

}  // namespace
}  // namespace penalty::io
