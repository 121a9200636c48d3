// The wiring of topological changes (scene/topology/wiring.cpp): a component that cannot follow a
// change is refused by name, before anything changes.
#include "topological_change_scenes.hpp"

namespace penalty {
namespace {

using namespace test_topology_scenes;

TEST(TopologicalChanges, WhatCannotFollowIsRefusedByName) {
    // a SubsetMapping's points would lose their input points: no rule yet, the change is refused
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    const std::string file = tchg_change_file("one.txt", "T= 0.01\n  REMOVE= 1\n0\n");
    const std::string scene = tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/><CGLinearSolver/>
  <UniformMass totalMass="1"/>
  <TopologicalChangeProcessor filename=")" + file + R"("/>
  <Node name="skin">
    <MechanicalObject name="skinDofs" position="0 0 0"/>
    <SubsetMapping name="attach" indices="0"/>
  </Node>)");
    EXPECT_THAT(test::error_of(scene), HasSubstr("SubsetMapping 'attach' (test.scn:"));
    EXPECT_THAT(test::error_of(scene), HasSubstr("does not follow topological changes"));
    // a component without a rule: a projective constraint with a target per point (SOFA's
    // PositionBasedDynamicsProjectiveConstraint has no topology data: its reinit does nothing)
    for (
        const auto& [component, named] : {std::pair<std::string, std::string>{
            R"(<UniformMass totalMass="1"/><PositionBasedDynamicsProjectiveConstraint name="pbd" stiffness="0.5" position=")" +
                test::points_text(cube.points) + "\"/>",
            "PositionBasedDynamicsProjectiveConstraint 'pbd' (test.scn:"}}) {
        const std::string text = tchg_body(cube.points, cube.tetrahedra, R"(<EulerImplicitSolver/><CGLinearSolver/>
  )" + component + R"(<TopologicalChangeProcessor filename=")" + file + R"("/>)");
        EXPECT_THAT(test::error_of(text), HasSubstr(named));
    }

    auto s = build(tchg_body(cube.points, cube.tetrahedra, "<UniformMass totalMass=\"1\"/>"));
    EXPECT_THROW(s->remove_elements("nothing", ElementType::tetrahedron, {0}), std::invalid_argument);
    EXPECT_THROW(s->remove_elements("volume", ElementType::tetrahedron, {5}), std::invalid_argument);
    EXPECT_THROW(s->remove_elements("volume", ElementType::quad, {0}), std::invalid_argument);
    EXPECT_EQ(s->topology_container("volume").mesh().tetrahedra().size(), 5u);

    // a carving tool needs a collision model
    EXPECT_THAT(test::error_of(R"(<Node name="root"><CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
  <MinProximityIntersection/><CollisionResponse/><CarvingManager active="1"/>
  <Node name="body"><TetrahedronSetTopologyContainer position="0 0 0 1 0 0 0 1 0 0 0 1" tetrahedra="0 1 2 3"/>
    <TetrahedronSetTopologyModifier/><MechanicalObject/><TetrahedronCollisionModel tags="CarvingSurface"/></Node></Node>)"),
                HasSubstr("CarvingManager: attribute 'toolModel': no tool"));
}

}  // namespace
}  // namespace penalty
