// Components that only make what is drawn (builder/drawing_components.cpp): a beam's tube quads
// (Edge2QuadTopologicalMapping) and surface (TubularMapping) are accepted where they feed a visual
// model only, change nothing simulated, and are refused where they would feed a MechanicalObject,
// naming the file, line, component and attribute.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using test::build;
using test::error_of;
using ::testing::HasSubstr;

std::string drawing_replaced(std::string xml, const std::string& what, const std::string& by) {
    xml.replace(xml.find(what), what.size(), by);
    return xml;
}

const Node& drawing_child(const Node& n, std::size_t i) { return *n.children()[i]; }

TEST(MultiMappingComponents, MappingsThatOnlyFeedDrawingAreAccepted) {
    // an IdentityMapping without output in a node holding an OglModel and no MechanicalObject maps
    // onto the visual model (SOFA's Mapping::create links "@./"): nothing simulated
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Beam"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <RegularGridTopology name="line" nx="4" ny="1" nz="1" xmin="0" xmax="3" ymin="0" ymax="0" zmin="0" zmax="0"/>
    <MechanicalObject template="Rigid3" name="frames"/>
    <UniformMass totalMass="1"/>
    <Node name="Visu"><OglModel name="visual"/><IdentityMapping/></Node>
    <Node name="Tube">
      <OglModel name="surface"/>
      <QuadSetTopologyContainer name="quads"/>
      <Edge2QuadTopologicalMapping nbPointsOnEachCircle="8" radius="1" input="@../line" output="@quads"/>
      <TubularMapping nbPointsOnEachCircle="8" radius="1" input="@../frames" output="@surface"/>
    </Node>
  </Node>
</Node>)";
    auto s = build(xml);
    const Node& beam = drawing_child(s->simulation().root(), 0);
    EXPECT_EQ(drawing_child(beam, 0).mapping(), nullptr);
    EXPECT_EQ(drawing_child(beam, 1).mapping(), nullptr);
    // onto a MechanicalObject they are refused, naming the attribute
    const std::string mechanical = drawing_replaced(
        drawing_replaced(xml, R"(<OglModel name="surface"/>)", R"(<MechanicalObject name="surface"/>)"),
        R"(<TubularMapping nbPointsOnEachCircle="8" radius="1" input="@../frames" output="@surface"/>)", "");
    EXPECT_THAT(error_of(mechanical), HasSubstr("test.scn:10: Edge2QuadTopologicalMapping: attribute 'output': feeds "
                                                "node '/Beam/Tube', which has a MechanicalObject"));
}

/// A beam of four Rigid3 frames held by springs, its first one fixed, with `tube` in its node.
std::string beam_with(const std::string& tube) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Beam"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <RegularGridTopology name="line" nx="4" ny="1" nz="1" xmin="0" xmax="3" ymin="0" ymax="0" zmin="0" zmax="0"/>
    <MechanicalObject template="Rigid3" name="frames"/>
    <UniformMass totalMass="1"/>
    <RestShapeSpringsForceField stiffness="50" angularStiffness="20" points="1 2 3"/>
    <FixedProjectiveConstraint indices="0"/>
)" + tube + R"(  </Node>
</Node>)";
}

const std::string kTube = R"(    <Node name="Tube">
      <OglModel name="surface"/>
      <QuadSetTopologyContainer name="quads"/>
      <Edge2QuadTopologicalMapping nbPointsOnEachCircle="8" radius="1" input="@../line" output="@quads"/>
      <TubularMapping nbPointsOnEachCircle="8" radius="1" input="@../frames" output="@surface"/>
    </Node>
)";
const std::string kBeamWithTube = beam_with(kTube);

TEST(DrawingComponents, ATubeForDrawingChangesNothingSimulated) {
    // the beam with and without its tube node: the same frames, bit for bit, after 20 steps
    auto with_tube = build(kBeamWithTube);
    auto without = build(beam_with(""));
    for (int k = 0; k < 20; ++k) {
        with_tube->step();
        without->step();
    }
    const auto& a = dynamic_cast<const Rigid3Object&>(*with_tube->data({"/Beam/frames", false}, "position").state);
    const auto& b = dynamic_cast<const Rigid3Object&>(*without->data({"/Beam/frames", false}, "position").state);
    ASSERT_EQ(a.position.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(a.position[i].center, b.position[i].center) << i;
        EXPECT_EQ(a.position[i].orientation.coeffs(), b.position[i].orientation.coeffs()) << i;
    }
    EXPECT_LT(a.position[3].center.y(), -0.01);  // the beam sags: something was simulated
}

TEST(DrawingComponents, WhatWouldFeedAMechanicalObjectIsRefusedNamingTheAttribute) {
    // TubularMapping onto a MechanicalObject
    EXPECT_EQ(error_of(drawing_replaced(kBeamWithTube, R"(<OglModel name="surface"/>)",
                                        R"(<MechanicalObject name="surface"/>)")),
              "test.scn:11: Edge2QuadTopologicalMapping: attribute 'output': feeds node '/Beam/Tube', which has a "
              "MechanicalObject: penalty builds the tube's quads only for drawing (a node without a "
              "MechanicalObject)");
    const std::string no_quads = drawing_replaced(
        drawing_replaced(kBeamWithTube, R"(<OglModel name="surface"/>)", R"(<MechanicalObject name="surface"/>)"),
        R"(<Edge2QuadTopologicalMapping nbPointsOnEachCircle="8" radius="1" input="@../line" output="@quads"/>)", "");
    EXPECT_EQ(error_of(no_quads),
              "test.scn:12: TubularMapping: attribute 'output': penalty maps a tube only onto a visual model "
              "(OglModel), not onto a MechanicalObject");
    // the quad mapping without its output
    EXPECT_EQ(error_of(drawing_replaced(kBeamWithTube, R"( output="@quads")", "")),
              "test.scn:11: Edge2QuadTopologicalMapping: attribute 'output': names the quad container the tube is "
              "made in");
}

}  // namespace
