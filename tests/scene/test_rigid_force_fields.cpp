// The rigid force fields built from scenes (scene/builder/rigid_force_fields.cpp): a cantilever of
// beams sags as the point loads predict; joint springs between mapped frames run.
#include "field_and_constraint_scenes.hpp"

namespace {

using namespace penalty;
using namespace penalty::test_field_scenes;
using penalty::test::build;
using ::testing::HasSubstr;

TEST(FieldAndConstraintComponents, CantileverOfBeamsSagsAsThePointLoadsPredict) {
    // 4 beams along x, frame 0 fixed, 0.01 kg per frame under g = 10: a static tip deflection of
    // Σ_i P x_i² (3L − x_i)/(6EI) (each frame's weight P at x_i); long implicit steps reach it
    const std::string scene = R"(<Node name="root" dt="2" gravity="0 -10 0">
      <Node name="Beam"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
        <CGLinearSolver iterations="400" tolerance="1e-30" threshold="1e-30"/>
        <MeshTopology edges="0 1 1 2 2 3 3 4"/>
        <MechanicalObject template="Rigid3" name="frames" position="0 0 0 0 0 0 1  0.5 0 0 0 0 0 1  1 0 0 0 0 0 1  1.5 0 0 0 0 0 1  2 0 0 0 0 0 1"/>
        <FixedProjectiveConstraint indices="0"/>
        <UniformMass vertexMass="0.01"/>
        <BeamFEMForceField radius="0.05" youngModulus="1e8" poissonRatio="0.3"/>
      </Node>
    </Node>)";
    auto s = build(scene);
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("4 beams"));
    for (int i = 0; i < 60; ++i) s->step();
    const auto& frames = dynamic_cast<const Rigid3Object&>(*s.get()->states()[0].state);
    const double ei = 1e8 * std::numbers::pi * std::pow(0.05, 4) / 4, length = 2.0, p = 0.01 * 10;
    double tip = 0;
    for (double xi : {0.5, 1.0, 1.5, 2.0}) tip += p * xi * xi * (3 * length - xi) / (6 * ei);
    EXPECT_NEAR(frames.position[4].center.y(), -tip, 1e-4 * tip);
    EXPECT_NEAR(frames.position[0].center.norm(), 0.0, 0.0);
}

TEST(FieldAndConstraintComponents, JointSpringsBetweenMappedFramesRun) {
    // the shape of SOFA's JointSpringForceField.scn: the springs act on frames a RigidMapping
    // Rigid3 → Rigid3 makes; rigidIndexPerPoint of another length than the output means `index`
    const std::string scene = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
      <Node name="chain"><EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
        <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
        <MechanicalObject template="Rigid3" name="DOFs" position="0 0 0 0 0 0 1  2 0 0 0 0 0 1  4 0 0 0 0 0 1"/>
        <UniformMass vertexMass="1 1 [1 0 0,0 1 0,0 0 1]"/>
        <FixedProjectiveConstraint template="Rigid3" indices="0"/>
        <Node name="attaches">
          <MechanicalObject template="Rigid3" name="attaches" position="1 0 0 0 0 0 1  -1 0 0 0 0 0 1  1 0 0 0 0 0 1  -1 0 0 0 0 0 1"/>
          <RigidMapping template="Rigid3,Rigid3" input="@.." output="@." rigidIndexPerPoint="0 1 1 2"/>
          <JointSpringForceField template="Rigid3" spring="BEGIN_SPRING 0 1 FREE_AXIS 0 0 0 0 1 0 KS_T 0 30000 KS_R 0 200000 KD 1 R_LIM_Y -1.57 1.57 END_SPRING
             BEGIN_SPRING 2 3 END_SPRING"/>
        </Node>
      </Node>
    </Node>)";
    auto s = build(scene);
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("2 joint springs"));
    for (int i = 0; i < 50; ++i) s->step();
    const auto& dofs = dynamic_cast<const Rigid3Object&>(*s->states()[0].state);
    EXPECT_EQ(dofs.position[0].center, Vec3::Zero());
    // the hinges hold the chain together: frame 1's attach point stays on frame 0's (within the
    // springs' stretch under gravity, mg/k ~ 1e-3 m)
    const auto& attaches = dynamic_cast<const Rigid3Object&>(*s->states()[1].state);
    EXPECT_LT((attaches.position[0].center - attaches.position[1].center).norm(), 2e-2);
    EXPECT_LT(dofs.position[2].center.y(), -0.01) << "the chain swings down";
}

}  // namespace
