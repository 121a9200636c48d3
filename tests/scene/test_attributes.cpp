// The attribute reader of the scene builder (src/scene/builder/attributes.cpp): a value linked from
// another component's Data (@component.data, followed through chains, else the linked
// component's default), the value checks, and the refusals' exact messages naming test.scn:line,
// the component and the attribute. A particle of mass m held by a rest spring (k = 100) through
// one implicit Euler step: y = dt·(dt·m·g)/(m + dt²·k), so the step shows the mass read.
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;

/// The particle with `mass` (a UniformMass of node "P"), and node "Other" holding `other`.
std::string attribute_scene(const std::string& mass, const std::string& other) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="P">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <SparseLDLSolver/>
    <MechanicalObject position="0 0 0"/>
)" + mass + R"(
    <RestShapeSpringsForceField stiffness="100"/>
  </Node>
  <Node name="Other">
    <MechanicalObject position="0 0 0"/>
)" + other +
           R"(
  </Node>
</Node>)";
}

double attribute_step_y(const std::string& mass, const std::string& other) {
    auto s = build(attribute_scene(mass, other));
    s->step();
    return dynamic_cast<const Vec3Object&>(*s->states().front().state).position[0].y();
}

double attribute_expected_y(double m) { return 0.01 * (0.01 * m * -10.0 / (m + 0.01 * 0.01 * 100.0)); }

TEST(Attributes, AValueLinkedFromAnotherComponentsData) {
    EXPECT_NEAR(attribute_step_y(R"(    <UniformMass totalMass="2"/>)", ""), attribute_expected_y(2), 1e-17);
    EXPECT_NEAR(attribute_step_y(R"(    <UniformMass totalMass="@../Other/m.totalMass"/>)",
                                 R"(    <UniformMass name="m" totalMass="2"/>)"),
                attribute_expected_y(2), 1e-17);
    // a chain: P's mass → Other's m → Other/C's n
    EXPECT_NEAR(attribute_step_y(R"(    <UniformMass totalMass="@../Other/m.totalMass"/>)",
                                 R"(    <UniformMass name="m" totalMass="@C/n.totalMass"/>
    <Node name="C"><MechanicalObject position="0 0 0"/><UniformMass name="n" totalMass="4"/></Node>)"),
                attribute_expected_y(4), 1e-17);
    // the linked component does not write it: its default (a MeshMatrixMass's totalMass, 1)
    EXPECT_NEAR(attribute_step_y(R"(    <UniformMass totalMass="@../Other/C/mm.totalMass"/>)",
                                 R"(    <Node name="C"><MechanicalObject position="0 0 0  1 0 0  0 1 0  0 0 1"/>
      <MeshTopology tetrahedra="0 1 2 3"/><MeshMatrixMass name="mm" massDensity="3"/></Node>)"),
                attribute_expected_y(1), 1e-17);
}

TEST(Attributes, RefusalsNameTheLineTheComponentAndTheAttribute) {
    EXPECT_EQ(error_of(attribute_scene(R"(    <UniformMass totalMass="@../Other/m"/>)",
                                       R"(    <UniformMass name="m" totalMass="2"/>)")),

              "test.scn:6: UniformMass: attribute 'totalMass': a link to a value must name a component's Data "
              "(@component.data), found '@../Other/m'");
    EXPECT_EQ(error_of(attribute_scene(R"(    <UniformMass name="self" totalMass="@self.totalMass"/>)", "")),
              "test.scn:6: UniformMass 'self': attribute 'totalMass': a chain of more than 16 links");
    EXPECT_EQ(error_of(attribute_scene(R"(    <UniformMass totalMass="@../Other/u.totalMass"/>)",
                                       R"(    <UniformMass name="u" vertexMass="1"/>)")),

              "test.scn:6: UniformMass: attribute 'totalMass': links to Data 'totalMass' of UniformMass 'u', which the "
              "scene does not give and penalty does not compute there");
    EXPECT_EQ(error_of(attribute_scene(R"(    <UniformMass totalMass="0"/>)", "")),
              "test.scn:6: UniformMass: attribute 'totalMass': must be > 0, found '0'");
    // a linked value is checked: the message gives the value and the link it came through
    EXPECT_EQ(error_of(attribute_scene(R"(    <UniformMass totalMass="@../Other/m.totalMass"/>)",
                                       R"(    <UniformMass name="m" totalMass="-2"/>)")),
              "test.scn:6: UniformMass: attribute 'totalMass': must be > 0, found '-2' through "
              "'@../Other/m.totalMass'");
    EXPECT_EQ(
        error_of(attribute_scene(R"(    <UniformMass totalMass="1"/>)",
                                 R"(    <Node name="V"><MechanicalObject template="Vec2d" position="0 0"/></Node>)")),

        "test.scn:11: MechanicalObject: template 'Vec2d' is not supported (Vec3d or Rigid3d)");
}

}  // namespace
