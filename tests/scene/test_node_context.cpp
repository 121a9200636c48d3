// What a component finds in its node's context, as SOFA's Node resolves it:
// - in a node without a MechanicalObject it acts on the nearest ancestor's state and, when the
//   node has no topology, reads the nearest ancestor's topology (Node::getMechanicalState and
//   Node::getMeshTopologyLink search the parents); a scene with the components in a child node
//   runs exactly as the same scene with them in the state's own node;
// - a node with two topologies uses the last one (its NodeSingle link is set again).
#include "penalty/io/error.hpp"
#include "penalty/mechanics/state.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using ::testing::HasSubstr;

using penalty::test::build;

// A 3×3-point cloth (8 triangles) above a fixed floor of two triangles (no cloth point lies over
// the floor's diagonal: MinProximity's Triangle-Point test leaves edges to Line models); `cloth_extra` goes in the
// cloth's node, `surface` is the cloth's child node (or empty).
std::string cloth_scene(const std::string& cloth_extra, const std::string& surface) {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.2" contactDistance="0.05"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="floor">
    <MechanicalObject position="-2.3 0 -2  1.7 0 -2  1.7 0 2  -2.3 0 2"/>
    <MeshTopology triangles="0 2 1  0 3 2"/>
    <TriangleCollisionModel moving="0" simulated="0" contactStiffness="20000"/>
  </Node>
  <Node name="cloth">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="dofs" position="0 0.3 0  0.5 0.3 0  1 0.3 0  0 0.3 0.5  0.5 0.3 0.5  1 0.3 0.5  0 0.3 1  0.5 0.3 1  1 0.3 1"/>
    <UniformMass totalMass="0.9"/>
)" + cloth_extra +
           surface +
           R"(  </Node>
</Node>
)";
}

const std::string kTriangles = R"(triangles="0 1 4  0 4 3  1 2 5  1 5 4  3 4 7  3 7 6  4 5 8  4 8 7")";

std::vector<Vec3> cloth_after(scene::Scene& s, int steps) {
    for (int i = 0; i < steps; ++i) s.step();
    for (const auto& r : s.states())
        if (r.node_path == "/cloth") return dynamic_cast<const Vec3Object&>(*r.state).position;
    ADD_FAILURE() << "no cloth state";
    return {};
}

TEST(NodeContextLookup, CollisionModelsInAChildNodeActOnTheParentsState) {
    // The FEM sits in the child node in both scenes; the collision models move.
    const std::string models =
        "<TriangleCollisionModel contactStiffness=\"10\"/><PointCollisionModel contactStiffness=\"10\"/>";
    const std::string fem = "<TriangleSetTopologyContainer " + kTriangles +
                            "/><TriangularFEMForceField youngModulus=\"300\" poissonRatio=\"0.3\"/>";
    auto a = build(cloth_scene("", "<Node name=\"surface\">" + fem + models + "</Node>\n"));
    auto b = build(cloth_scene("<MeshTopology " + kTriangles + "/>" + models + "\n",
                               "<Node name=\"surface\">" + fem + "</Node>\n"));
    ASSERT_EQ(a->collision_models().size(), 3u);
    // The models of the child node read the cloth's state: the node they record is the cloth's.
    EXPECT_EQ(a->collision_models()[1].node->name(), "cloth");
    EXPECT_EQ(a->collision_models()[2].node->name(), "cloth");
    const std::vector<Vec3> xa = cloth_after(*a, 60);
    const std::vector<Vec3> xb = cloth_after(*b, 60);
    ASSERT_EQ(xa.size(), 9u);
    // It fell (0.3 m in free fall takes 0.25 s) and rests on the floor, about contactDistance
    // above it: contacts were made.
    for (const Vec3& x : xa) {
        EXPECT_LT(x.y(), 0.1);
        EXPECT_GT(x.y(), 0.0);
    }
    for (std::size_t i = 0; i < xa.size(); ++i) EXPECT_EQ(xa[i], xb[i]) << "point " << i;
}

TEST(NodeContextLookup, TopologyComesFromTheNearestAncestor) {
    // The FEM in the child node has no topology of its own: it takes the cloth's.
    const std::string in_child =
        cloth_scene("    <MeshTopology " + kTriangles + "/>\n",
                    "    <Node name=\"fem\">\n      <TriangularFEMForceField youngModulus=\"300\"/>\n    </Node>\n");
    const std::string in_parent = cloth_scene(
        "    <MeshTopology " + kTriangles + "/>\n    <TriangularFEMForceField youngModulus=\"300\"/>\n", "");
    auto a = build(in_child);
    auto b = build(in_parent);
    const std::vector<Vec3> xa = cloth_after(*a, 10);
    const std::vector<Vec3> xb = cloth_after(*b, 10);
    for (std::size_t i = 0; i < xa.size(); ++i) EXPECT_EQ(xa[i], xb[i]) << "point " << i;
}

TEST(NodeContextLookup, NoStateAnywhereUpIsAnErrorNamingTheComponent) {
    try {
        build("<Node name=\"root\">\n  <Node name=\"A\">\n    <MeshTopology " + kTriangles +
              "/>\n    <TriangleCollisionModel/>\n  </Node>\n</Node>\n");
        FAIL() << "expected a scene error";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("test.scn:4"));
        EXPECT_THAT(e.what(), HasSubstr("TriangleCollisionModel"));
        EXPECT_THAT(e.what(), HasSubstr("needs a MechanicalObject in its node or an ancestor node"));
    }
}

TEST(NodeContextLookup, TheLastTopologyOfANodeIsTheNodesTopology) {
    // The first topology has one triangle, the second (last) two: the FEM and the collision
    // model take the second's.
    const auto s = build(R"(<Node name="root">
  <DefaultAnimationLoop/>
  <DefaultAnimationLoop/>
  <Node name="A">
    <MeshTopology position="0 0 0  1 0 0  1 1 0  0 1 0" triangles="0 1 2"/>
    <TriangleSetTopologyContainer position="0 0 0  1 0 0  1 1 0  0 1 0" triangles="0 1 2  0 2 3"/>
    <MechanicalObject/>
    <TriangleCollisionModel/>
  </Node>
</Node>
)");
    ASSERT_EQ(s->states().size(), 1u);
    ASSERT_NE(s->states().front().topology, nullptr);
    EXPECT_EQ(s->states().front().topology->triangles().size(), 2u);
    ASSERT_EQ(s->collision_models().size(), 1u);
    EXPECT_EQ(s->collision_models().front().model->size(), 2u);
}

}  // namespace
