// ParabolicProjectiveConstraint's velocities as SOFA's projectVelocity makes them: it assigns the
// relative time r(t + dt) to the variable holding r(t) inside its loop over the indices, so only
// the first listed DOF gets the parabola's velocity and every later one 0. On a damped spring body
// the next step's forces see it; the numbers below are SOFA HEAD's (sofa-head, 2a278d8) on this
// scene. velocityForEveryIndex="1" (beyond SOFA) gives every index the velocity.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace penalty {
namespace {

constexpr const char* kParabolicOnDampedCube = R"(<Node name="root" gravity="0 -9.81 0" dt="0.01">
  <Node name="body">
    <EulerExplicitSolver symplectic="1"/>
    <MeshTopology position="0 0 0  1 0 0  0 1 0  1 1 0  0 0 1  1 0 1  0 1 1  1 1 1"
                  tetrahedra="0 1 2 4  1 3 2 7  1 4 5 7  2 4 7 6  1 2 4 7"/>
    <MechanicalObject name="dofs"/>
    <UniformMass vertexMass="0.05"/>
    <MeshSpringForceField stiffness="200" damping="0.5"/>
    <ParabolicProjectiveConstraint indices="1 6" P1="1 0 0" P2="1.3 0.5 0.2" P3="1.6 0.1 0.4" BeginTime="0" EndTime="1"/>
  </Node>
</Node>)";

Vec3Object& pv_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

TEST(ParabolicVelocity, OnlyTheFirstIndexGetsTheParabolasVelocityAsSofa) {
    auto s = test::build(kParabolicOnDampedCube);
    Vec3Object& x = pv_state(*s);
    // after init (Simulation::init's MechanicalProjectPositionAndVelocityVisitor at t = 0)
    EXPECT_DOUBLE_EQ(x.velocity[1].x(), 0.39227419354838716);
    EXPECT_DOUBLE_EQ(x.velocity[1].y(), 1.9002903225806451);
    EXPECT_DOUBLE_EQ(x.velocity[1].z(), 0.2615161290322581);
    EXPECT_EQ(x.velocity[6], Vec3::Zero());
    EXPECT_EQ(x.position[6], x.position[1]);  // both on the parabola
    s->step();
    s->step();
    // SOFA HEAD's positions after 2 steps (the damping of step 2 reads the velocities of step 1)
    const Vec3 sofa0(-0.013085140555188855, -0.056134905255730332, -0.053424667191714958);
    const Vec3 sofa3(1.0529911427339167, 1.0164899994505372, -0.052898729197226241);
    EXPECT_LT((x.position[0] - sofa0).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((x.position[3] - sofa3).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(x.velocity[6], Vec3::Zero());

    std::string fixed = kParabolicOnDampedCube;
    fixed.replace(fixed.find("BeginTime="), 0, "velocityForEveryIndex=\"1\" ");
    auto f = test::build(fixed);
    EXPECT_EQ(pv_state(*f).velocity[6], pv_state(*f).velocity[1]);
    EXPECT_NE(pv_state(*f).velocity[6], Vec3::Zero());
}

}  // namespace
}  // namespace penalty
