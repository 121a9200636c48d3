// DiagonalMass under topological changes (diagonal_mass_changes.cpp, SOFA's DiagonalMass topology
// callbacks): a triangle's share ρ·area/3 added to or taken from each of its vertices and the total,
// a new point at mass 0, a removed point's mass out of the total by swap-and-pop, and the density
// recomputed from the vertex masses after a point change (initFromVertexMass). Two unit right
// triangles (area 1/2) at density 6: a share of 1 a vertex.
#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace penalty {
namespace {

TopologyChange mass_change(TopologyChangeKind kind, ElementType element, std::vector<ElementId> indices) {
    TopologyChange c;
    c.kind = kind;
    c.element = element;
    c.indices = std::move(indices);
    return c;
}

/// The square (0,0), (1,0), (1,1), (0,1) as triangles (0,1,2), (0,2,3), at density 6.
struct MassedSquare {
    MeshTopology mesh;
    Vec3Object state;
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<DiagonalMass> mass;
    MassedSquare() {
        mesh.set_triangles({{0, 1, 2}, {0, 2, 3}});
        state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
        state.init();
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "square");
        mass = std::make_unique<DiagonalMass>(state, mesh);
        mass->set_mass_density(6.0);
        mass->init();
    }
};

TEST(DiagonalMassChanges, ATrianglesShareComesAndGoesAtItsVertices) {
    MassedSquare s;
    ASSERT_EQ(s.mass->element_kind(), LumpedElementKind::triangle);
    EXPECT_EQ(s.mass->vertex_masses(), (std::vector<double>{2, 1, 2, 1}));
    EXPECT_EQ(s.mass->total_mass(), 6.0);
    // TrianglesRemoved {1} (sent while the triangle is still there): its vertices 0, 2, 3 lose 1
    const std::vector<TopologyChange> removed{mass_change(TopologyChangeKind::removed, ElementType::triangle, {1})};
    s.mass->handle_topology_changes(*s.container, removed);
    EXPECT_EQ(s.mass->vertex_masses(), (std::vector<double>{1, 1, 1, 0}));
    EXPECT_EQ(s.mass->total_mass(), 3.0);
    // TrianglesAdded of the same triangle: back
    const std::vector<TopologyChange> added{mass_change(TopologyChangeKind::added, ElementType::triangle, {1})};
    s.mass->handle_topology_changes(*s.container, added);
    EXPECT_EQ(s.mass->vertex_masses(), (std::vector<double>{2, 1, 2, 1}));
    EXPECT_EQ(s.mass->total_mass(), 6.0);
    // another element type (edges) is not the mass's
    const std::vector<TopologyChange> edges{mass_change(TopologyChangeKind::removed, ElementType::edge, {0})};
    s.mass->handle_topology_changes(*s.container, edges);
    EXPECT_EQ(s.mass->total_mass(), 6.0);
}

TEST(DiagonalMassChanges, PointsComeAtMassZeroAndLeaveBySwapAndPop) {
    MassedSquare s;
    // PointsAdded: mass 0
    const std::vector<TopologyChange> added{mass_change(TopologyChangeKind::added, ElementType::point, {4})};
    s.mass->handle_topology_changes(*s.container, added);
    EXPECT_EQ(s.mass->vertex_masses(), (std::vector<double>{2, 1, 2, 1, 0}));
    // PointsRemoved {0}: the last point's mass moves into slot 0, the total loses 2
    const std::vector<TopologyChange> removed{mass_change(TopologyChangeKind::removed, ElementType::point, {0})};
    s.mass->handle_topology_changes(*s.container, removed);
    EXPECT_EQ(s.mass->vertex_masses(), (std::vector<double>{0, 1, 2, 1}));
    EXPECT_EQ(s.mass->total_mass(), 4.0);
    // renumbered: new point k is old point indices[k]
    const std::vector<TopologyChange> renumbered{
        mass_change(TopologyChangeKind::renumbered, ElementType::point, {2, 0, 1, 3})};
    s.mass->handle_topology_changes(*s.container, renumbered);
    EXPECT_EQ(s.mass->vertex_masses(), (std::vector<double>{2, 0, 1, 1}));
    // after a point change the density is the total over the masses at density 1 (initFromVertexMass):
    // the square's lumped masses at density 1 sum to its area, 1
    s.mass->update_internal_data();
    EXPECT_EQ(s.mass->total_mass(), 4.0);
    EXPECT_NEAR(s.mass->mass_density(), 4.0, 1e-14);
}

}  // namespace
}  // namespace penalty
