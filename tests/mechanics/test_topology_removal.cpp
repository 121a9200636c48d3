// TopologyContainer's removals (topology_removal.cpp, SOFA's ...SetTopologyModifier::
// remove...Process): swap-and-pop, the isolated lower elements and points, the event lists and
// their order, element by element against hand-derived expectations; the checks before anything
// changes.
#include "topology_container_checks.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace penalty {
namespace {

using test_topology::Ids;
using test_topology::tc_expect_consistent;
using test_topology::TcRecorder;

TEST(TopologyContainer, RemovingATriangleSwapsTheLastInAndRemovesItsIsolatedEdgesAndPoint) {
    MeshTopology mesh;
    mesh.set_triangles({{0, 1, 2}, {1, 3, 2}});
    // derived edges (first occurrence, triangle orientation): (1,2) (2,0) (0,1) (3,2) (1,3)
    ASSERT_EQ(mesh.edges(), (std::vector<Edge>{{1, 2}, {2, 0}, {0, 1}, {3, 2}, {1, 3}}));
    TopologyContainer c(mesh, ElementType::triangle, "surface");
    std::vector<std::string> log;
    TcRecorder handler("h", log), listener("l", log), state("s", log);
    c.add_handler(handler, {ElementType::triangle, ElementType::point});
    c.add_listener(listener);
    c.add_state_follower(state);
    const auto revision = mesh.revision();

    c.remove_triangles({0});

    // triangle 1 moved into slot 0; edges (0,1) and (2,0) lost their only triangle (removed in
    // decreasing order: edge 2 takes the last edge (1,3), then edge 1 takes (3,2)); point 0 lost its
    // only triangle and takes point 3.
    EXPECT_EQ(mesh.num_points(), 3u);
    EXPECT_EQ(mesh.triangles(), (std::vector<Triangle>{{1, 0, 2}}));
    EXPECT_EQ(mesh.edges(), (std::vector<Edge>{{1, 2}, {0, 2}, {1, 0}}));
    EXPECT_EQ(mesh.edges_in_triangle()[0], (std::array<std::int32_t, 3>{1, 0, 2}));
    EXPECT_EQ(mesh.edges_around_vertex()[0], (Ids{1, 2}));
    EXPECT_EQ(mesh.edges_around_vertex()[1], (Ids{0, 2}));
    EXPECT_EQ(mesh.edges_around_vertex()[2], (Ids{0, 1}));
    EXPECT_EQ(mesh.vertices_around_vertex()[0], (std::vector<PointId>{2, 1}));
    EXPECT_GT(mesh.revision(), revision);
    tc_expect_consistent(c);
    // Three propagations: triangles (handler on its triangle phase), edges (not registered: only
    // the listener), points (handler on its point phase, then the listener, then the state).
    EXPECT_EQ(log, (std::vector<std::string>{"h:removed triangles 0", "h:ending", "l:removed triangles 0", "l:ending",
                                             "l:removed edges 2 1", "l:ending", "h:removed points 0", "h:ending",
                                             "l:removed points 0", "l:ending", "s:removed points 0"}));
}

TEST(TopologyContainer, RemovingOneOfTwoTetrahedraRemovesItsOwnFacesEdgesAndApex) {
    MeshTopology mesh;
    mesh.set_tetrahedra({{0, 1, 2, 3}, {1, 2, 3, 4}});
    ASSERT_EQ(mesh.triangles().size(), 7u);
    ASSERT_EQ(mesh.edges().size(), 9u);
    TopologyContainer c(mesh, ElementType::tetrahedron, "volume");
    tc_expect_consistent(c);
    std::vector<std::string> log;
    TcRecorder listener("l", log);
    c.add_listener(listener);

    c.remove_tetrahedra({0});

    EXPECT_EQ(mesh.tetrahedra(), (std::vector<Tetrahedron>{{1, 2, 3, 0}}));  // point 4 took point 0's slot
    EXPECT_EQ(mesh.num_points(), 4u);
    EXPECT_EQ(mesh.triangles().size(), 4u);
    EXPECT_EQ(mesh.edges().size(), 6u);
    tc_expect_consistent(c);
    // one propagation for the tetrahedron, one for its 3 own faces and 3 own edges, one for point 0
    ASSERT_EQ(log.size(), 7u);
    EXPECT_EQ(log[0], "l:removed tetrahedra 0");
    EXPECT_EQ(log[2].rfind("l:removed triangles", 0), 0u);
    EXPECT_EQ(log[3].rfind("l:removed edges", 0), 0u);
    EXPECT_EQ(log[5], "l:removed points 0");
}

TEST(TopologyContainer, RemovalChecksEveryIndexBeforeChangingAnything) {
    MeshTopology mesh;
    mesh.set_tetrahedra({{0, 1, 2, 3}, {1, 2, 3, 4}});
    TopologyContainer c(mesh, ElementType::tetrahedron, "volume");
    EXPECT_THROW(c.remove_tetrahedra({1, 2}), std::invalid_argument);
    EXPECT_THROW(c.remove_tetrahedra({1, 1}), std::invalid_argument);
    EXPECT_THROW(c.remove_tetrahedra({-1}), std::invalid_argument);
    EXPECT_THROW(c.remove_quads({0}), std::invalid_argument);  // a tetrahedron container has no quads
    EXPECT_EQ(mesh.tetrahedra().size(), 2u);
    EXPECT_EQ(mesh.revision(), 0u);
    try {
        c.remove_tetrahedra({0, 7});
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("tetrahedra 7"), std::string::npos) << e.what();
    }
}

