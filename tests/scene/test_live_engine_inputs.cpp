// Engine inputs besides the points that follow moving data (src/scene/live_engines.cpp,
// kLiveEngineKinds' `followed`): MeshROI's `ROIposition` (its bounding box stays that of init),
// TransformEngine's `translation`, `rotation` and `scale` and BoxROI's `box` linked to the positions
// of states that move (or to an engine's output over them). The trajectories are SOFA HEAD's (2a278d8, `sofa-head SCENE
// 80 OUT --every 1`, %.17g), bit for bit.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace penalty;

/// A node whose one state moves at a constant velocity: its weight is cancelled by a
/// ConstantForceField (both sum to exactly 0), so implicit Euler adds h·v each step.
std::string mover(const std::string& node, const std::string& name, const std::string& position,
                  const std::string& velocity) {
    return "  <Node name=\"" + node + R"(">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name=")" +
           name + "\" position=\"" + position + "\" velocity=\"" + velocity + R"("/>
    <UniformMass totalMass="1"/>
    <ConstantForceField totalForce="0 9.81 0"/>
  </Node>
)";
}

/// The falling beam of the live-engine tests (5x2x2 springs, implicit Euler) after `movers`, with
/// `extra` in its node.
std::string beam_after(const std::string& movers, const std::string& extra) {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
)" + movers +
           R"(  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="5" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="0.5" zmin="0" zmax="0.5"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="200" damping="0.1"/>
)" + extra +
           R"(  </Node>
</Node>)";
}

/// A closed box of 12 triangles, normals outward, on 8 corners (MeshROI's ROI mesh).
const std::string kBoxTriangles = "0 2 1  0 3 2  4 5 6  4 6 7  0 1 5  0 5 4  3 7 6  3 6 2  0 4 7  0 7 3  1 2 6  1 6 5";

const std::vector<Vec3>& falling_beam_positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Beam/dofs", false}, "position").state).position;
}

std::vector<double> data_numbers(scene::Scene& s, const std::string& path, const std::string& data) {
    return s.data({path, false}, data).numbers;
}

void advance_steps(scene::Scene& s, int n) {
    for (int k = 0; k < n; ++k) s.step();
}

/// A cube moving along +x at 1 m/s (x in [-0.21, 0.63] at init, off-centre so that MeshROI's rays
/// cross no edge of its triangles) is the ROI mesh of a MeshROI over the falling beam, whose
/// points in it are fixed.
std::string moving_mesh_roi() {
    return beam_after(mover("Cube", "cube",
                            "-0.21 -0.23 -0.27  0.63 -0.23 -0.27  0.63 0.27 -0.27  -0.21 0.27 -0.27  "
                            "-0.21 -0.23 0.71  0.63 -0.23 0.71  0.63 0.27 0.71  -0.21 0.27 0.71",
                            "1 0 0  1 0 0  1 0 0  1 0 0  1 0 0  1 0 0  1 0 0  1 0 0"),
                      R"(    <MeshROI name="roi" ROIposition="@/Cube/cube.position" ROItriangles=")" + kBoxTriangles +
                          R"(" position="@dofs.position"/>
    <FixedProjectiveConstraint name="fix" indices="@roi.indices"/>
)");
}

TEST(LiveEngineFollowedInputs, MeshRoiFollowsItsMovingRoiMeshWithinTheBoxOfInitAsSofaHead) {
    auto s = test::build(moving_mesh_roi());
    const std::vector<Vec3>& x = falling_beam_positions(*s);
    EXPECT_EQ(data_numbers(*s, "/Beam/roi", "indices"), (std::vector<double>{0, 1, 10, 11}));
    advance_steps(*s, 22);
    // the cube's xmin passed 0: points 0 and 10 fall from step 21 (read after the step, as
    // SofaPython3's `roi.indices.value`: from step 22, the step's solve having moved them in again)
    EXPECT_EQ(data_numbers(*s, "/Beam/roi", "indices"), (std::vector<double>{1, 11}));
    advance_steps(*s, 8);
    EXPECT_EQ(x[0], Vec3(0.002973811463892745, 0.04618618665416311, 1.6279353273560143e-05));
    EXPECT_EQ(x[2], Vec3(0.9922380224820421, -0.06728780650474522, -0.0005239008526353311));
    EXPECT_EQ(x[11], Vec3(0.5, 0.0, 0.5));
    EXPECT_EQ(x[12], Vec3(0.9922380224820351, -0.0672878065047445, 0.5005239008526344));
    advance_steps(*s, 10);
    // point 2 (0.98, -0.13, 0) is inside the moved cube (x in [0.19, 1.03]) but beyond the
    // bounding box of init (x <= 0.63), which MeshROI::isPointInROI tests first: not selected
    EXPECT_GT(x[2][0], 0.19);
    EXPECT_LT(x[2][0], 0.63 + 0.4);
    EXPECT_EQ(data_numbers(*s, "/Beam/roi", "indices"), (std::vector<double>{1, 11}));
    advance_steps(*s, 32);
    EXPECT_TRUE(data_numbers(*s, "/Beam/roi", "indices").empty());  // xmin passed 0.5 (step 71; read: 72)
    advance_steps(*s, 8);
    EXPECT_EQ(x[0], Vec3(0.2451121942493577, 0.3467339476787226, -5.551474373969886e-05));
    EXPECT_EQ(x[2], Vec3(0.7584581088956867, -0.5153243513537072, 0.000381625220826301));
    EXPECT_EQ(x[11], Vec3(0.5019482482389321, -0.08278320357385799, 0.49990120496605733));
    EXPECT_EQ(x[12], Vec3(0.7584581086148595, -0.5153243510738968, 0.4996183745600272));
    // MeshROI's `ROIposition` is followed: no warning that it is read once
    for (const std::string& w : s->warnings()) EXPECT_EQ(w.find("ROIposition"), std::string::npos) << w;
}

