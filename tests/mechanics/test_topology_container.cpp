// TopologyContainer: the cross tables' consistency over random removals and additions (the
// removals and additions element by element: test_topology_removal.cpp, test_topology_addition.cpp).
#include "topology_container_checks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace penalty {
namespace {

using test_topology::tc_expect_consistent;

/// A cube of 5·n³ tetrahedra made of n³ cells (each cell 5 tetrahedra; neighbouring cells
/// mirrored so that faces match).
MeshTopology tc_tetrahedral_cube(int n) {
    auto id = [n](int x, int y, int z) { return PointId(x + (n + 1) * (y + (n + 1) * z)); };
    std::vector<Tetrahedron> tets;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                PointId v[8] = {id(x, y, z),     id(x + 1, y, z),     id(x + 1, y + 1, z),     id(x, y + 1, z),
                                id(x, y, z + 1), id(x + 1, y, z + 1), id(x + 1, y + 1, z + 1), id(x, y + 1, z + 1)};
                if ((x + y + z) % 2 == 0) {
                    tets.push_back({v[0], v[1], v[3], v[4]});
                    tets.push_back({v[1], v[2], v[3], v[6]});
                    tets.push_back({v[1], v[4], v[5], v[6]});
                    tets.push_back({v[3], v[4], v[6], v[7]});
                    tets.push_back({v[1], v[3], v[4], v[6]});
                } else {
                    tets.push_back({v[0], v[1], v[2], v[5]});
                    tets.push_back({v[0], v[2], v[3], v[7]});
                    tets.push_back({v[0], v[4], v[5], v[7]});
                    tets.push_back({v[2], v[5], v[6], v[7]});
                    tets.push_back({v[0], v[2], v[5], v[7]});
                }
            }
    // positively oriented (a face shared by two tetrahedra then runs both ways, as SOFA's meshes)
    const auto at = [n](PointId p) {
        const int k = int(p);
        return Vec3(k % (n + 1), (k / (n + 1)) % (n + 1), k / ((n + 1) * (n + 1)));
    };
    for (Tetrahedron& t : tets)
        if ((at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0])).dot(at(t[3]) - at(t[0])) < 0) std::swap(t[2], t[3]);
    MeshTopology m;
    m.set_tetrahedra(std::move(tets));
    return m;
}

TEST(TopologyContainer, RandomRemovalsAndAdditionsKeepEveryCrossTableConsistent) {
    MeshTopology mesh = tc_tetrahedral_cube(3);
    TopologyContainer c(mesh, ElementType::tetrahedron, "cube");
    tc_expect_consistent(c);
    std::mt19937 rng(51);
    std::vector<Tetrahedron> removed;
    int steps = 0;
    while (mesh.tetrahedra().size() > 3) {
        const std::size_t n = mesh.tetrahedra().size();
        std::vector<ElementId> pick;
        std::uniform_int_distribution<int> count(1, 4);
        for (int k = count(rng); k > 0; --k) {
            const auto i = ElementId(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng));
            if (std::find(pick.begin(), pick.end(), i) == pick.end()) pick.push_back(i);
        }
        // expected element list: SOFA's swap-and-pop, in decreasing order, of the tetrahedra alone
        std::vector<Tetrahedron> expected = mesh.tetrahedra();
        std::vector<ElementId> sorted = pick;
        std::sort(sorted.rbegin(), sorted.rend());
        for (const ElementId i : sorted) {
            expected[std::size_t(i)] = expected.back();
            expected.pop_back();
        }
        const std::size_t points_before = mesh.num_points();
        c.remove_tetrahedra(pick);
        if (mesh.num_points() == points_before) {
            EXPECT_EQ(mesh.tetrahedra(), expected);  // no point renamed
        }
        EXPECT_EQ(mesh.tetrahedra().size(), expected.size());
        tc_expect_consistent(c);
        if (++steps % 5 == 0 && mesh.num_points() >= 4) {  // add one back between existing points
            const auto p = PointId(mesh.num_points());
            c.add_points(1);
            c.add_tetrahedra({{0, 1, 2, PointId(p)}});
            tc_expect_consistent(c);
        }
    }
    EXPECT_GT(steps, 20);
}

}  // namespace
}  // namespace penalty
