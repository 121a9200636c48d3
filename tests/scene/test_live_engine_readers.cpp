// Readers of a live engine's output beyond the projective constraints, and engines following
// inputs beyond their points (src/scene/live_engines.cpp). A SphereROI whose centres link a ball's
// moving positions selects the beam points the ball passes, the ball as of each step's start
// while the step runs. A ConstantForceField whose `indices` link a BoxROI over moving positions takes them at each
// addForce and runs SOFA's update callbacks when they change (ConstantForceField::updateFromIndices,
// updateFromForcesVector, updateFromTotalForce): one `forces` value, spread over the count of init,
// no longer fits a new count and the component is Invalid (no force); a `totalForce` is spread
// again. A RestShapeSpringsForceField's `points` linking it hold the points still in the box. The
// trajectories are SOFA HEAD's (2a278d8, `sofa-head SCENE 40 OUT --every 1`, %.17g), bit
// for bit, on a cantilever whose free end sags out of the box (20, then 18, 16 and 14 points in it).
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/falling_beam.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include <string>
#include <utility>
#include <vector>

namespace {

using namespace penalty;

/// The beam held at x = 0; a BoxROI around its points at init feeds `reader` (before the springs:
/// SOFA's order of the sum).
std::string cantilever_in_box(const std::string& reader) {
    return test::falling_beam(R"(    <FixedProjectiveConstraint indices="0 5 10 15"/>
)",
                              R"(    <BoxROI name="box" box="-0.1 -0.05 -0.1  2.1 0.6 0.6" position="@dofs.position"/>
    )" + reader + "\n");
}

const std::vector<Vec3>& reader_beam_positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Beam/dofs", false}, "position").state).position;
}

std::size_t points_in_box(scene::Scene& s) { return s.data({"/Beam/box", false}, "indices").numbers.size(); }

TEST(LiveEngineReaders, ConstantForceFieldWithOneForceIsInvalidOnceTheFollowedIndicesChangeCount) {
    auto s =
        test::build(cantilever_in_box(R"(<ConstantForceField name="push" indices="@box.indices" forces="0 -0.5 0"/>)"));
    const std::vector<Vec3>& x = reader_beam_positions(*s);
    for (int k = 0; k < 10; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 16U);
    // SOFA HEAD: the 20 forces of init no longer fit (updateFromForcesVector: Invalid, no force)
    EXPECT_EQ(x[4], Vec3(1.9849291851993416, -0.091178249334574302, 3.9602148622416299e-05));
    EXPECT_EQ(x[19], Vec3(2.0116790262214672, 0.40817041300676549, 0.50003212730506674));
    for (int k = 10; k < 40; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 14U);
    // without the force the beam springs back up
    EXPECT_EQ(x[4], Vec3(1.9474345206662571, -0.23551976738219282, 9.7205503432081167e-05));
    EXPECT_EQ(x[19], Vec3(2.0228286138950953, 0.25876609876646894, 0.50007240501292971));
}

TEST(LiveEngineReaders, ConstantForceFieldSpreadsItsTotalForceOverTheFollowedIndices) {
    auto s = test::build(
        cantilever_in_box(R"(<ConstantForceField name="push" indices="@box.indices" totalForce="0 -3 0"/>)"));
    const std::vector<Vec3>& x = reader_beam_positions(*s);
    for (int k = 0; k < 10; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 18U);
    // SOFA HEAD: T / 18 on each point in the box, then T / 16, T / 14 (updateFromTotalForce)
    EXPECT_EQ(x[4], Vec3(1.9901306309339966, -0.06305369382870285, 2.4666572693337988e-05));
    EXPECT_EQ(x[19], Vec3(2.0083003288498449, 0.43663448631303647, 0.50002400089920895));
    for (int k = 10; k < 40; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 14U);
    EXPECT_EQ(x[4], Vec3(1.9364712726168873, -0.27310608332049879, 9.3116151874950314e-05));
    EXPECT_EQ(x[19], Vec3(2.0237778737312744, 0.21906614328469079, 0.50009358434268136));
}

/// A controller's write of ConstantForceField.indices after 5 steps (SofaPython3:
/// `push.indices.value = [...]` before the 6th animate), then 15 more steps: the positions of
/// points 4 and 9 after step 20.
std::pair<Vec3, Vec3> after_indices_written(const std::string& indices) {
    auto s = test::build(test::falling_beam(R"(    <FixedProjectiveConstraint indices="0 5 10 15"/>
)",
                                            R"(    <ConstantForceField name="push" indices="1 2 3 4" forces="0 -0.5 0"/>
)"));
    for (int k = 0; k < 5; ++k) s->step();
    s->set_data({"/Beam/push", false}, "indices", indices);
    for (int k = 5; k < 20; ++k) s->step();
    const std::vector<Vec3>& x = reader_beam_positions(*s);
    return {x[4], x[9]};
}