/// The falling beam after three moving one-point states (`/Mover/m` up at 1 m/s, `/Turner/r` at
/// 20 degrees/s about z, `/Scaler/s` from 1 1 1 down at 1/s), with `engines` in its node.
std::string beam_after_movers(const std::string& engines) {
    return beam_after(mover("Mover", "m", "0 0 0", "0 1 0") + mover("Turner", "r", "0 0 0", "0 0 20") +
                          mover("Scaler", "s", "1 1 1", "0 -1 0"),
                      engines);
}

/// A TransformEngine over the falling beam whose translation, rotation (degrees) and scale link
/// the movers' positions (a Vec3 Data linked to a list of points takes the first point); a BoxROI
/// over its output fixes the beam's points.
std::string moving_transform() {
    return beam_after_movers(
        R"(    <TransformEngine name="t" input_position="@dofs.position" translation="@/Mover/m.position"
      rotation="@/Turner/r.position" scale="@/Scaler/s.position"/>
    <BoxROI name="box" box="-0.1 0.3 -0.1  2.1 0.8 0.6" position="@t.output_position"/>
    <FixedProjectiveConstraint name="fix" indices="@box.indices"/>
)");
}

/// The same with TransformPosition (method scaleRotationTranslation), and a second TransformPosition
/// (method scale, by 2 about an origin linking the mover) feeding a second BoxROI.
std::string moving_transform_position() {
    return beam_after_movers(
        R"(    <TransformPosition name="t" method="scaleRotationTranslation" input_position="@dofs.position"
      translation="@/Mover/m.position" rotation="@/Turner/r.position" scale="@/Scaler/s.position"/>
    <BoxROI name="box" box="-0.1 0.3 -0.1  2.1 0.8 0.6" position="@t.output_position"/>
    <FixedProjectiveConstraint name="fix" indices="@box.indices"/>
    <TransformPosition name="grow" method="scale" input_position="@dofs.position" origin="@/Mover/m.position" scale="2 2 2"/>
    <BoxROI name="box2" box="2.5 -0.9 -0.1  4.1 -0.5 1.1" position="@grow.output_position"/>
    <FixedProjectiveConstraint name="fix2" indices="@box2.indices"/>
)");
}

TEST(LiveEngineFollowedInputs, TransformEngineFollowsItsMovingTranslationRotationAndScaleAsSofaHead) {
    auto s = test::build(moving_transform());
    const std::vector<Vec3>& x = falling_beam_positions(*s);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{5, 6, 7, 8, 9, 15, 16, 17, 18, 19}));
    advance_steps(*s, 30);
    // SOFA HEAD: 9 and 19 fall from step 26, 8 and 18 from step 30; a read after the step selects
    // at the step's positions and translation (SofaPython3's `box.indices.value`), the next step's
    // solve at those of the movers' solve, which runs first
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"),
              (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 11, 12, 13, 14, 15, 16, 17}));
    EXPECT_EQ(x[0], Vec3(0.00021736133638171207, -0.0006969529148446895, 9.177711392701379e-05));
    EXPECT_EQ(x[5], Vec3(0.0, 0.5, 0.0));
    EXPECT_EQ(x[9], Vec3(2.000088317721722, 0.4994135634588918, -4.218604382555395e-05));
    EXPECT_EQ(x[19], Vec3(2.000088317721722, 0.4994135634588918, 0.5000421860438254));
    advance_steps(*s, 50);
    // 7 and 17 fell from step 36, 6 and 16 from 46, 5 and 15 from 61 (SofaPython3's read: 0 10)
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{0, 10}));
    EXPECT_EQ(x[0], Vec3(0.00028571087820310486, -0.0009096917394247518, 0.00011873921641257834));
    EXPECT_EQ(x[5], Vec3(0.05080221154582755, 0.4963185271876348, -7.533509006489922e-05));
    EXPECT_EQ(x[9], Vec3(2.0417561158790396, 0.28856930971653383, -1.8103288555184124e-05));
    EXPECT_EQ(x[19], Vec3(2.0417561158790396, 0.2885693097165339, 0.5000181032885543));
    for (const std::string& w : s->warnings())
        EXPECT_EQ(w.find("changes while the scene runs"), std::string::npos) << w;
}

