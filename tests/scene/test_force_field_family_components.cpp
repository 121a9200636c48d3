// Force fields built from scenes made here: InteractionEllipsoidForceField (a cloth pushed by an
// ellipsoid on a Rigid3d frame), HexahedronFEMForceField method polar, and TriangularFEMForceField
// method large step by step against SOFA HEAD's numbers; bad attributes are errors naming the
// file, line, component and attribute.
#include "force_field_family_scenes.hpp"
#include "penalty/mechanics/interaction_ellipsoid.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty::test_family_scenes;
using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

TEST(HexahedronFemComponent, PolarIsBuiltAndSvdIsRefused) {
    auto polar = build(with_text(kHexahedronScene, "METHOD", "polar"));
    auto large = build(with_text(kHexahedronScene, "METHOD", "large"));
    for (int i = 0; i < 20; ++i) {
        polar->step();
        large->step();
    }
    // a bending cantilever: both corotational, close but not the same frames
    const Vec3 tip_polar = family_state(*polar, 0).position[2], tip_large = family_state(*large, 0).position[2];
    EXPECT_LT(tip_polar.y(), -1e-3);
    EXPECT_LT((tip_polar - tip_large).norm(), 0.1 * std::abs(tip_polar.y()));
    EXPECT_THAT(error_of(with_text(kHexahedronScene, "METHOD", "svd")),
                HasSubstr("test.scn:6: HexahedronFEMForceField 'FEM': attribute 'method': 'svd' is not supported "
                          "(small, large or polar)"));
}

// A sagging membrane of eight triangles (one vertex lifted) under TriangularFEMForceField large:
// SOFA HEAD's positions after 8 steps of this scene (sofa-head, %.17g), reproduced to the bit
// (TriangularFEMForceField::initLarge, accumulateForceLarge, applyStiffnessLarge in SOFA's order).
TEST(TriangularFemComponent, LargeMethodFollowsSofaToTheBit) {
    auto s = build(R"(<Node name="root" dt="0.04" gravity="0 0 -3">
  <Node name="Cloth">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 0 0  1 0 0  2 0 0  0 1 0  1 1 0.1  2 1 0  0 2 0  1 2 0  2 2 0"/>
    <TriangleSetTopologyContainer name="topo" triangles="0 1 4  0 4 3  1 2 5  1 5 4  3 4 7  3 7 6  4 5 8  4 8 7"/>
    <UniformMass vertexMass="0.05"/>
    <TriangularFEMForceField name="FEM" method="large" youngModulus="60" poissonRatio="0.3"/>
    <FixedProjectiveConstraint indices="0 2"/>
  </Node>
</Node>)");
    for (int i = 0; i < 8; ++i) s->step();
    const Vec3Object& x = family_state(*s, 0);
    EXPECT_EQ(x.position[1], Vec3(0.9999676981476896, -0.0046483888907747749, -0.14930836094571773));
    EXPECT_EQ(x.position[4], Vec3(1.0112628146473306, 0.99460220391173437, -0.06143739377559651));
    EXPECT_EQ(x.position[8], Vec3(2.0120174082480444, 1.9896544919020525, -0.17544982697891781));
}

}  // namespace
