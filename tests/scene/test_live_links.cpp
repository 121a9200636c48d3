// SOFA's Data links followed after a write (src/scene/live_links.cpp): a state vector linked to
// an engine's output takes the engine's new output at the next step when a write made it dirty
// (the written Data, an engine with a dirty input, a Data linked to a dirty one, to the fixed
// point), and keeps the solve's values otherwise; a read right after the write pulls the engine.
// Against SOFA HEAD through SofaPython3 (tests/python/scripts/engine_links.py), bit for bit, and
// an engine chain in closed form.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

namespace penalty {
namespace {

using scene::DataOwner;

/// Row `i` of a Vec3 Data's value.
Vec3 ll_row(scene::Scene& s, const std::string& path, std::string_view data, std::size_t i) {
    const scene::DataValue v = s.data({path, false}, data);
    return {v.numbers.at(3 * i), v.numbers.at(3 * i + 1), v.numbers.at(3 * i + 2)};
}

// The scene of tests/python/scripts/engine_links.py: five points turned by a TransformEngine
// ("Free", no solver: its state is the engine's output) and five falling points whose
// positions link another TransformEngine's output ("Falling", implicit Euler, 1 kg). Before step
// k the turn's rotation becomes 10·k degrees about x and, at odd k, the lift's translation 0.1 m
// higher (SOFA's controller at AnimateBeginEvent). SOFA HEAD 2a278d8 + SofaPython3 87be1a3
// (tests/python/scripts/engine_links_sofa_head.json), point 4 (1, 1, 1):
//   Free after steps 1 to 4: the point turned by 10, 20, 30, 40 degrees;
//   Falling: y = 1.0990190000000002, 1.0970570000000002, 1.197057, 1.193133: the engine's output
//   replaces the positions at steps 1 and 3, steps 2 and 4 go on from the solve's; the velocity
//   −0.0981·k is never replaced (it links nothing);
//   a rotation of 45 degrees written after step 4 and read at once: (1, −5.551115123125783e-17,
//   1.414213562373095).
TEST(LiveLinks, StatesLinkedToAnEngineTakeItsOutputAfterAWriteAsSofaHead) {
    auto s = test::build(R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <MeshTopology name="mesh" position="0 0 0  1 0 0  0 1 0  0 0 1  1 1 1"/>
  <Node name="Free">
    <TransformEngine name="turn" input_position="@../mesh.position" rotation="0 0 0"/>
    <MechanicalObject name="points" position="@turn.output_position"/>
  </Node>
  <Node name="Falling">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-12"/>
    <TransformEngine name="lift" input_position="@../mesh.position" translation="0 0 0"/>
    <MechanicalObject name="points" position="@lift.output_position"/>
    <UniformMass totalMass="1"/>
  </Node>
</Node>)");
    const std::vector<Vec3> free{
        Vec3(1.0, 0.8111595753452777, 1.1584559306791384), Vec3(1.0, 0.5976724774602398, 1.281712764111577),
        Vec3(1.0, 0.3660254037844387, 1.3660254037844386), Vec3(1.0, 0.1232568334324387, 1.4088320528055174)};
    const std::vector<double> falling{1.0990190000000002, 1.0970570000000002, 1.197057, 1.193133};
    const std::vector<double> velocity{-0.09810000000000003, -0.19620000000000007, -0.2943000000000001,
                                       -0.39240000000000014};
    double lift = 0;
    for (int k = 1; k <= 4; ++k) {
        s->set_data({"/Free/turn", false}, "rotation", std::to_string(10 * k) + " 0 0");
        if (k % 2 == 1) {
            lift += 0.1;
            std::ostringstream t;
            t.precision(17);
            t << "0 " << lift << " 0";
            s->set_data({"/Falling/lift", false}, "translation", t.str());
        }
        s->step();
        EXPECT_EQ(ll_row(*s, "/Free/points", "position", 4), free[std::size_t(k - 1)]) << "step " << k;
        EXPECT_EQ(ll_row(*s, "/Falling/points", "position", 4), Vec3(1.0, falling[std::size_t(k - 1)], 1.0))
            << "step " << k;
        EXPECT_EQ(ll_row(*s, "/Falling/points", "velocity", 4), Vec3(0.0, velocity[std::size_t(k - 1)], 0.0))
            << "step " << k;
    }
    s->set_data({"/Free/turn", false}, "rotation", "45 0 0");
    EXPECT_EQ(ll_row(*s, "/Free/points", "position", 4), Vec3(1.0, -5.551115123125783e-17, 1.414213562373095));
    // the falling points' link stayed clean: the solve's positions
    EXPECT_EQ(ll_row(*s, "/Falling/points", "position", 4), Vec3(1.0, 1.193133, 1.0));
}

TEST(LiveLinks, ADirtyInputReachesAStateThroughAChainOfEnginesAndAnUnrelatedWriteKeepsTheSolve) {
    // a → b → points (a translates, b turns by 90 degrees about z: (x, y, z) → (−y, x, z)); a
    // write of a's translation reaches the state through b at the next step; a write of the
    // solver's damping (linked to nothing) leaves the solve's positions
    auto s = test::build(R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <MeshTopology name="mesh" position="1 0 0  0 2 0"/>
  <Node name="N">
    <EulerImplicitSolver name="ode" rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="10" tolerance="1e-30" threshold="1e-30"/>
    <TransformEngine name="a" input_position="@../mesh.position" translation="0 0 0"/>
    <TransformEngine name="b" input_position="@a.output_position" rotation="0 0 90"/>
    <MechanicalObject name="points" position="@b.output_position"/>
    <UniformMass vertexMass="1"/>
  </Node>
</Node>)");
    s->step();  // from (0, 1, 0): y = 1 − h²·g
    EXPECT_NEAR(ll_row(*s, "/N/points", "position", 0).y(), 1 - 0.001, 1e-15);
    s->set_data({"/N/ode", false}, "rayleighMass", "0");
    s->step();  // the solve goes on: y = 1 − 3·h²·g
    EXPECT_NEAR(ll_row(*s, "/N/points", "position", 0).y(), 1 - 0.003, 1e-15);
    EXPECT_EQ(s->generation(), 1u);
    s->set_data({"/N/a", false}, "translation", "0 0 5");
    s->step();  // b(a(x)) replaces the positions, then the step's solve: the velocity −2·h·g stays
    const Vec3 p0 = ll_row(*s, "/N/points", "position", 0), p1 = ll_row(*s, "/N/points", "position", 1);
    EXPECT_NEAR(p0.x(), 0.0, 1e-15);
    EXPECT_NEAR(p0.y(), 1 - 0.003, 1e-15);
    EXPECT_NEAR(p0.z(), 5.0, 1e-15);
    EXPECT_NEAR(p1.x(), -2.0, 1e-15);
    EXPECT_NEAR(p1.y(), -0.003, 1e-15);
    EXPECT_NEAR(ll_row(*s, "/N/points", "velocity", 1).y(), -0.3, 1e-15);
}

}  // namespace
}  // namespace penalty
