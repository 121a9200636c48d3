// MeshOBJLoader handleSeams (io::parse_obj's handle_seams): SOFA's MeshOBJLoader::readOBJ splits a
// point per distinct (texture coordinate, normal) pair of its corners and drops unused points.
#include "penalty/io/mesh.hpp"

#include <gtest/gtest.h>

namespace {

using namespace penalty;
using namespace penalty::io;

TEST(ObjSeams, WithoutTextureOrNormalIndicesOnlyUnusedPointsAreDropped) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\nv 1 1 0\nf 1 2 5 4\n";
    const MeshData plain = parse_obj(text, "plain.obj");
    ASSERT_EQ(plain.positions.size(), 5u);
    const MeshData seams = parse_obj(text, "seams.obj", false, /*handle_seams=*/true);
    ASSERT_EQ(seams.positions.size(), 4u);  // point 3 (9 9 9) is used by no face
    EXPECT_EQ(seams.positions[2], Vec3(0, 1, 0));
    ASSERT_EQ(seams.quads.size(), 1u);
    EXPECT_EQ(seams.quads[0], (Quad{0, 1, 3, 2}));
    // every point used: the same points and elements as without handleSeams
    const std::string all_used = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    EXPECT_EQ(parse_obj(all_used, "a.obj", false, true).positions, parse_obj(all_used, "a.obj").positions);
    EXPECT_EQ(parse_obj(all_used, "a.obj", false, true).triangles, parse_obj(all_used, "a.obj").triangles);
}

TEST(ObjSeams, PointsSplitPerTextureAndNormalPairInPairOrder) {
    // two triangles sharing the edge 1–3; point 1 has texture coordinates 2 and 1 in them, point 3
    // has normal 1 in both (one vertex); point 2 only in the first, point 4 only in the second
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
        "vt 0 0\nvt 1 0\nvt 0 1\n"
        "vn 0 0 1\n"
        "f 1/2/1 2/2/1 3/3/1\n"
        "f 1/1/1 3/3/1 4//1\n";
    const MeshData m = parse_obj(text, "seams.obj", false, true);
    // point 1 → (vt 0, vn 0) then (vt 1, vn 0); point 2; point 3; point 4 → (−1, vn 0)
    ASSERT_EQ(m.positions.size(), 5u);
    EXPECT_EQ(m.positions[0], Vec3(0, 0, 0));
    EXPECT_EQ(m.positions[1], Vec3(0, 0, 0));
    EXPECT_EQ(m.positions[2], Vec3(1, 0, 0));
    EXPECT_EQ(m.positions[3], Vec3(0, 1, 0));
    EXPECT_EQ(m.positions[4], Vec3(1, 1, 0));
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0], (Triangle{1, 2, 3}));
    EXPECT_EQ(m.triangles[1], (Triangle{0, 3, 4}));
    // negative indices count back from the vt / vn lines read so far
    const MeshData relative =
        parse_obj(text.substr(0, text.find("f 1/2")) + "f 1/-2/-1 2/-2/-1 3/-1/-1\n", "r.obj", false, true);
    EXPECT_EQ(relative.positions.size(), 3u);
}

}  // namespace