TEST(LiveEngineReaders, ConstantForceFieldIndicesWrittenToAnotherCountMakeItInvalidAsSofaHead) {
    // SOFA HEAD through SofaPython3: the 4 forces the single value became no longer fit 3 indices
    // (no force from step 6 on); 4 other indices take them
    const auto [x4, x9] = after_indices_written("1 2 3");
    EXPECT_EQ(x4, Vec3(1.972799442348448, -0.14289252821982693, 0.0005097601067403427));
    EXPECT_EQ(x9, Vec3(2.01715633371499, 0.35522759198573856, -0.0006835345480050041));
    const auto [y4, y9] = after_indices_written("6 7 8 9");
    EXPECT_EQ(y4, Vec3(1.9675128121263556, -0.16900840704631473, 0.004404641593635944));
    EXPECT_EQ(y9, Vec3(2.0189759847405733, 0.32804872588104894, -0.0034089320536792953));
}

TEST(LiveEngineReaders, RestShapeSpringsFollowTheirPointsAsSofaHead) {
    // the springs hold the points still in the box (RestShapeSpringsForceField::addForce's
    // recomputeIndices reads d_points): 20 points, then 18, 16 and 14
    auto s = test::build(
        cantilever_in_box(R"(<RestShapeSpringsForceField name="hold" points="@box.indices" stiffness="2"/>)"));
    const std::vector<Vec3>& x = reader_beam_positions(*s);
    for (int k = 0; k < 20; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 16U);
    // SOFA HEAD (`sofa-head SCENE 60 OUT --every 1`)
    EXPECT_EQ(x[4], Vec3(1.9820579334367652, -0.10088942178378377, 5.7095533984223099e-05));
    EXPECT_EQ(x[19], Vec3(2.012883411346932, 0.39831266726854264, 0.50002350350968461));
    for (int k = 20; k < 60; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 14U);
    EXPECT_EQ(x[4], Vec3(1.9709751546824927, -0.14825648298057467, 8.7067048757523828e-05));
    EXPECT_EQ(x[19], Vec3(2.0170193128708074, 0.34985607102764343, 0.50002690916138381));
}

/// A ball moving down at 3 m/s (falling too) through the falling beam; a SphereROI around the ball
/// (its `centers` link the ball's positions) fixes the beam points it passes. The ball's node
/// comes first: SOFA resolves the link when it parses the ROI.
std::string ball_through_beam(const std::string& engines = R"(
    <SphereROI name="near" centers="@../Ball/ball.position" radii="0.45" position="@dofs.position"/>)") {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Ball">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="ball" position="1.5 1.5 0.25" velocity="0 -3 0"/>
    <UniformMass totalMass="1"/>
  </Node>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="5" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="0.5" zmin="0" zmax="0.5"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="200" damping="0.1"/>
    )" + engines +
           R"(
    <FixedProjectiveConstraint name="fix" indices="@near.indices"/>
  </Node>
</Node>)";
}

std::vector<double> selected(scene::Scene& s) { return s.data({"/Beam/near", false}, "indices").numbers; }

TEST(LiveEngineInputs, SphereRoiCentresFollowAMovingStateAsSofaHead) {
    auto s = test::build(ball_through_beam());
    const std::vector<Vec3>& x = reader_beam_positions(*s);
    for (int k = 0; k < 20; ++k) s->step();
    EXPECT_TRUE(selected(*s).empty());
    s->step();  // the ball of step 20 selects nothing during step 21; after it, the ball of step 21 does
    EXPECT_EQ(selected(*s), (std::vector<double>{8, 18}));
    for (int k = 21; k < 25; ++k) s->step();
    // SOFA HEAD (`sofa-head SCENE 60 OUT --every 1`): points 8 and 18 fixed from step 22 on
    EXPECT_EQ(x[3], Vec3(1.5015902078448213, -0.30707244089876495, -9.810847472497861e-05));
    EXPECT_EQ(x[8], Vec3(1.5000000009766248, 0.1936115125492473, -4.0504137247213631e-10));
    EXPECT_EQ(x[18], Vec3(1.5000000009727388, 0.19361151254287695, 0.50000000041180759));
    for (int k = 25; k < 40; ++k) s->step();
    EXPECT_EQ(selected(*s), (std::vector<double>{3, 13}));  // SOFA HEAD's after step 40
    for (int k = 40; k < 45; ++k) s->step();
    EXPECT_EQ(x[3], Vec3(1.5601093311857408, -0.71423301141629258, -0.00042994337570550866));
    EXPECT_EQ(x[8], Vec3(1.4927531262222593, -0.21813364377878525, 0.0001842778515713931));
    EXPECT_EQ(x[18], Vec3(1.4927531237016609, -0.21813364346569203, 0.49981572268139601));
}