TEST(TopologyContainer, StatesFollowPointRemovalBySwapAndPop) {
    MeshTopology mesh;
    mesh.set_edges({{0, 1}, {2, 3}, {3, 4}});
    TopologyContainer c(mesh, ElementType::edge, "wire");
    Vec3Object state;
    for (int i = 0; i < 5; ++i) state.position.push_back(Vec3(i, 0, 0));
    state.init();
    for (int i = 0; i < 5; ++i) state.velocity[std::size_t(i)] = Vec3(0, i, 0);
    StateTopologyFollower<Vec3Types> follower(state);
    c.add_state_follower(follower);
    c.remove_edges({0});  // points 0 and 1 are isolated: removed as {1, 0}
    // point 1 takes point 4, then point 0 takes point 3
    ASSERT_EQ(state.position.size(), 3u);
    EXPECT_EQ(state.position[0], Vec3(3, 0, 0));
    EXPECT_EQ(state.position[1], Vec3(4, 0, 0));
    EXPECT_EQ(state.position[2], Vec3(2, 0, 0));
    EXPECT_EQ(state.velocity[1], Vec3(0, 4, 0));
    EXPECT_EQ(state.dx.size(), 3u);
    EXPECT_EQ(mesh.edges(), (std::vector<Edge>{{0, 1}, {2, 0}}));  // (3,4) moved into slot 0, renamed
}

TEST(TopologyRemoval, AQuadRemovedWithoutItsIsolatedItemsLeavesItsEdgesAndPoints) {
    // two quads sharing the side (1,2): removing quad 0 with remove_isolated_edges and
    // remove_isolated_points off moves quad 1 into slot 0 and keeps all 7 edges and 6 points;
    // with them on, the edges (0,1), (3,0) and (2,3) and the points 0 and 3 go
    for (const bool isolated : {false, true}) {
        MeshTopology mesh;
        mesh.set_quads({{0, 1, 2, 3}, {1, 4, 5, 2}});
        TopologyContainer c(mesh, ElementType::quad, "strip");
        ASSERT_EQ(mesh.edges().size(), 7u);
        c.remove_quads({0}, isolated, isolated);
        EXPECT_EQ(mesh.quads().size(), 1u) << isolated;
        EXPECT_EQ(mesh.edges().size(), isolated ? 4u : 7u) << isolated;
        EXPECT_EQ(mesh.num_points(), isolated ? 4u : 6u) << isolated;
        if (!isolated) {
            EXPECT_EQ(mesh.quads()[0], (Quad{1, 4, 5, 2}));
            continue;
        }
        // every remaining edge is a side of the remaining quad when the isolated ones went
        for (const Edge& e : mesh.edges()) {
            const Quad& q = mesh.quads()[0];
            int sides = 0;
            for (int j = 0; j < 4; ++j) {
                const PointId a = q[std::size_t(j)], b = q[std::size_t((j + 1) % 4)];
                sides += (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a) ? 1 : 0;
            }
            EXPECT_EQ(sides, 1) << e[0] << "-" << e[1];
        }
    }
}

TEST(TopologyRemoval, RemovingPointsRenamesTheLastIntoTheirSlotsInDecreasingOrder) {
    // an edge container of 5 points, edges (0,1) and (3,4); removing the free point 2 moves
    // point 4 into slot 2: the edge (3,4) becomes (3,2); the event names point 2
    MeshTopology mesh;
    mesh.set_edges({{0, 1}, {3, 4}});
    TopologyContainer c(mesh, ElementType::edge, "wire");
    std::vector<std::string> log;
    TcRecorder listener("l", log);
    c.add_listener(listener);
    c.remove_points({2});
    EXPECT_EQ(mesh.num_points(), 4u);
    EXPECT_EQ(mesh.edges(), (std::vector<Edge>{{0, 1}, {3, 2}}));
    ASSERT_EQ(mesh.edges_around_vertex().size(), 4u);
    EXPECT_EQ(mesh.edges_around_vertex()[2], (Ids{1}));
    EXPECT_EQ(mesh.edges_around_vertex()[3], (Ids{1}));
    EXPECT_EQ(mesh.edges_around_vertex()[0], (Ids{0}));
    EXPECT_EQ(log, (std::vector<std::string>{"l:removed points 2", "l:ending"}));
    tc_expect_consistent(c);  // every table one entry per point, the triangle ones too
}

}  // namespace
}  // namespace penalty
