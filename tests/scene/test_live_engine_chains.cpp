// Engines over moving points beyond BoxROI and TransformEngine (src/scene/live_engines.cpp):
// SphereROI, PlaneROI, MeshROI, ProximityROI and TransformPosition run again on read after their
// input moved; chains of engines run in dependency order; FixedPlaneProjectiveConstraint and
// PartialFixedProjectiveConstraint follow the indices. The trajectories are SOFA HEAD's (2a278d8,
// `sofa-head SCENE 60 OUT --every 1`, %.17g), bit for bit.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/falling_beam.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace {

using namespace penalty;

using test::falling_beam;

/// A chain (a BoxROI over a TransformEngine over the positions) fixes points; a SphereROI over the
/// positions feeds a FixedPlaneProjectiveConstraint that removes their vertical response.
const std::string kChainAndBall =
    R"(    <TransformEngine name="lift" input_position="@dofs.position" translation="0 0.4 0"/>
    <BoxROI name="box" box="-0.1 -0.2 -0.1  1.1 0.2 0.6" position="@lift.output_position"/>
    <FixedProjectiveConstraint name="fix" indices="@box.indices"/>
    <SphereROI name="ball" centers="2 -0.5 0.25" radii="0.45" position="@dofs.position"/>
    <FixedPlaneProjectiveConstraint name="plane" direction="0 1 0" indices="@ball.indices"/>
)";

/// A chain (a PlaneROI over a TransformPosition over the positions) feeds a
/// PartialFixedProjectiveConstraint (y only); a ProximityROI (the 2 points nearest a centre)
/// feeds a FixedProjectiveConstraint.
const std::string kSlabAndNearest =
    R"(    <TransformPosition name="shift" method="translation" translation="0 0.4 0" input_position="@dofs.position"/>
    <PlaneROI name="slab" plane="-0.1 -0.2 -0.1  1.1 -0.2 -0.1  1.1 -0.2 0.6  0.4" position="@shift.output_position"/>
    <PartialFixedProjectiveConstraint name="partial" indices="@slab.indices" fixedDirections="0 1 0"/>
    <ProximityROI name="near" centers="2 -0.6 0" radii="0.3" N="2" position="@dofs.position"/>
    <FixedProjectiveConstraint name="fix" indices="@near.indices"/>
)";

const std::vector<Vec3>& positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Beam/dofs", false}, "position").state).position;
}

std::vector<double> numbers(scene::Scene& s, const std::string& path, const std::string& data) {
    return s.data({path, false}, data).numbers;
}

TEST(LiveEngineChains, BoxRoiOverATransformEngineAndSphereRoiFollowTheFallAsSofaHead) {
    auto s = test::build(falling_beam(kChainAndBall));
    const std::vector<Vec3>& x = positions(*s);
    for (int k = 0; k < 20; ++k) s->step();
    // SOFA HEAD's indices after step 20 (SofaPython3: box.indices.value, ball.indices.value)
    EXPECT_EQ(numbers(*s, "/Beam/box", "indices"), (std::vector<double>{0, 1, 2, 10, 11, 12}));
    EXPECT_EQ(numbers(*s, "/Beam/ball", "indices"), (std::vector<double>{4, 14}));
    for (int k = 20; k < 30; ++k) s->step();
    EXPECT_EQ(x[0], Vec3(0.0053870399536623172, -0.40835088276520282, -1.4758194199527282e-06));
    EXPECT_EQ(x[4], Vec3(2.0085655080150886, -0.3505066191798008, -0.00019137434133056905));
    EXPECT_EQ(x[7], Vec3(0.99283844959870138, 0.11380848561278417, -0.00033411621994080669));
    EXPECT_EQ(x[19], Vec3(1.9903075651766213, 0.14796976507239687, 0.50009661493090962));
    for (int k = 30; k < 60; ++k) s->step();
    EXPECT_EQ(x[0], Vec3(0.029136539239057527, -1.0930438598127825, 0.00012938394266658491));
    EXPECT_EQ(x[4], Vec3(2.0200064204428725, -0.81740803538453932, -0.00018666390072220792));
    EXPECT_EQ(x[7], Vec3(0.95863639030272929, -0.47452421940446898, -0.00077736227454086051));
    EXPECT_EQ(x[19], Vec3(1.942755154659753, -0.32446271783151537, 0.5000290852566045));
    EXPECT_EQ(numbers(*s, "/Beam/plane", "indices"), (std::vector<double>{4, 9, 14, 19}));
}

