// MeshMatrixMass and RestShapeSpringsForceField of a scene file
// (src/scene/builder/matrix_mass_and_rest_springs.cpp): the mass of a tetrahedron from massDensity
// or totalMass, consistent or lumped; a particle held by a rest spring through one implicit Euler
// step in closed form, activeDirections freeing a direction; the roles, pivot_points' warning and
// the refusals' exact messages naming test.scn:line, the component and the attribute.
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

/// The unit-corner tetrahedron (volume 1/6) with `mass` in node "T".
std::string matrix_mass_scene(const std::string& mass) {
    return R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="T">
    <MechanicalObject name="dofs" position="0 0 0  1 0 0  0 1 0  0 0 1"/>
    <MeshTopology tetrahedra="0 1 2 3"/>
)" + mass + R"(
  </Node>
  <Node name="Other"><MechanicalObject name="other" position="0 0 0"/></Node>
</Node>)";
}

TEST(MatrixMassAndRestSprings, TheTetrahedronsMassFromItsDensityOrTotal) {
    EXPECT_THAT(scene::describe_scene(*build(matrix_mass_scene(R"(    <MeshMatrixMass massDensity="6"/>)"))),
                HasSubstr("consistent mass matrix of the tetrahedra, 1 kg in all"));
    EXPECT_THAT(
        scene::describe_scene(*build(matrix_mass_scene(R"(    <MeshMatrixMass massDensity="12" lumping="1"/>)"))),
        HasSubstr("lumped mass matrix of the tetrahedra, 2 kg in all"));
    EXPECT_THAT(scene::describe_scene(*build(matrix_mass_scene(R"(    <MeshMatrixMass totalMass="3"/>)"))),
                HasSubstr("consistent mass matrix of the tetrahedra, 3 kg in all"));
}

TEST(MatrixMassAndRestSprings, MassRefusalsNameTheLineTheComponentAndTheAttribute) {
    EXPECT_EQ(error_of(matrix_mass_scene(R"(    <MeshMatrixMass separateGravity="1"/>)")),
              "test.scn:5: MeshMatrixMass: attribute 'separateGravity': 1 is not supported");
    EXPECT_EQ(error_of(matrix_mass_scene(R"(    <MeshMatrixMass massDensity="1 -1"/>)")),
              "test.scn:5: MeshMatrixMass: attribute 'massDensity': must be finite and >= 0, found '-1'");
    EXPECT_EQ(error_of(matrix_mass_scene(R"(    <MeshMatrixMass vertexMass=""/>)")),
              "test.scn:5: MeshMatrixMass: attribute 'vertexMass': is empty");
    EXPECT_EQ(error_of(matrix_mass_scene(R"(    <MeshMatrixMass geometryState="@/Other/other"/>)")),
              "test.scn:5: MeshMatrixMass: attribute 'geometryState': must be the mass's own state");
}

/// A particle of mass 1 at the origin, held by a rest spring of stiffness 100, under gravity −10 y.
std::string rest_spring_scene(const std::string& springs) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="P">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <SparseLDLSolver/>
    <MechanicalObject name="dofs" position="0 0 0"/>
    <UniformMass totalMass="1"/>
)" + springs +
           R"(
  </Node>
  <Node name="Other"><MeshTopology name="mesh" position="0 0 0"/></Node>
</Node>)";
}

double rest_spring_step_y(const std::string& springs) {
    auto s = build(rest_spring_scene(springs));
    s->step();
    return dynamic_cast<const Vec3Object&>(*s->states().front().state).position[0].y();
}

TEST(MatrixMassAndRestSprings, ARestSpringHoldsThePointThroughAnImplicitStep) {
    // (m + dt²·k)·Δv = dt·m·g: Δv = −0.1/1.01, x = dt·Δv
    EXPECT_NEAR(rest_spring_step_y(R"(    <RestShapeSpringsForceField stiffness="100"/>)"), 0.01 * (-0.1 / 1.01),
                1e-17);
    // y not held: no force along y, but SOFA HEAD's assembled matrix (buildStiffnessMatrix) keeps
    // k on the inactive direction, so a direct solver's step is the held one's
    EXPECT_NEAR(rest_spring_step_y(R"(    <RestShapeSpringsForceField stiffness="100" activeDirections="1 0 1"/>)"),
                0.01 * (-0.1 / 1.01), 1e-17);
    // assembleAsAddDForce (beyond SOFA): the matrix of addDForce, without it: free fall
    EXPECT_NEAR(
        rest_spring_step_y(
            R"(    <RestShapeSpringsForceField stiffness="100" activeDirections="1 0 1" assembleAsAddDForce="1"/>)"),
        0.01 * -0.1, 1e-17);
    EXPECT_THAT(scene::describe_scene(*build(rest_spring_scene(R"(    <RestShapeSpringsForceField points="0"/>)"))),
                HasSubstr("1 spring to the rest positions"));
}

TEST(MatrixMassAndRestSprings, PivotPointsAreIgnoredWithAWarning) {
    auto s = build(rest_spring_scene(R"(    <RestShapeSpringsForceField pivot_points="0 0 0"/>)"));
    EXPECT_THAT(s->warnings(), ::testing::Contains(std::string("test.scn:7: RestShapeSpringsForceField: pivot_points "
                                                               "is ignored (SOFA HEAD stores it but never reads it)")));
}

TEST(MatrixMassAndRestSprings, SpringRefusalsNameTheLineTheComponentAndTheAttribute) {
    EXPECT_EQ(error_of(rest_spring_scene(R"(    <RestShapeSpringsForceField stiffness="10 -1"/>)")),
              "test.scn:7: RestShapeSpringsForceField: attribute 'stiffness': must be finite and >= 0, found '-1'");
    EXPECT_EQ(error_of(rest_spring_scene(R"(    <RestShapeSpringsForceField angularStiffness="1"/>)")),
              "test.scn:7: RestShapeSpringsForceField: attribute 'angularStiffness': applies to Rigid3d states only");
    EXPECT_EQ(error_of(rest_spring_scene(R"(    <RestShapeSpringsForceField activeDirections="1 0"/>)")),
              "test.scn:7: RestShapeSpringsForceField: attribute 'activeDirections': expected 3 flags, found 2");
    EXPECT_EQ(
        error_of(rest_spring_scene(R"(    <RestShapeSpringsForceField activeDirections="1 0.5 1"/>)")),
        "test.scn:7: RestShapeSpringsForceField: attribute 'activeDirections': flags must be 0 or 1, found '0.5'");
    EXPECT_EQ(
        error_of(rest_spring_scene(R"(    <RestShapeSpringsForceField external_rest_shape="@/Other/mesh"/>)")),

        "test.scn:7: RestShapeSpringsForceField: attribute 'external_rest_shape': must link to a MechanicalObject");
}

}  // namespace