TEST(LiveEngineFollowedInputs, TransformPositionFollowsItsMovingTranslationRotationScaleAndOriginAsSofaHead) {
    auto s = test::build(moving_transform_position());
    const std::vector<Vec3>& x = falling_beam_positions(*s);
    EXPECT_TRUE(data_numbers(*s, "/Beam/box2", "indices").empty());
    advance_steps(*s, 30);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"),
              (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 11, 12, 13, 14, 15, 16, 17}));
    EXPECT_EQ(x[4], Vec3(1.9997543733854433, -0.0007841863398770553, 0.00010331201708163755));
    EXPECT_EQ(x[9], Vec3(2.000088317721722, 0.4994135634588918, -4.218604382555395e-05));
    EXPECT_EQ(x[14], Vec3(1.9997543733854433, -0.0007841863398770366, 0.4998966879829184));
    advance_steps(*s, 20);
    // the bottom points x = 1.5, 2 scaled by 2 about (0, 0.5, 0): y' = 2y - 0.5 in [-0.9, -0.5]
    // (fixed, they keep their velocity: activate_projectVelocity 0)
    EXPECT_EQ(data_numbers(*s, "/Beam/box2", "indices"), (std::vector<double>{3, 4, 13, 14}));
    advance_steps(*s, 30);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{0, 10}));
    EXPECT_EQ(data_numbers(*s, "/Beam/box2", "indices"), (std::vector<double>{3, 4, 13, 14}));
    EXPECT_EQ(x[4], Vec3(1.9986479708238545, -0.017210242171736702, -0.00011382135639744103));
    EXPECT_EQ(x[9], Vec3(2.0087065906041897, 0.4841124971227732, 2.836936373202182e-05));
    EXPECT_EQ(x[14], Vec3(1.9986479708238545, -0.017210242171736948, 0.500113821356396));
}

TEST(LiveEngineFollowedInputs, TransformEngineOverFixedPointsRunsAgainWhenItsTranslationMoves) {
    // no solver: the test writes the mover's position; the engine's points are inline
    auto s = test::build(R"(<Node name="root" dt="0.01">
  <Node name="Mover">
    <MechanicalObject name="m" position="0 1 0  5 5 5"/>
  </Node>
  <Node name="Points">
    <TransformEngine name="t" input_position="1 0 0  2 0 0" translation="@/Mover/m.position" scale="2 2 2"/>
    <MechanicalObject name="dofs" position="@t.output_position"/>
  </Node>
</Node>)");
    // scale then translate by the first point of m: (2, 1, 0), (4, 1, 0)
    EXPECT_EQ(data_numbers(*s, "/Points/t", "output_position"), (std::vector<double>{2, 1, 0, 4, 1, 0}));
    s->set_data({"/Mover/m", false}, "position", "0 0 3  7 7 7");
    EXPECT_EQ(data_numbers(*s, "/Points/t", "output_position"), (std::vector<double>{2, 0, 3, 4, 0, 3}));
    s->step();  // the state linked to the output takes it before the step
    EXPECT_EQ(data_numbers(*s, "/Points/dofs", "position"), (std::vector<double>{2, 0, 3, 4, 0, 3}));
}

/// A falling beam in x in [-2, 0], y and z in [-0.5, 0] whose points in a BoxROI are fixed, the
/// BoxROI's `box` linking `box_link`, after a tool node (`tool`: one or two points thrown under
/// gravity); `extra` before the BoxROI.
std::string box_following(const std::string& tool_points, const std::string& tool_velocities, const std::string& extra,
                          const std::string& box_link) {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Tool">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="mo" position=")" +
           tool_points + "\" velocity=\"" + tool_velocities + R"("/>
    <UniformMass totalMass="1"/>
  </Node>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="5" ny="2" nz="2" xmin="-2" xmax="0" ymin="-0.5" ymax="0" zmin="-0.5" zmax="0"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="200" damping="0.1"/>
)" + extra +
           "    <BoxROI name=\"box\" box=\"" + box_link + R"(" position="@dofs.position"/>
    <FixedProjectiveConstraint name="fix" indices="@box.indices"/>
  </Node>
