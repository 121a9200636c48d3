// The points an incision adds and moves (topology_point_moves.cpp): SOFA's
// PointSetTopologyModifier::addPoints(n, srcElems) (a point placed in an edge or a triangle, its
// state values weighted from the element's vertices) and TriangleSetTopologyModifier::
// movePointsProcess (the states' values of moved points from their ancestors, a "moved" event to
// the states only), with the checks naming the container.
#include "topology_container_checks.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace penalty {
namespace {

using test_topology::TcRecorder;

/// The triangle (0,0,0), (4,0,0), (0,2,0) as a container and a state following it.
struct PointMovesTriangle {
    MeshTopology mesh;
    Vec3Object state;
    std::unique_ptr<TopologyContainer> container;
    std::unique_ptr<StateTopologyFollower<Vec3Types>> follower;
    PointMovesTriangle() {
        mesh.set_triangles({{0, 1, 2}});
        container = std::make_unique<TopologyContainer>(mesh, ElementType::triangle, "cut");
        state.position = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 2, 0)};
        state.init();
        for (std::size_t i = 0; i < 3; ++i) state.velocity[i] = Vec3(double(i), 0, 1);
        follower = std::make_unique<StateTopologyFollower<Vec3Types>>(state);
        container->add_state_follower(*follower);
    }
};

std::string point_moves_error(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

TEST(TopologyPointMoves, PointsAddedInAnEdgeAndATriangleTakeTheirWeightedPlaces) {
    // a point at 0.25 along the edge (0 → 1): 0.75·p0 + 0.25·p1 = (1,0,0); a point at local
    // (0.5, 0.25) in the triangle: 0.25·p0 + 0.5·p1 + 0.25·p2 = (2, 0.5, 0)
    PointMovesTriangle t;
    std::vector<std::string> log;
    TcRecorder handler("h", log);
    t.container->add_handler(handler, {ElementType::point});
    t.container->add_points({PointAncestorElement{ElementType::edge, {0, 1, 0}, {0.25, 0, 0}},
                             PointAncestorElement{ElementType::triangle, {0, 1, 2}, {0.5, 0.25, 0}}});
    ASSERT_EQ(t.state.position.size(), 5u);
    EXPECT_EQ(t.state.position[3], Vec3(1, 0, 0));
    EXPECT_EQ(t.state.position[4], Vec3(2, 0.5, 0));
    // velocities weighted the same way: 0.75·(0,0,1) + 0.25·(1,0,1), 0.25·v0 + 0.5·v1 + 0.25·v2
    EXPECT_EQ(t.state.velocity[3], Vec3(0.25, 0, 1));
    EXPECT_EQ(t.state.velocity[4], Vec3(1.0, 0, 1));
    EXPECT_EQ(t.mesh.num_points(), 5u);
    EXPECT_EQ(log, (std::vector<std::string>{"h:added points 3 4", "h:ending"}));
}

TEST(TopologyPointMoves, MovedPointsTakeTheirAncestorsWeightedValuesAndOnlyTheStatesHear) {
    // point 2 moved to 0.5·p0 + 0.5·p1 = (2,0,0): the states change, the topology data are not
    // told (SOFA's data ignore TrianglesMoved), the listeners neither
    PointMovesTriangle t;
    std::vector<std::string> log;
    TcRecorder handler("h", log), listener("l", log), state("s", log);
    t.container->add_handler(handler, {ElementType::point, ElementType::triangle});
    t.container->add_listener(listener);
    t.container->add_state_follower(state);
    const auto triangles = t.mesh.triangles();
    t.container->move_points({2}, {{0, 1}}, {{0.5, 0.5}});
    EXPECT_EQ(t.state.position[2], Vec3(2, 0, 0));
    EXPECT_EQ(t.state.velocity[2], Vec3(0.5, 0, 1));
    EXPECT_EQ(t.state.position[0], Vec3(0, 0, 0));  // the others stay
    EXPECT_EQ(t.mesh.triangles(), triangles);
    EXPECT_EQ(log, (std::vector<std::string>{"s:moved points 2"}));
    // no point: nothing at all
    t.container->move_points({}, {}, {});
    EXPECT_EQ(log.size(), 1u);
}

TEST(TopologyPointMoves, BadPointsAreRefusedNamingTheContainerAndThePoint) {
    PointMovesTriangle t;
    EXPECT_EQ(point_moves_error([&] {
                  t.container->add_points({PointAncestorElement{ElementType::point, {0, 0, 0}, {0, 0, 0}}});
              }),
              "TopologyContainer 'cut': new point 0 must lie in an edge or a triangle");
    EXPECT_EQ(point_moves_error([&] {
                  t.container->add_points({PointAncestorElement{ElementType::edge, {0, 1, 0}, {0.5, 0, 0}},
                                           PointAncestorElement{ElementType::triangle, {0, 1, 7}, {0.1, 0.1, 0}}});
              }),
              "TopologyContainer 'cut': new point 1 has ancestor 7: the container has 3 points");
    EXPECT_EQ(point_moves_error([&] {
                  t.container->move_points({1, 2}, {{0}}, {{1.0}});
              }),
              "TopologyContainer 'cut': 2 moved points with 1 ancestor lists");
    EXPECT_EQ(point_moves_error([&] { t.container->move_points({3}, {{0}}, {{1.0}}); }),
              "TopologyContainer 'cut': cannot move point 3 of 3");
    EXPECT_EQ(point_moves_error([&] {
                  t.container->move_points({1}, {{0, -2}}, {{0.5, 0.5}});
              }),
              "TopologyContainer 'cut': moved point 1 has ancestor -2: the container has 3 points");
    // nothing changed
    EXPECT_EQ(t.state.position.size(), 3u);
    EXPECT_EQ(t.state.position[1], Vec3(4, 0, 0));
    EXPECT_EQ(t.mesh.num_points(), 3u);
}

}  // namespace
}  // namespace penalty
