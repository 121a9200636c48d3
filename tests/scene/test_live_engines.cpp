// Engines over moving states, run on read (src/scene/live_engines.hpp): a BoxROI over
// `@dofs.position` feeding a FixedProjectiveConstraint fixes the points that fall into its box,
// step by step, bit for bit with SOFA HEAD; a state whose position links a TransformEngine over
// moving positions follows them after each step; a scene without such a link has no live engine.
#include "penalty/mechanics/transform_engines.hpp"
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/falling_beam.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace {

using namespace penalty;
using ::testing::HasSubstr;

/// A 5x2x2 grid of springs falling under gravity; a BoxROI over its moving positions feeds a
/// FixedProjectiveConstraint: the points of x <= 1 that fall into the box y in [-0.6, -0.2] stop
/// accelerating (FixedProjectiveConstraint keeps their velocity: activate_projectVelocity is 0),
/// then leave the box at constant speed and fall again.
std::string beam_falling_into_box(const std::string& do_update = "1") {
    return test::falling_beam(
        R"(    <BoxROI name="box" box="-0.1 -0.6 -0.1  1.1 -0.2 0.6" position="@dofs.position" doUpdate=")" +
        do_update + R"("/>
    <FixedProjectiveConstraint name="fix" indices="@box.indices"/>
)");
}

const std::vector<Vec3>& moving_state_positions(scene::Scene& s, const std::string& path) {
    return dynamic_cast<const Vec3Object&>(*s.data({path, false}, "position").state).position;
}

std::vector<double> moving_engine_indices(scene::Scene& s, const std::string& path, const std::string& data) {
    return s.data({path, false}, data).numbers;
}

TEST(LiveEngines, BoxRoiOverMovingPositionsFixesThePointsThatFallIntoItAsSofaHead) {
    auto s = test::build(beam_falling_into_box());
    EXPECT_TRUE(moving_engine_indices(*s, "/Beam/box", "indices").empty());  // nothing in the box at init
    for (int k = 0; k < 25; ++k) s->step();
    // SOFA HEAD (2a278d8), the same scene, `sofa-head SCENE 60 OUT --every 1`: step 25
    const std::vector<Vec3>& x = moving_state_positions(*s, "/Beam/dofs");
    EXPECT_EQ(x[0], Vec3(-7.8282170945794033e-12, -0.30158536548834619, -2.4150902663972015e-09));
    EXPECT_EQ(x[4], Vec3(1.9990756613852376, -0.30970030543458232, 1.7115925347740484e-05));
    EXPECT_EQ(x[7], Vec3(1.0016991046387009, 0.19750674606352314, 0.0001805162700368692));
    EXPECT_EQ(x[19], Vec3(2.0027502501823014, 0.19027805233980077, 0.50002049208651789));
    // the lower points of x <= 1 are in the box (read now, from the positions of step 25)
    EXPECT_EQ(moving_engine_indices(*s, "/Beam/box", "indices"), (std::vector<double>{0, 1, 2, 10, 11, 12}));
    EXPECT_EQ(moving_engine_indices(*s, "/Beam/fix", "indices"), (std::vector<double>{0, 1, 2, 10, 11, 12}));
    for (int k = 25; k < 60; ++k) s->step();
    EXPECT_EQ(x[0], Vec3(-0.0026380994641987403, -1.0412261741193267, 3.168945747275121e-05));
    EXPECT_EQ(x[4], Vec3(1.9871818925550955, -1.1154158757113946, 6.1383976319079054e-05));
    EXPECT_EQ(x[7], Vec3(1.0094664242227576, -0.56521358704675095, -0.00029354997531591439));
    EXPECT_EQ(x[19], Vec3(2.0120552086651307, -0.61601186921330864, 0.50006014165813506));
    // then the points of x in [1, 2] are in the box (SOFA HEAD's BoxROI.indices after step 60)
    EXPECT_EQ(moving_engine_indices(*s, "/Beam/box", "indices"), (std::vector<double>{5, 6, 7, 15, 16, 17}));
}

TEST(LiveEngines, FixedPointsKeepTheirVelocityWhileInTheBox) {
    auto s = test::build(beam_falling_into_box());
    for (int k = 0; k < 25; ++k) s->step();
    const auto& v = dynamic_cast<const Vec3Object&>(*s->data({"/Beam/dofs", false}, "velocity").state).velocity;
    const Vec3 before = v[0];
    s->step();  // point 0 stays in the box: its response is 0, its velocity unchanged (not zeroed)
    EXPECT_EQ(v[0], before);
    EXPECT_LT(before.y(), -1.0);
}

TEST(LiveEngines, DoUpdateZeroKeepsTheSelectionOfInit) {
    auto s = test::build(beam_falling_into_box("0"));
    for (int k = 0; k < 25; ++k) s->step();
    EXPECT_TRUE(moving_engine_indices(*s, "/Beam/fix", "indices").empty());
    // free fall: the points of x <= 1 went on accelerating
    EXPECT_LT(moving_state_positions(*s, "/Beam/dofs")[0].y(), -0.31);
}

TEST(LiveEngines, StateLinkedToATransformEngineOverMovingPositionsFollowsThemEachStep) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="5" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="0.5" zmin="0" zmax="0.5"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="200" damping="0.1"/>
    <FixedProjectiveConstraint indices="0 10"/>
  </Node>
  <Node name="Image">
    <TransformEngine name="transform" input_position="@../Beam/dofs.position" translation="3 0 0"
                     rotation="0 0 30" scale="1 2 1"/>
    <MechanicalObject name="copy" position="@transform.output_position"/>
  </Node>
</Node>)";
    auto s = test::build(xml);
    TransformEngineParameters p;
    p.translation = Vec3(3, 0, 0);
    p.rotation_deg = Vec3(0, 0, 30);
    p.scale = Vec3(1, 2, 1);
    const std::vector<Vec3>& beam = moving_state_positions(*s, "/Beam/dofs");
    const std::vector<Vec3>& copy = moving_state_positions(*s, "/Image/copy");
    for (int k = 0; k < 60; ++k) {
        s->step();
        ASSERT_EQ(copy, transform_engine(beam, p)) << "step " << k + 1;
    }
    // SOFA HEAD through SofaPython3 (copy.position.value after 60 animate calls): point 4
    EXPECT_EQ(copy[4], Vec3(5.676444200600734, -2.2398382388027867, 0.00014346191950923755));
}

TEST(LiveEngines, AFollowedReaderIsNotNamedInTheWarnings) {
    auto s = test::build(beam_falling_into_box());
    EXPECT_EQ(s->warnings().end(), std::find_if(s->warnings().begin(), s->warnings().end(), [](const std::string& w) {
                  return w.find("engine over moving positions") != std::string::npos;
              }));
}

TEST(LiveEngines, AReaderPenaltyCannotFollowIsNamedInTheWarnings) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="Beam">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="3" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="0.5" zmin="0" zmax="0.5"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <BoxROI name="box" box="-0.1 -0.1 -0.1  1.1 0.6 0.6" position="@dofs.position"/>
    <RestShapeSpringsForceField name="hold" points="@box.indices" stiffness="10" recompute_indices="0"/>
  </Node>
</Node>)";
    auto s = test::build(xml);
    const std::vector<std::string> w = s->warnings();
    EXPECT_NE(w.end(), std::find_if(w.begin(), w.end(), [](const std::string& text) {
                  return text.find(
                             "RestShapeSpringsForceField 'hold': attribute 'points' links BoxROI 'box'.indices, an "
                             "engine over moving positions: penalty reads it once") != std::string::npos;
              }));
}

}  // namespace