TEST(LiveEngineChains, FixedPlaneKeepsThePointsItsInitAppendedUntilTheEngineRunsAgainAsSofaHead) {
    std::string engines = kChainAndBall;
    const std::string plane = R"(direction="0 1 0" indices)";
    engines.replace(engines.find(plane), plane.size(), R"(direction="0 1 0" dmin="-0.1" dmax="0.1" indices)");
    auto s = test::build(falling_beam(engines));
    const std::vector<Vec3>& x = positions(*s);
    // init appends the points of -0.1 < y < 0.1 to the ball's (empty) selection: step 1 keeps their
    // height; then the positions moved, the ball runs again and the list is its output alone
    s->step();
    EXPECT_EQ(x[0], Vec3(-1.8905489485838926e-05, 0, -7.087349329894208e-06));
    EXPECT_EQ(x[4], Vec3(2.0000189054894859, 0, -7.0873493298942097e-06));
    s->step();
    EXPECT_EQ(x[0], Vec3(-2.0000689182906614e-05, -0.0010107023212544853, -6.8241560437884146e-06));
    for (int k = 2; k < 30; ++k) s->step();
    EXPECT_EQ(x[0], Vec3(0.0049425730904242892, -0.38896472377142138, -1.5187977858169276e-06));
    EXPECT_EQ(x[4], Vec3(2.0079525558875595, -0.33576951817958406, -0.00018360196069275997));
}

TEST(LiveEngineChains, PlaneRoiOverATransformPositionAndProximityRoiFollowTheFallAsSofaHead) {
    auto s = test::build(falling_beam(kSlabAndNearest));
    const std::vector<Vec3>& x = positions(*s);
    for (int k = 0; k < 30; ++k) s->step();
    EXPECT_EQ(x[0], Vec3(-0.00014770688894837259, -0.45116295257725914, -0.0010106209286924038));
    EXPECT_EQ(x[4], Vec3(2.0000000011490271, -0.43702066278453156, -5.8438002973758838e-09));
    EXPECT_EQ(x[9], Vec3(1.9965791493787746, 0.062011855333072088, 0.0041853342103030655));
    EXPECT_EQ(x[19], Vec3(1.99623112421542, 0.057544980786697973, 0.50423565420295768));
    for (int k = 30; k < 45; ++k) s->step();
    // SOFA HEAD's after step 45: ProximityROI lists the nearest last (its heap's order)
    EXPECT_EQ(numbers(*s, "/Beam/near", "indices"), (std::vector<double>{9, 4}));
    for (int k = 45; k < 60; ++k) s->step();
    EXPECT_EQ(x[0], Vec3(0.0081395499929774028, -1.34510511031507, -0.020809239279375426));
    EXPECT_EQ(x[4], Vec3(2.0032664293092228, -1.1652976122193419, -0.0057755771057721624));
    EXPECT_EQ(x[9], Vec3(1.9569666296810528, -0.66953697863403294, 0.048863207916505259));
    EXPECT_EQ(x[19], Vec3(1.9567590598972586, -0.7274059789779922, 0.54570967260062675));
    // SOFA HEAD's: the slab held 5 6 7 15 16 17 from step 47 to 57; the beam falls through it
    EXPECT_EQ(numbers(*s, "/Beam/slab", "indices"), (std::vector<double>{7}));
}

/// Four points of a state without a solver, which the test moves by writing `position`.
std::string four_points(const std::string& engines) {
    return R"(<Node name="root" dt="0.01">
  <Node name="Points">
    <MechanicalObject name="dofs" position="0 0 0  1 0 0  2 0 0  3 0 0"/>
)" + engines +
           R"(  </Node>
</Node>)";
}

void move_points(scene::Scene& s, const std::string& text) { s.set_data({"/Points/dofs", false}, "position", text); }

