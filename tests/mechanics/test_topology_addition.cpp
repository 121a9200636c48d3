// TopologyContainer's additions (topology_addition.cpp, SOFA's ...SetTopologyModifier::
// add...Process): the lower elements a new element needs, each with its event first, the points
// with their weighted ancestors in the states, and the checks naming the container.
#include "topology_container_checks.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace penalty {
namespace {

using test_topology::tc_expect_consistent;
using test_topology::TcRecorder;

TEST(TopologyContainer, AddingATetrahedronCreatesItsFacesAndEdgesEachWithItsEventFirst) {
    MeshTopology mesh;
    mesh.set_tetrahedra({{0, 1, 2, 3}});
    mesh.set_num_points(5);
    TopologyContainer c(mesh, ElementType::tetrahedron, "volume");
    std::vector<std::string> log;
    TcRecorder handler("h", log);
    c.add_handler(handler, {ElementType::tetrahedron});
    c.add_tetrahedra({{1, 2, 3, 4}});
    EXPECT_EQ(mesh.tetrahedra().size(), 2u);
    EXPECT_EQ(mesh.triangles().size(), 7u);
    EXPECT_EQ(mesh.edges().size(), 9u);
    tc_expect_consistent(c);
    // face 0 (2,3,4) of the new tetrahedron first: its edges (3,4), (4,2) then the face; face 1
    // (1,4,3): edge (1,4) then the face; face 2 (2,4,1) (face 3 (1,3,2) exists); the tetrahedron.
    EXPECT_EQ(log, (std::vector<std::string>{"h:added edges 6", "h:added edges 7", "h:added triangles 4",
                                             "h:added edges 8", "h:added triangles 5", "h:added triangles 6",
                                             "h:added tetrahedra 1", "h:ending"}));
    EXPECT_EQ(mesh.edges()[6], (Edge{3, 4}));
    EXPECT_EQ(mesh.triangles()[4], (Triangle{2, 3, 4}));
}

TEST(TopologyContainer, AddedPointsGrowTheStatesWithWeightedAncestorsBeforeTheEvent) {
    MeshTopology mesh;
    mesh.set_triangles({{0, 1, 2}});
    TopologyContainer c(mesh, ElementType::triangle, "surface");
    Vec3Object state;
    state.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 2, 0)};
    state.init();
    StateTopologyFollower<Vec3Types> follower(state);
    c.add_state_follower(follower);
    std::vector<std::string> log;
    TcRecorder handler("h", log);
    c.add_handler(handler, {ElementType::point});
    c.add_points(2, {{0, 1}, {1, 2}}, {{0.25, 0.75}, {0.5, 0.5}});
    ASSERT_EQ(state.position.size(), 5u);
    EXPECT_EQ(state.rest_position.size(), 5u);
    EXPECT_EQ(state.position[3], Vec3(0.75, 0, 0));
    EXPECT_EQ(state.position[4], Vec3(0.5, 1, 0));
    EXPECT_EQ(mesh.num_points(), 5u);
    EXPECT_EQ(mesh.triangles_around_vertex().size(), 5u);
    EXPECT_EQ(log, (std::vector<std::string>{"h:added points 3 4", "h:ending"}));
    EXPECT_THROW(c.add_triangles({{0, 1, 9}}), std::invalid_argument);
    EXPECT_THROW(c.add_triangles({{0, 1, 1}}), std::invalid_argument);
    c.add_triangles({{1, 3, 4}});
    tc_expect_consistent(c);
}

TEST(TopologyAddition, AQuadCreatesItsMissingEdgesInOrderThenItself) {
    // the quad (0,1,2,3) and two free points; the new quad (1,4,5,2) shares the side (2,1): it
    // needs three edges, made as SOFA's QuadSetTopologyModifier::addQuadProcess looks them up,
    // side (q[j+1], q[j+2]) for j = 0..3: (4,5), (5,2), (2,1) (there), (1,4); each is added (and
    // announced) before the quad
    MeshTopology mesh;
    mesh.set_quads({{0, 1, 2, 3}});
    mesh.set_num_points(6);
    TopologyContainer c(mesh, ElementType::quad, "strip");
    ASSERT_EQ(mesh.edges().size(), 4u);
    std::vector<std::string> log;
    TcRecorder handler("h", log);
    c.add_handler(handler, {ElementType::edge, ElementType::quad});
    c.add_quads({{1, 4, 5, 2}});
    ASSERT_EQ(mesh.quads().size(), 2u);
    ASSERT_EQ(mesh.edges().size(), 7u);
    EXPECT_EQ(mesh.edges()[4], (Edge{4, 5}));
    EXPECT_EQ(mesh.edges()[5], (Edge{5, 2}));
    EXPECT_EQ(mesh.edges()[6], (Edge{1, 4}));
    EXPECT_EQ(log, (std::vector<std::string>{"h:added edges 4", "h:added edges 5", "h:added edges 6", "h:added quads 1",
                                             "h:ending"}));
    // the shared side is in both quads' shells
    EXPECT_EQ(mesh.quads_around_vertex()[1], (std::vector<std::int32_t>{0, 1}));
    EXPECT_EQ(mesh.quads_around_vertex()[4], (std::vector<std::int32_t>{1}));
}

TEST(TopologyAddition, BadElementsAreRefusedNamingTheContainerTheElementAndTheVertex) {
    MeshTopology mesh;
    mesh.set_triangles({{0, 1, 2}});
    TopologyContainer c(mesh, ElementType::triangle, "surface");
    const auto message = [&](auto&& f) {
        try {
            f();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(message([&] {
                  c.add_triangles({{0, 1, 2}, {0, 1, 9}});
              }),
              "TopologyContainer 'surface': new triangles 1 uses vertex 9: the container has 3 points");
    EXPECT_EQ(message([&] {
                  c.add_triangles({{0, 2, 2}});
              }),
              "TopologyContainer 'surface': new triangles 0 uses vertex 2 twice");
    EXPECT_EQ(message([&] {
                  c.add_edges({{0, -1}});
              }),
              "TopologyContainer 'surface': new edges 0 uses vertex -1: the container has 3 points");
    EXPECT_EQ(message([&] {
                  c.add_tetrahedra({{0, 1, 2, 3}});
              }),
              "TopologyContainer 'surface': a triangles container has no tetrahedra");
    // nothing changed
    EXPECT_EQ(mesh.triangles().size(), 1u);
    EXPECT_EQ(mesh.revision(), 0u);
}

}  // namespace
}  // namespace penalty
