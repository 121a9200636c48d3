// Scene's topological-change API (src/scene/topology/scene_topology.cpp): remove_elements and
// add_elements between steps, as SOFA's modifiers called at a step's start (SOFA HEAD's states bit
// for bit); every element type through its container's removal or addition (swap-and-pop, the
// isolated points removed, new points weighted from their ancestors); the graph told of each
// change; the refusals' exact messages, nothing changed: a call from inside a step, vertex
// indices that are not whole elements, points given as vertices.
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>

namespace penalty {
namespace {

/// The message of the std::invalid_argument `f` raises ("no error" when none).
std::string st_refusal(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

Vec3Object& st_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

/// A node "n" with a container of `type` ("...SetTopologyContainer" and its modifier) holding
/// `elements`, and a state: the positions given to the container.
std::string st_container(const std::string& type, const std::string& points, const std::string& elements = "",
                         const std::string& state = "<MechanicalObject name=\"dofs\"/>") {
    return R"(<Node name="root" gravity="0 0 0"><Node name="n"><)" + type +
           R"(SetTopologyContainer name="mesh" position=")" + points + "\" " + elements + "/><" + type +
           "SetTopologyModifier/>" + state + R"(<UniformMass vertexMass="1"/></Node></Node>)";
}

// SOFA HEAD (2a278d8): the 2×2×2-cell tetrahedral cube hanging from its x = 0 face, with a
// TopologicalChangeProcessor removing tetrahedron 4 at t = 0.02 and adding it again
// ("ADD= Tetrahedra 1", 1 3 9 13) at t = 0.04, `sofa-head SCENE 20 OUT --every 1`. The same
// changes through the API after steps 2 and 4 (the processor makes them at the start of steps 3
// and 5): SOFA HEAD's positions after step 20, bit for bit (every step is).
TEST(SceneTopology, RemovalsAndAdditionsBetweenStepsAreSofaHeadsModifiersAtTheNextStepsStart) {
    const test::TetraCube cube = test::tetra_cube(2, 0.2);
    auto s = test::build(R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><DefaultAnimationLoop/><Node name="body">
  <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
  <CGLinearSolver iterations="200" tolerance="1e-20" threshold="1e-20"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
                         test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) +
                         R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <DiagonalMass massDensity="1000"/>
  <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>
  <FixedProjectiveConstraint indices="3 6 9 12 15 18 21 24"/>
</Node></Node>)");
    const TopologyContainer& c = s->topology_container("volume");
    const Node& root = s->simulation().root();
    s->step();
    s->step();
    std::uint64_t structure = root.structure_version();
    s->remove_elements("volume", ElementType::tetrahedron, {4});
    EXPECT_NE(root.structure_version(), structure);            // the solvers build their systems again
    EXPECT_EQ(c.mesh().tetrahedra()[4], cube.tetrahedra[39]);  // swap-and-pop
    ASSERT_EQ(c.mesh().tetrahedra().size(), 39u);
    s->step();
    s->step();
    structure = root.structure_version();
    s->add_elements("volume", ElementType::tetrahedron, {1, 3, 9, 13});
    EXPECT_NE(root.structure_version(), structure);
    EXPECT_EQ(c.mesh().tetrahedra().back(), (Tetrahedron{1, 3, 9, 13}));
    for (int k = 4; k < 20; ++k) s->step();
    const Vec3Object& x = st_state(*s);
    ASSERT_EQ(x.num_dofs(), 27u);
    EXPECT_EQ(x.position[0], Vec3(-0.022735809390624261, -0.045381857291573062, 0.024777004703595569));
    EXPECT_EQ(x.position[13], Vec3(0.092411561728431679, -0.051880118515542063, 0.099175057344377926));
    EXPECT_EQ(x.position[26], Vec3(0.21747271898421477, 0.00059285883725447922, 0.19654978301004949));
}

TEST(SceneTopology, PointsAreRemovedByTheLastTakingTheirPlaceAndAddedFromTheirAncestors) {
    auto s = test::build(st_container("Point", "0 0 0  1 0 0  2 0 0  3 0 0", "",
                                      R"(<MechanicalObject name="dofs" velocity="0 1 0  0 2 0  0 4 0  0 8 0"/>)"));
    Vec3Object& x = st_state(*s);
    s->remove_elements("mesh", ElementType::point, {1});
    ASSERT_EQ(x.num_dofs(), 3u);
    EXPECT_EQ(x.position, (std::vector<Vec3>{Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(2, 0, 0)}));
    EXPECT_EQ(x.velocity, (std::vector<Vec3>{Vec3(0, 1, 0), Vec3(0, 8, 0), Vec3(0, 4, 0)}));
    // two new points: the first the mean of points 0 and 2 (equal coefficients), the second zero
    // (it was left uninitialized: fixed in StateTopologyFollower, src/mechanics/topology/state_follower.cpp)
    s->add_elements("mesh", ElementType::point, {}, 2, {{0, 2}, {}});
    ASSERT_EQ(x.num_dofs(), 5u);
    EXPECT_EQ(x.position[3], Vec3(1, 0, 0));
    EXPECT_EQ(x.velocity[3], Vec3(0, 2.5, 0));
    EXPECT_EQ(x.position[4], Vec3::Zero());  // SOFA: MechanicalObject::resize, a zero Coord
    EXPECT_EQ(x.velocity[4], Vec3::Zero());
    EXPECT_EQ(x.rest_position[4], Vec3::Zero());
    EXPECT_EQ(s->topology_container("mesh").mesh().num_points(), 5u);
    EXPECT_EQ(st_refusal([&] {
                  s->add_elements("mesh", ElementType::point, {0, 1}, 1);
              }),
              "add_elements: points take a count, not vertex indices");
    EXPECT_EQ(x.num_dofs(), 5u);
}

TEST(SceneTopology, EachElementTypeIsRemovedAndAddedThroughItsContainer) {
    // edges: a chain 0-1-2-3; edge 0 goes, the last edge takes its place, point 0 (isolated) goes
    // and the last point (3) takes its index
    auto edges = test::build(st_container("Edge", "0 0 0  1 0 0  2 0 0  3 0 0", R"(edges="0 1  1 2  2 3")"));
    const MeshTopology& chain = edges->topology_container("mesh").mesh();
    edges->remove_elements("mesh", ElementType::edge, {0});
    EXPECT_EQ(chain.edges(), (std::vector<Edge>{{2, 0}, {1, 2}}));
    EXPECT_EQ(st_state(*edges).position, (std::vector<Vec3>{Vec3(3, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)}));
    edges->add_elements("mesh", ElementType::edge, {0, 1});
    EXPECT_EQ(chain.edges().back(), (Edge{0, 1}));

    // triangles: the 2×2 sheet (9 points, 8 triangles); the corner triangle 0 (0 3 1) goes, and
    // its corner point 0 with it
    const test::TriangleSheet sheet = test::triangle_sheet(2, 1.0);
    auto triangles = test::build(st_container("Triangle", test::points_text(sheet.points),
                                              "triangles=\"" + test::elements_text(sheet.triangles) + "\""));
    const MeshTopology& surface = triangles->topology_container("mesh").mesh();
    triangles->remove_elements("mesh", ElementType::triangle, {0});
    EXPECT_EQ(surface.triangles().size(), 7u);
    EXPECT_EQ(surface.num_points(), 8u);
    EXPECT_EQ(st_state(*triangles).position[0], Vec3(2, 0, 2));  // the last point took index 0
    triangles->add_elements("mesh", ElementType::triangle, {1, 3, 4});
    EXPECT_EQ(surface.triangles().size(), 8u);

    // quads: two unit squares side by side; the first goes with its two own points
    auto quads =
        test::build(st_container("Quad", "0 0 0  1 0 0  2 0 0  0 1 0  1 1 0  2 1 0", R"(quads="0 1 4 3  1 2 5 4")"));
    const MeshTopology& sheet2 = quads->topology_container("mesh").mesh();
    quads->remove_elements("mesh", ElementType::quad, {0});
    ASSERT_EQ(sheet2.quads().size(), 1u);
    EXPECT_EQ(sheet2.num_points(), 4u);
    for (const Vec3& p : st_state(*quads).position) EXPECT_GE(p.x(), 1.0);
    quads->add_elements("mesh", ElementType::quad, {0, 1, 2, 3});
    EXPECT_EQ(sheet2.quads().size(), 2u);

    // hexahedra: two unit cubes side by side; the first goes with its four own points
    auto hexahedra = test::build(
        st_container("Hexahedron", "0 0 0  1 0 0  2 0 0  0 1 0  1 1 0  2 1 0  0 0 1  1 0 1  2 0 1  0 1 1  1 1 1  2 1 1",
                     R"(hexahedra="0 1 4 3 6 7 10 9  1 2 5 4 7 8 11 10")"));
    const MeshTopology& bricks = hexahedra->topology_container("mesh").mesh();
    hexahedra->remove_elements("mesh", ElementType::hexahedron, {0});
    ASSERT_EQ(bricks.hexahedra().size(), 1u);
    EXPECT_EQ(bricks.num_points(), 8u);
    for (const Vec3& p : st_state(*hexahedra).position) EXPECT_GE(p.x(), 1.0);
    const Hexahedron kept = bricks.hexahedra()[0];
    hexahedra->add_elements("mesh", ElementType::hexahedron, {kept.begin(), kept.end()});
    EXPECT_EQ(bricks.hexahedra().size(), 2u);
    EXPECT_EQ(bricks.hexahedra()[1], kept);

    // a type the container does not hold, and vertices that are not whole elements: refused,
    // nothing changed
    EXPECT_EQ(st_refusal([&] { hexahedra->remove_elements("mesh", ElementType::tetrahedron, {0}); }),
              "TopologyContainer '/n/mesh': a hexahedra container has no tetrahedra");
    EXPECT_EQ(st_refusal([&] {
                  hexahedra->add_elements("mesh", ElementType::hexahedron, {0, 1, 2, 3, 4, 5, 6});
              }),
              "add_elements: 7 vertex indices are not a whole number of hexahedra (8 each)");
    EXPECT_EQ(st_refusal([&] {
                  quads->add_elements("mesh", ElementType::quad, {0, 1, 2});
              }),
              "add_elements: 3 vertex indices are not a whole number of quads (4 each)");
    EXPECT_EQ(bricks.hexahedra().size(), 2u);
    EXPECT_EQ(sheet2.quads().size(), 2u);
}

TEST(SceneTopology, AChangeFromInsideAStepIsRefusedAndChangesNothing) {
    // a handler of the collision phase (SOFA: changes happen at AnimateBegin/EndEvent)
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    auto s = test::build(
        R"(<Node name="root" dt="0.01"><Node name="body"><EulerImplicitSolver/><CGLinearSolver/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
        test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) +
        R"("/><TetrahedronSetTopologyModifier/><MechanicalObject/><UniformMass totalMass="1"/></Node></Node>)");
    std::vector<std::string> refusals;
    s->set_event_listener([&](std::string_view event) {
        if (event != "CollisionBeginEvent") return;
        refusals.push_back(st_refusal([&] { s->remove_elements("volume", ElementType::tetrahedron, {0}); }));
        refusals.push_back(st_refusal([&] { s->add_elements("volume", ElementType::tetrahedron, {0, 1, 2, 4}); }));
    });
    const std::uint64_t revision = s->topology_revision();
    s->step();
    EXPECT_EQ(refusals, (std::vector<std::string>{
                            "remove_elements: topological changes happen between steps (onAnimateBeginEvent, "
                            "onAnimateEndEvent), not during the collision phase of a step",
                            "add_elements: topological changes happen between steps (onAnimateBeginEvent, "
                            "onAnimateEndEvent), not during the collision phase of a step"}));
    EXPECT_EQ(s->topology_revision(), revision);
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 5u);
    // between steps: accepted
    s->set_event_listener(nullptr);
    s->remove_elements("volume", ElementType::tetrahedron, {0});
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 4u);
    EXPECT_NE(s->topology_revision(), revision);
}

}  // namespace
}  // namespace penalty