TEST(LiveEngineChains, EachEngineSelectsAgainAfterItsInputMoved) {
    auto s =
        test::build(four_points(R"(    <SphereROI name="ball" centers="0 2 0" radii="1.5" position="@dofs.position"/>
    <PlaneROI name="slab" plane="-1 1.5 -1  4 1.5 -1  4 1.5 1  1" position="@dofs.position"/>
    <ProximityROI name="near" centers="3 3 0" radii="10" N="2" position="@dofs.position"/>
    <MeshROI name="cube" position="@dofs.position" ROIposition="-0.45 1.1 -0.3  1.3 1.1 -0.3  1.3 2.9 -0.3  -0.45 2.9 -0.3
      -0.45 1.1 0.45  1.3 1.1 0.45  1.3 2.9 0.45  -0.45 2.9 0.45"
      ROItriangles="0 2 1  0 3 2  4 5 6  4 6 7  0 1 5  0 5 4  3 7 6  3 6 2  0 4 7  0 7 3  1 2 6  1 6 5"/>
    <TransformPosition name="flat" method="projectOnPlane" origin="0 0 0" normal="1 0 0" input_position="@dofs.position"/>
)"));
    // at init every point is at y = 0: outside the ball (centre y 2), the slab (x in [-1, 4],
    // y in [1, 2], z in [-1, 1]) and the cube (x in [-0.45, 1.3], y in [1.1, 2.9], z in [-0.3, 0.45], off-centre so
    // that MeshROI's ray from a point to a corner of the box crosses no edge); the two nearest (3, 3, 0) are 3 and 2,
    // listed in the order of ProximityROI's heap (the farther first)
    EXPECT_TRUE(numbers(*s, "/Points/ball", "indices").empty());
    EXPECT_TRUE(numbers(*s, "/Points/slab", "indices").empty());
    EXPECT_TRUE(numbers(*s, "/Points/cube", "indices").empty());
    EXPECT_EQ(numbers(*s, "/Points/near", "indices"), (std::vector<double>{2, 3}));
    // points 0 and 1 up to y = 1.5 (distances to the ball's centre 0.5 and 1.118), 3 up to y = 3.5
    move_points(*s, "0 1.5 0  1 1.5 0  2 0 0  3 3.5 0");
    EXPECT_EQ(numbers(*s, "/Points/ball", "indices"), (std::vector<double>{0, 1}));
    EXPECT_EQ(numbers(*s, "/Points/slab", "indices"), (std::vector<double>{0, 1}));
    EXPECT_EQ(numbers(*s, "/Points/cube", "indices"), (std::vector<double>{0, 1}));
    // nearest (3, 3, 0): point 3 at 0.5, point 1 at 2.5 (point 2 at 3.16, point 0 at 3.35)
    EXPECT_EQ(numbers(*s, "/Points/near", "indices"), (std::vector<double>{1, 3}));
    // projected on the plane x = 0
    EXPECT_EQ(numbers(*s, "/Points/flat", "output_position"),
              (std::vector<double>{0, 1.5, 0, 0, 1.5, 0, 0, 0, 0, 0, 3.5, 0}));
}

TEST(LiveEngineChains, AChainRunsTheEngineBeforeItFirst) {
    // a BoxROI over a TransformEngine over a TransformPosition over the state
    auto s = test::build(four_points(
        R"(    <TransformPosition name="up" method="translation" translation="0 1 0" input_position="@dofs.position"/>
    <TransformEngine name="double" input_position="@up.output_position" scale="2 2 2"/>
    <BoxROI name="box" box="1.5 2.5 -1  4.5 3.5 1" position="@double.output_position"/>
)"));
    // init: (2i, 2, 0): none has y in [2.5, 3.5]
    EXPECT_TRUE(numbers(*s, "/Points/box", "indices").empty());
    // point 1 to (1, 0.5, 0) → (2, 3, 0) inside; point 2 to (2, 0.5, 0) → (4, 3, 0) inside;
    // point 3 to (3, 0.5, 0) → (6, 3, 0) outside in x
    move_points(*s, "0 0 0  1 0.5 0  2 0.5 0  3 0.5 0");
    EXPECT_EQ(numbers(*s, "/Points/box", "indices"), (std::vector<double>{1, 2}));
    EXPECT_EQ(numbers(*s, "/Points/double", "output_position"),
              (std::vector<double>{0, 2, 0, 2, 3, 0, 4, 3, 0, 6, 3, 0}));
    move_points(*s, "0 0 0  1 0 0  2 0 0  3 0 0");
    EXPECT_TRUE(numbers(*s, "/Points/box", "indices").empty());
}

TEST(LiveEngineChains, DoUpdateZeroOverAChainKeepsTheSelectionOfInitWithoutAWarning) {
    auto s =
        test::build(four_points(R"(    <TransformEngine name="up" input_position="@dofs.position" translation="0 1 0"/>
    <SphereROI name="ball" centers="0 1 0" radii="0.5" position="@up.output_position" doUpdate="0"/>
)"));
    EXPECT_EQ(numbers(*s, "/Points/ball", "indices"), (std::vector<double>{0}));
    move_points(*s, "1 0 0  0 0 0  2 0 0  3 0 0");
    EXPECT_EQ(numbers(*s, "/Points/ball", "indices"), (std::vector<double>{0}));
    const std::vector<std::string> w = s->warnings();
    EXPECT_EQ(w.end(), std::find_if(w.begin(), w.end(), [](const std::string& text) {
                  return text.find("engine over moving positions") != std::string::npos;
              }));
}

}  // namespace