</Node>)";
}

TEST(LiveEngineFollowedInputs, BoxRoiFollowsABoxLinkedToAMovingStateAsSofaHead) {
    // SOFA copies the tool's point p into a box (p, 0 0 0) (BaseData::genericCopyValueFrom), tested
    // as copied: the box from p (thrown along -x, falling) to the origin fixes more and more points
    auto s = test::build(box_following("-0.2 -0.3 -0.6", "-3 0 0", "", "@../Tool/mo.position"));
    const std::vector<Vec3>& x = falling_beam_positions(*s);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{9, 19}));
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "box"), (std::vector<double>{-0.2, -0.3, -0.6, 0, 0, 0}));
    advance_steps(*s, 20);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{8, 9, 18, 19}));
    EXPECT_EQ(x[0], Vec3(-1.9328149226704778, -0.724929106736469, -0.5042394735035174));
    EXPECT_EQ(x[8], Vec3(-0.49950227225507415, -0.04696605435570763, -0.500095840023197));
    advance_steps(*s, 20);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"),
              (std::vector<double>{1, 2, 3, 7, 8, 9, 11, 12, 13, 17, 18, 19}));
    EXPECT_EQ(x[0], Vec3(-1.7701725716717267, -1.078416599031002, -0.525255142698762));
    EXPECT_EQ(x[5], Vec3(-1.9349952799689936, -0.6062417012797686, -0.5112545833189219));
    EXPECT_EQ(x[10], Vec3(-1.7691156296754147, -1.09297345831004, -0.025659753821946078));
    advance_steps(*s, 20);
    // SOFA HEAD: 0 and 10 fixed from step 50, 5 and 15 from 56
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"),
              (std::vector<double>{0, 1, 2, 3, 5, 6, 7, 8, 9, 10, 11, 12, 13, 15, 16, 17, 18, 19}));
    EXPECT_EQ(x[0], Vec3(-1.5895920381433735, -1.4027426797263642, -0.5502559103401813));
    EXPECT_EQ(x[5], Vec3(-1.8411013677331955, -0.9707962450086723, -0.5282942103437885));
    EXPECT_EQ(x[8], Vec3(-0.49770049498249547, -0.1611863471035385, -0.5002204246487552));
    EXPECT_EQ(x[10], Vec3(-1.588035825634158, -1.4274549730808748, -0.05098275342289702));
    for (const std::string& w : s->warnings()) EXPECT_EQ(w.find("'box'"), std::string::npos) << w;
}

TEST(LiveEngineFollowedInputs, BoxRoiFollowsABoxLinkedToAnEngineOverAMovingStateAsSofaHead) {
    // two tool points, shifted up by a TransformEngine: two boxes, the second moving along +x
    auto s = test::build(box_following(
        "-0.2 -0.3 -0.6  -1.9 -0.45 -0.3", "-3 0 0  2 0 0",
        "    <TransformEngine name=\"shift\" input_position=\"@../Tool/mo.position\" translation=\"0 0.1 0\"/>\n",
        "@shift.output_position"));
    const std::vector<Vec3>& x = falling_beam_positions(*s);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{9, 16, 17, 18, 19}));
    advance_steps(*s, 20);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{8, 9, 17, 18, 19}));  // 16 left
    EXPECT_EQ(x[0], Vec3(-1.9951985172149458, -0.5425275543299295, -0.46402008467207834));
    EXPECT_EQ(x[16], Vec3(-1.5000442687920108, -0.0012989941446841882, 0.00040253333500469754));
    advance_steps(*s, 20);
    EXPECT_EQ(x[1], Vec3(-1.4810001685543137, -0.5771524109232324, -0.44323238466588144));
    EXPECT_EQ(x[16], Vec3(-1.5019939820784767, -0.03567381303134343, 0.011141670780721055));
    advance_steps(*s, 20);
    EXPECT_EQ(data_numbers(*s, "/Beam/box", "indices"), (std::vector<double>{0, 1, 2, 3, 6, 7, 8, 9, 17, 18, 19}));
    EXPECT_EQ(x[0], Vec3(-1.963854203035718, -0.6662785860310719, -0.3936892567183473));
    EXPECT_EQ(x[1], Vec3(-1.4675990323972454, -0.617987787724245, -0.4135891645861939));
    EXPECT_EQ(x[10], Vec3(-1.95088213046114, -0.6006877499088575, 0.10164958316079896));
    EXPECT_EQ(x[16], Vec3(-1.5018045395556763, -0.05865336155155473, 0.01824367248719639));
}

}  // namespace
