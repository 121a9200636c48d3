// CarvingManager (scene/topology/carving_manager.cpp): a sphere tool carves exactly the tetrahedra of
// the triangles within its reach.
#include "topological_change_scenes.hpp"

namespace penalty {
namespace {

using namespace test_topology_scenes;

TEST(TopologicalChanges, ASphereToolCarvesExactlyTheTetrahedraOfTheTrianglesWithinItsReach) {
    const test::TetraCube cube = test::tetra_cube(3, 0.3);  // top face at y = 0.3
    // two spheres within reach (distance 0.025 < radius 0.02 + contact distance 0.01: value < 0 =
    // carvingDistance), two within the alarm distance only (0.035: value 0.005 > 0), each above a
    // triangle's interior
    const double r = 0.02;
    const std::vector<Vec3> tool{Vec3(0.045, 0.325, 0.02), Vec3(0.23, 0.325, 0.115), Vec3(0.12, 0.335, 0.225),
                                 Vec3(0.255, 0.335, 0.23)};
    auto s = build(tchg_carving_scene(cube, tool, r, 0.0));
    const MeshTopology& border = s->topology_container("border").mesh();
    const Vec3Object& x = tchg_state(*s);
    // expected: the tetrahedron under each sphere within reach (the one holding the top face
    // triangle under its centre)
    std::set<std::array<PointId, 4>> expected = tchg_sorted(cube.tetrahedra, cube.points, cube.points);
    for (std::size_t k = 0; k < 2; ++k) {
        const Vec3& c = tool[k];
        int found = 0;
        for (const Triangle& t : border.triangles()) {
            const Vec3 a = x.position[std::size_t(t[0])], b = x.position[std::size_t(t[1])],
                       d = x.position[std::size_t(t[2])];
            if (std::abs(a.y() - 0.3) > 1e-12 || std::abs(b.y() - 0.3) > 1e-12 || std::abs(d.y() - 0.3) > 1e-12)
                continue;
            // barycentric coordinates of (c.x, c.z) in the triangle's xz projection
            const double det = (b.x() - a.x()) * (d.z() - a.z()) - (d.x() - a.x()) * (b.z() - a.z());
            const double u = ((c.x() - a.x()) * (d.z() - a.z()) - (d.x() - a.x()) * (c.z() - a.z())) / det;
            const double v = ((b.x() - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (b.z() - a.z())) / det;
            if (u <= 0 || v <= 0 || u + v >= 1) continue;
            ++found;
            const std::set<PointId> face(t.begin(), t.end());
            for (const Tetrahedron& tet : cube.tetrahedra) {
                std::array<PointId, 4> key = tet;
                std::sort(key.begin(), key.end());
                if (std::includes(key.begin(), key.end(), face.begin(), face.end())) expected.erase(key);
            }
        }
        ASSERT_EQ(found, 1) << "sphere " << k << " is not above one triangle's interior";
    }
    ASSERT_EQ(expected.size(), cube.tetrahedra.size() - 2);
    s->step();  // detection at the step's start, carving at its end
    const Vec3Object& y = tchg_state(*s);
    EXPECT_EQ(tchg_sorted(s->topology_container("volume").mesh().tetrahedra(), y.rest_position, cube.points), expected);
}

}  // namespace
}  // namespace penalty
