// Force fields built from scenes made here: InteractionEllipsoidForceField (a cloth pushed by an
// ellipsoid on a Rigid3d frame), HexahedronFEMForceField method polar, and TriangularFEMForceField
// method large step by step against SOFA HEAD's numbers; bad attributes are errors naming the
// file, line, component and attribute.
#include "penalty/mechanics/interaction_ellipsoid.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

std::string with_text(std::string xml, const std::string& what, const std::string& by) {
    xml.replace(xml.find(what), what.size(), by);
    return xml;
}

const Vec3Object& family_state(const scene::Scene& s, std::size_t i) {
    return dynamic_cast<const Vec3Object&>(*s.states()[i].state);
}

// Points falling onto a sphere carried by a rigid frame at (0, 0, 0) (SOFA's example scene's
// layout: the frame in its own node with an explicit solver, translations fixed).
const std::string kEllipsoidScene = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Obstacle"><EulerExplicitSolver/>
    <MechanicalObject name="frame" template="Rigid3" position="0 0 0 0 0 0 1"/>
    <UniformMass totalMass="1"/>
    <PartialFixedProjectiveConstraint indices="0" fixedDirections="1 1 1 0 0 0"/>
  </Node>
  <Node name="Points"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 1.2 0  0.3 1.1 0  5 5 5"/>
    <UniformMass vertexMass="0.1"/>
    <InteractionEllipsoidForceField name="ellipsoid" template="Vec3,Rigid3" object1="@dofs" object2="@../Obstacle/frame"
        stiffness="100" damping="1" center="0 0 0" vradius="1 1 1" object2_forces="false"/>
  </Node>
</Node>)";

TEST(InteractionEllipsoidComponent, PointsRestOnTheSphereAndTheFrameIsOnlyRead) {
    auto s = build(kEllipsoidScene);
    for (int i = 0; i < 300; ++i) s->step();
    const Vec3Object& x = family_state(*s, 1);
    // at rest, k·(1 − |x|) = m·g at the top: |x| = 1 − 0.1·10/100 = 0.99 (the side point slides off)
    EXPECT_NEAR(x.position[0].y(), 0.99, 1e-6);
    EXPECT_NEAR(x.position[0].x(), 0.0, 1e-12);
    EXPECT_LT(x.position[2].y(), 5.0 - 1.0);  // the far point falls freely
    const auto& frame = dynamic_cast<const Rigid3Object&>(*s->states()[0].state);
    EXPECT_EQ(frame.position[0].center, Vec3::Zero());
}

TEST(InteractionEllipsoidComponent, BadAttributesNameTheAttribute) {
    EXPECT_THAT(
        error_of(with_text(kEllipsoidScene, R"(vradius="1 1 1")", R"(vradius="1 0 1")")),
        HasSubstr(
            "test.scn:11: InteractionEllipsoidForceField 'ellipsoid': attribute 'vradius': radii must be non-zero"));
    EXPECT_THAT(
        error_of(with_text(kEllipsoidScene, R"(center="0 0 0")", R"(center="0 0 0 1")")),
        HasSubstr("InteractionEllipsoidForceField 'ellipsoid': attribute 'center': needs 3 numbers per ellipsoid"));
    EXPECT_THAT(error_of(with_text(kEllipsoidScene, R"(object2="@../Obstacle/frame")", R"(object2="@dofs")")),
                HasSubstr("InteractionEllipsoidForceField 'ellipsoid': attribute 'object2': must be a Rigid3d state"));
    EXPECT_THAT(error_of(with_text(kEllipsoidScene, R"(object2_forces="false")", R"(object2_dof_index="2")")),
                HasSubstr("attribute 'object2_dof_index': 2 is out of range (1 frames)"));
    EXPECT_THAT(error_of(with_text(kEllipsoidScene, R"(template="Vec3,Rigid3")", R"(template="Vec3,Vec3")")),
                HasSubstr("InteractionEllipsoidForceField 'ellipsoid': template 'Vec3,Vec3' is not supported"));
}

const std::string kHexahedronScene = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Block"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <RegularGridTopology nx="3" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="1" zmin="0" zmax="1"/>
    <MechanicalObject name="dofs"/>
    <UniformMass vertexMass="0.1"/>
    <HexahedronFEMForceField name="FEM" method="METHOD" youngModulus="2000" poissonRatio="0.3"/>
    <FixedProjectiveConstraint indices="0 3 6 9"/>
  </Node>
</Node>)";

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

// A hyperelastic cantilever: a grid's hexahedra split into tetrahedra by Hexa2TetraTopologicalMapping
// in a child node whose input links to the parent node (`input="@../"`, SOFA's example layout).
const std::string kHyperelasticScene = R"(<Node name="root" dt="0.005" gravity="0 -9 0">
  <Node name="Beam"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <RegularGridTopology name="grid" min="0 0 0" max="1 1 2" n="2 2 3"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <Node name="tetras">
      <MeshTopology name="Container"/>
      <Hexa2TetraTopologicalMapping input="@../" output="@Container"/>
      <TetrahedronHyperelasticityFEMForceField name="FEM" ParameterSet="3448 31034" materialName="MATERIAL"/>
    </Node>
    <FixedProjectiveConstraint indices="0 1 2 3"/>
  </Node>
</Node>)";

TEST(HyperelasticityComponent, EveryMaterialBuildsAndBadAttributesNameTheAttribute) {
    for (const char* material : {"ArrudaBoyce", "StVenantKirchhoff", "NeoHookean"}) {
        auto s = build(with_text(kHyperelasticScene, "MATERIAL", material));
        for (int i = 0; i < 10; ++i) s->step();
        EXPECT_LT(family_state(*s, 0).position[11].y(), 1.0 - 1e-5) << material;  // the free end sags
    }
    auto ogden = build(with_text(with_text(kHyperelasticScene, "MATERIAL", "Ogden"), "3448 31034", "1500 500 5000"));
    ogden->step();
    EXPECT_THAT(error_of(with_text(kHyperelasticScene, "MATERIAL", "Costa")),
                HasSubstr("test.scn:9: TetrahedronHyperelasticityFEMForceField 'FEM': attribute 'materialName': "
                          "'Costa' is not supported"));
    EXPECT_THAT(error_of(with_text(kHyperelasticScene, "MATERIAL", "MooneyRivlin")),
                HasSubstr("attribute 'ParameterSet': MooneyRivlin needs 3 parameters, found 2"));
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