TEST(LiveEngineInputs, ProximityRoiCentresAreAnInputThatRunsItAgainAsSofaHead) {
    // ProximityROI adds its centres as an input (unlike SphereROI): during step 15 the ball of
    // step 15 (solved first) selects points 8 and 18 (SOFA HEAD, 60 steps bit for bit)
    auto s = test::build(ball_through_beam(
        R"(<ProximityROI name="near" centers="@../Ball/ball.position" radii="0.6" N="2" position="@dofs.position"/>)"));
    const std::vector<Vec3>& x = reader_beam_positions(*s);
    for (int k = 0; k < 20; ++k) s->step();
    EXPECT_EQ(x[8], Vec3(1.4999999999770972, 0.31575278129932699, -1.5991582076052593e-10));
    EXPECT_EQ(x[18], Vec3(1.4999999999770972, 0.31575278129931661, 0.50000000015990542));
}

TEST(LiveEngineInputs, AnInputPenaltyDoesNotFollowIsNamedInAWarning) {
    // a TransformPosition's normal linking the moving ball's positions (TransformPosition::init
    // normalises it once: penalty does not follow it): SOFA would run it again, penalty reads it once
    auto s = test::build(
        ball_through_beam(R"(<SphereROI name="near" centers="1.5 0 0.25" radii="0.45" position="@dofs.position"/>
    <TransformPosition name="flat" method="projectOnPlane" normal="@../Ball/ball.position" input_position="@dofs.position"/>)"));
    EXPECT_THAT(s->warnings(), ::testing::Contains(::testing::HasSubstr(
                                   "TransformPosition 'flat': input 'normal' links MechanicalObject 'ball'.position, "
                                   "which changes while the scene runs: penalty reads it once")));
    auto followed = test::build(ball_through_beam());
    EXPECT_THAT(followed->warnings(), ::testing::Not(::testing::Contains(::testing::HasSubstr("input 'centers'"))));
}

TEST(LiveEngineInputs, SubsetTopologyAndMergePointsRunAgainAsSofaHead) {
    // a SubsetTopology box over the moving positions fixes the points falling into it (the box of
    // test_live_engines.cpp's BoxROI: SOFA HEAD gives the same trajectory); MergePoints follows
    // the beam (position1) and the ball (position2)
    auto s = test::build(ball_through_beam(
        R"(<SubsetTopology name="near" rest_position="@dofs.position" box="-0.1 -0.6 -0.1  1.1 -0.2 0.6"/>
    <MergePoints name="merge" position1="@dofs.position" position2="@../Ball/ball.position"/>)"));
    const std::vector<Vec3>& x = reader_beam_positions(*s);
    const std::vector<Vec3>& ball =
        dynamic_cast<const Vec3Object&>(*s->data({"/Ball/ball", false}, "position").state).position;
    for (int k = 0; k < 25; ++k) s->step();
    EXPECT_EQ(selected(*s), (std::vector<double>{0, 1, 2, 10, 11, 12}));
    // SOFA HEAD (`sofa-head SCENE 60 OUT --every 1`), step 25
    EXPECT_EQ(x[0], Vec3(-7.8282170945794033e-12, -0.30158536548834619, -2.4150902663972015e-09));
    EXPECT_EQ(x[7], Vec3(1.0016991046387009, 0.19750674606352314, 0.0001805162700368692));
    const auto merged = [&s] { return s->data({"/Beam/merge", false}, "points").numbers; };
    std::vector<double> expected;
    for (const std::vector<Vec3>* part : {&x, &ball})
        for (const Vec3& p : *part) expected.insert(expected.end(), {p.x(), p.y(), p.z()});
    EXPECT_EQ(merged(), expected);
    EXPECT_EQ(ball[0], Vec3(1.5, 0.43117500000000036, 0.25));  // SOFA HEAD's merge.points[20]
    for (int k = 25; k < 60; ++k) s->step();
    EXPECT_EQ(selected(*s), (std::vector<double>{5, 6, 7, 15, 16, 17}));
    EXPECT_EQ(x[0], Vec3(-0.0026380994641987403, -1.0412261741193267, 3.168945747275121e-05));
    EXPECT_EQ(x[7], Vec3(1.0094664242227576, -0.56521358704675095, -0.00029354997531591439));
    EXPECT_EQ(merged()[3 * 20 + 1], -2.095229999999996);
}

}  // namespace
