// TriangularFEMForceField following a TopologyContainer as SOFA's triangleInfo TopologyData does
// (src/mechanics/topology/triangular_fem_changes.cpp): a removal swaps the last triangle's data into
// the removed slot, a new triangle's data comes from the rest positions at its addition, and a
// moved vertex changes no triangle's data. Each expectation is the data computed at a known time
// (the rest areas at creation), which a rebuild from the current rest positions would not give.
#include "penalty/mechanics/state_topology.hpp"
#include "penalty/mechanics/topology_container.hpp"
#include "penalty/mechanics/topology_followers.hpp"
#include "penalty/mechanics/triangular_fem.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace penalty {
namespace {

/// The 3 × 3-vertex square [0, 2]² cut into 8 triangles, a state on it, a dynamic container, and a
/// TriangularFEMForceField (large) following the container.
struct FemOnContainer {
    MeshTopology mesh;
    Vec3Object state;
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<StateTopologyFollower<Vec3Types>> follower;
    std::unique_ptr<TriangularFEMForceField> fem;
    std::unique_ptr<MemberTopologyHandler<TriangularFEMForceField>> handler;

    FemOnContainer() {
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) state.position.emplace_back(i, j, 0);
        // triangle 7 = (4, 8, 7) is the last one and has the centre 4
        mesh.set_triangles({{0, 1, 4}, {0, 4, 3}, {1, 2, 4}, {2, 5, 4}, {3, 4, 6}, {4, 7, 6}, {4, 5, 8}, {4, 8, 7}});
        state.init();
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "surface");
        follower = std::make_unique<StateTopologyFollower<Vec3Types>>(state);
        container->add_state_follower(*follower);
        fem = std::make_unique<TriangularFEMForceField>(state, container->mesh(), 1000.0, 0.3, FemMethod::Large);
        fem->init();
        handler = std::make_unique<MemberTopologyHandler<TriangularFEMForceField>>(*fem, *container);
        container->add_handler(*handler, {ElementType::triangle, ElementType::point});
    }
    /// Moves the centre (point 4) to 0.6·(1, 1) + 0.4·(1, 2) = (1, 1.4, 0), rest position included.
    void move_centre() { container->move_points({4}, {{4, 7}}, {{0.6, 0.4}}); }
};

TEST(TriangularFemChanges, RemovalSwapsTheLastTrianglesDataIntoTheSlot) {
    FemOnContainer f;
    f.move_centre();
    ASSERT_NEAR((f.state.rest_position[4] - Vec3(1, 1.4, 0)).norm(), 0.0, 1e-15);
    // every triangle keeps its rest shape of creation: ½ each
    for (const double a : f.fem->rest_areas()) EXPECT_DOUBLE_EQ(a, 0.5);
    f.container->remove_triangles({0}, false, false);
    ASSERT_EQ(f.fem->triangles().size(), 7U);
    EXPECT_EQ(f.fem->triangles(), f.container->mesh().triangles());
    EXPECT_EQ(f.fem->triangles()[0], (Triangle{4, 8, 7}));
    // slot 0 holds triangle 7's data of creation; from the moved centre its area would be 0.3
    EXPECT_DOUBLE_EQ(f.fem->rest_areas()[0], 0.5);
    for (const double a : f.fem->rest_areas()) EXPECT_DOUBLE_EQ(a, 0.5);
    // and a triangle built fresh on the moved rest positions has the moved shape
    TriangularFEMForceField fresh(f.state, f.container->mesh(), 1000.0, 0.3, FemMethod::Large);
    fresh.init();
    EXPECT_NEAR(fresh.rest_areas()[0], 0.3, 1e-15);
}

TEST(TriangularFemChanges, NewTriangleTakesTheRestShapeAtItsAddition) {
    FemOnContainer f;
    // a point at (2, 3, 0), then the triangle (7, 8, 9) on it: area ½·1·1
    f.container->add_points(1, {{7, 8}}, {{0.0, 1.0}});
    f.state.rest_position[9] = Vec3(2, 3, 0);
    f.container->add_triangles({{7, 8, 9}});
    ASSERT_EQ(f.fem->rest_areas().size(), 9U);
    EXPECT_DOUBLE_EQ(f.fem->rest_areas()[8], 0.5);
    // the rest position moves afterwards: the triangle keeps its shape of creation
    f.state.rest_position[9] = Vec3(2, 4, 0);
    f.container->remove_triangles({1}, false, false);
    EXPECT_EQ(f.fem->triangles()[1], (Triangle{7, 8, 9}));
    EXPECT_DOUBLE_EQ(f.fem->rest_areas()[1], 0.5);
    // a triangle added now takes the new rest positions: (6, 8, 9) with 9 at (2, 4): area 2
    f.container->add_triangles({{6, 8, 9}});
    EXPECT_DOUBLE_EQ(f.fem->rest_areas().back(), 2.0);
}

TEST(TriangularFemChanges, RemovedPointsRenameTheTrianglesVertices) {
    FemOnContainer f;
    // removing triangles 6 and 7 isolates point 8 (the last point): nothing renamed; removing
    // triangles 0 and 2 then isolates point 1, whose index the last point (7) takes
    f.container->remove_triangles({7, 6}, true, true);
    ASSERT_EQ(f.state.num_dofs(), 8U);
    f.container->remove_triangles({2, 0}, true, true);
    ASSERT_EQ(f.state.num_dofs(), 7U);
    EXPECT_EQ(f.fem->triangles(), f.container->mesh().triangles());
    ASSERT_EQ(f.fem->rest_areas().size(), 4U);
    // the forces are those of a fresh force field on the reduced mesh (nothing moved)
    for (std::size_t i = 0; i < f.state.num_dofs(); ++i)
        f.state.position[i] = f.state.rest_position[i] + Vec3(0.01 * double(i), -0.02 * double(i % 3), 0.005);
    TriangularFEMForceField fresh(f.state, f.container->mesh(), 1000.0, 0.3, FemMethod::Large);
    fresh.init();
    std::vector<Vec3> changed(f.state.num_dofs(), Vec3::Zero()), built(f.state.num_dofs(), Vec3::Zero());
    f.fem->add_force(changed, f.state.position, f.state.velocity);
    fresh.add_force(built, f.state.position, f.state.velocity);
    EXPECT_EQ(changed, built);
    EXPECT_NE(changed[0], Vec3::Zero());
}

}  // namespace
}  // namespace penalty
