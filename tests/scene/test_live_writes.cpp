// Writing a built scene's live Data after init (src/scene/live_writes.cpp): a state vector in
// place (Vec3d, Rigid3d with its quaternion normalised, counts checked); the node's time at once;
// the root's dt at once and its gravity reaching child nodes one step late (SOFA's
// UpdateSimulationContextVisitor), each in closed form; a cosmetic Data without a rebuild;
// TetrahedronFEMForceField's Young's modulus at the next step with updateStiffness, at reinit
// without; a node's reinit() taking the writes of the components below it; components added and
// removed before the next step (bit for bit as the scene built so); a rebuild that fails leaving
// the scene as it stood; reset(); the collision phase's events; the refusals' exact messages.
#include "penalty/io/error.hpp"
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <string>

namespace penalty {
namespace {

using scene::DataOwner;
using ::testing::HasSubstr;

/// The message of the std::invalid_argument `f` raises ("no error" when none).
std::string lw_refusal(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

const Vec3Object& lw_vec3(const scene::Scene& s, std::size_t k = 0) {
    return dynamic_cast<const Vec3Object&>(*s.states().at(k).state);
}

/// Free particles of 1 kg in the root (`root`) and in a child node "C" (`child`), implicit Euler
/// with an exact CG: v_{k+1} = v_k + h·g, x_{k+1} = x_k + h·v_{k+1}.
std::string lw_particles() {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
  <CGLinearSolver iterations="10" tolerance="1e-30" threshold="1e-30"/>
  <MechanicalObject name="top" position="0 0 0"/><UniformMass name="mass" vertexMass="1"/>
  <Node name="C">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="10" tolerance="1e-30" threshold="1e-30"/>
    <MechanicalObject name="low" position="0 0 0"/><UniformMass vertexMass="1"/>
  </Node>
</Node>)";
}

TEST(LiveWrites, AStateVectorIsWrittenInPlaceWithItsCountChecked) {
    auto s = test::build(R"(<Node name="root"><MechanicalObject name="m" position="0 0 0  1 1 1"/>
  <Node name="R"><MechanicalObject name="frame" template="Rigid3d" position="0 0 0 0 0 0 1"/></Node></Node>)");
    const Vec3Object& m = lw_vec3(*s);
    const Vec3* memory = m.position.data();
    s->set_data({"/m", false}, "velocity", "1 2 3 4 5 6");
    s->set_data({"/m", false}, "externalForce", "0 0 1 0 0 2");
    EXPECT_EQ(m.velocity, (std::vector<Vec3>{Vec3(1, 2, 3), Vec3(4, 5, 6)}));
    EXPECT_EQ(m.external_force, (std::vector<Vec3>{Vec3(0, 0, 1), Vec3(0, 0, 2)}));
    s->set_data({"/m", false}, "position", "5 6 7 8 9 10");
    EXPECT_EQ(m.position.data(), memory);
    EXPECT_EQ(s->generation(), 0u);  // no rebuild
    EXPECT_EQ(lw_refusal([&] {
                  s->set_data({"/m", false}, "position", "1 2 3");
              }),
              "MechanicalObject 'm': data 'position': expected 2 points (3 numbers each), found 3 numbers (penalty "
              "keeps a state's size after init)");
    EXPECT_EQ(lw_refusal([&] {
                  s->set_data({"/m", false}, "position", "1 2 3 4 5 nan");
              }),
              "MechanicalObject 'm': data 'position': expected finite numbers, found 'nan'");
    EXPECT_EQ(m.position[1], Vec3(8, 9, 10));

    // a frame: x y z qx qy qz qw, the quaternion as written (SOFA's; test_live_quirks.cpp: the
    // fix normalizes it); a velocity: 6 numbers
    const auto& r = dynamic_cast<const Rigid3Object&>(*s->states().at(1).state);
    s->set_data({"/R/frame", false}, "position", "1 2 3 0 0 3 4");
    EXPECT_EQ(r.position[0].center, Vec3(1, 2, 3));
    EXPECT_EQ(r.position[0].orientation.z(), 3.0);
    EXPECT_EQ(r.position[0].orientation.w(), 4.0);
    s->set_data({"/R/frame", false}, "velocity", "1 0 0 0 0 2");
    EXPECT_EQ(r.velocity[0].linear, Vec3(1, 0, 0));
    EXPECT_EQ(r.velocity[0].angular, Vec3(0, 0, 2));
    EXPECT_EQ(lw_refusal([&] {
                  s->set_data({"/R/frame", false}, "position", "1 2 3");
              }),
              "MechanicalObject 'frame': data 'position': expected 1 frames (x y z qx qy qz qw), found 3 numbers");
    EXPECT_EQ(lw_refusal([&] {
                  s->set_data({"/R/frame", false}, "velocity", "1 2 3");
              }),
              "MechanicalObject 'frame': data 'velocity': expected 1 rows of 6 numbers, found 3 numbers");
}

TEST(LiveWrites, TheTimeAndDtAreTakenAtOnceAndTheGravityReachesChildNodesOneStepLate) {
    // SOFA's DefaultAnimationLoop copies the root's context down after the solve: a gravity written
    // between steps acts on the root's particle at the next step, on the child's one step later
    auto s = test::build(lw_particles());
    s->step();  // both: v = h·g = −0.1
    s->set_data({"/", true}, "gravity", "0 -20 0");
    s->step();
    EXPECT_DOUBLE_EQ(lw_vec3(*s, 0).velocity[0].y(), -0.1 - 0.2);
    EXPECT_DOUBLE_EQ(lw_vec3(*s, 1).velocity[0].y(), -0.1 - 0.1);  // the old gravity once more
    s->step();
    EXPECT_DOUBLE_EQ(lw_vec3(*s, 1).velocity[0].y(), -0.2 - 0.2);
    EXPECT_EQ(s->data({"/", true}, "gravity").text, "0 -20 0");

    // without the delay: both at the next step
    auto now = test::build(lw_particles());
    now->set_gravity_write_delay(false);
    now->set_data({"/", true}, "gravity", "0 -20 0");
    now->step();
    EXPECT_DOUBLE_EQ(lw_vec3(*now, 1).velocity[0].y(), -0.2);

    // dt: the next step's h; the time: at once
    now->set_data({"/", true}, "dt", "0.05");
    now->step();
    EXPECT_DOUBLE_EQ(lw_vec3(*now, 0).velocity[0].y(), -0.2 - 0.05 * 20);
    EXPECT_DOUBLE_EQ(now->simulation().time(), 0.06);
    now->set_data({"/", true}, "time", "2.5");
    EXPECT_DOUBLE_EQ(now->simulation().time(), 2.5);
    EXPECT_EQ(lw_refusal([&] {
                  now->set_data({"/", true}, "time", "1 2");
              }),
              "Node 'root': data 'time': expected one number");
    EXPECT_EQ(lw_refusal([&] {
                  now->set_data({"/C", true}, "gravity", "0 0 0");
              }),
              "Node 'C': data 'gravity' cannot be written after init: SOFA copies the root's gravity over a child "
              "node's at each step");
    try {
        now->set_data({"/", true}, "dt", "0");
        ADD_FAILURE() << "dt = 0 accepted";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("attribute 'dt': must be > 0"));
    }
    EXPECT_DOUBLE_EQ(now->simulation().root().dt(), 0.05);
}

TEST(LiveWrites, ACosmeticDataIsKeptWithoutARebuildAndAnUnknownOwnerOrDataIsRefused) {
    auto s = test::build(lw_particles());
    s->set_data({"/mass", false}, "printLog", "1");
    s->step();
    EXPECT_EQ(s->generation(), 0u);
    EXPECT_EQ(s->data({"/mass", false}, "printLog").text, "1");
    EXPECT_EQ(lw_refusal([&] { s->set_data({"/nothing", false}, "printLog", "1"); }), "no component '/nothing'");
    EXPECT_EQ(lw_refusal([&] { s->set_data({"/D", true}, "gravity", "0 0 0"); }), "no node '/D'");
    EXPECT_EQ(lw_refusal([&] {
                  s->set_data({"/mass", false}, "totalMas", "1");
              }),
              "UniformMass 'mass' has no data 'totalMas'");
    EXPECT_EQ(lw_refusal([&] {
                  s->set_data({"/mass", false}, "name", "other");
              }),
              "UniformMass 'mass': data 'name' cannot be written after init: a component keeps its name after init "
              "(penalty finds components by their path)");
}

/// The 1×1×1 tetrahedral cube (5 tetrahedra) fixed at z = 0, pulled down by gravity.
std::string lw_tetra_body(const std::string& fem) {
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0"><Node name="B">
  <EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-20" threshold="1e-20"/>
  <MeshTopology position=")" +
           test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) + R"("/>
  <MechanicalObject name="mo"/><UniformMass totalMass="1"/>
  <FixedProjectiveConstraint indices="0 1 2 3"/>
  <TetrahedronFEMForceField name="ff" poissonRatio="0.3" )" +
           fem + R"(/>
</Node></Node>)";
}

std::vector<Vec3> lw_after(scene::Scene& s, int steps) {
    for (int k = 0; k < steps; ++k) s.step();
    return lw_vec3(s).position;
}

TEST(LiveWrites, YoungsModulusActsAtTheNextStepWithUpdateStiffnessAndAtReinitWithout) {
    // SOFA's TetrahedronFEMForceField::handleEvent recomputes the material stiffness at each
    // AnimateBeginEvent when updateStiffness is set. SOFA HEAD through SofaPython3 (this cube,
    // youngModulus.value = [300] after init, 4 steps): with updateStiffness the positions equal a
    // scene built with E = 300, without it they equal the unchanged scene's, as here
    const DataOwner ff{"/B/ff", false};
    auto fresh = test::build(lw_tetra_body(R"(youngModulus="300" updateStiffness="1")"));
    auto written = test::build(lw_tetra_body(R"(youngModulus="100" updateStiffness="1")"));
    written->set_data(ff, "youngModulus", "300");
    EXPECT_EQ(lw_after(*written, 4), lw_after(*fresh, 4));
    EXPECT_EQ(written->generation(), 1u);

    auto unchanged = test::build(lw_tetra_body(R"(youngModulus="100")"));
    auto waiting = test::build(lw_tetra_body(R"(youngModulus="100")"));
    waiting->set_data(ff, "youngModulus", "300");
    EXPECT_EQ(lw_after(*waiting, 2), lw_after(*unchanged, 2));
    EXPECT_EQ(waiting->generation(), 0u);
    // a node's reinit (SOFA's init of what is below it) takes the write: from then on, as a scene
    // built with E = 300 that ran its first two steps with E = 100
    auto switched = test::build(lw_tetra_body(R"(youngModulus="100")"));
    (void)lw_after(*switched, 2);
    switched->set_data(ff, "youngModulus", "300");
    switched->reinit({"/B", true});
    (void)lw_after(*switched, 2);
    waiting->reinit({"/", true});
    EXPECT_EQ(waiting->generation(), 1u);
    EXPECT_EQ(lw_after(*waiting, 2), lw_vec3(*switched).position);
    EXPECT_NE(lw_vec3(*waiting).position, lw_after(*unchanged, 2));
    EXPECT_EQ(lw_refusal([&] { waiting->reinit({"/B/none", false}); }), "no component '/B/none'");
}

TEST(LiveWrites, ComponentsAddedOrRemovedAfterInitAreBuiltBeforeTheNextStep) {
    // a ConstantForceField added to the child, the root's particle's mass removed (the child's stays)
    auto s = test::build(lw_particles());
    s->step();
    auto force = std::make_unique<io::SceneComponent>();
    force->type = "ConstantForceField";
    force->name = "push";
    force->file = "test.scn";
    force->attributes.push_back({"forces", "3 0 0", 0});
    EXPECT_EQ(s->add_to_node("/C", std::move(force)), "/C/push");
    EXPECT_EQ(s->add_to_node("/C", nullptr, "D"), "/C/D");
    s->step();
    EXPECT_EQ(s->generation(), 1u);
    // dv = h·(g + f/m): −0.1 then (0.03, −0.1)
    EXPECT_DOUBLE_EQ(lw_vec3(*s, 1).velocity[0].x(), 0.03);
    EXPECT_DOUBLE_EQ(lw_vec3(*s, 1).velocity[0].y(), -0.2);
    s->remove({"/C/push", false});
    s->step();
    EXPECT_DOUBLE_EQ(lw_vec3(*s, 1).velocity[0].x(), 0.03);  // no force any more
    EXPECT_EQ(lw_refusal([&] { s->remove({"/", true}); }), "the root node cannot be removed");
    EXPECT_EQ(lw_refusal([&] { s->remove({"/C/push", false}); }), "no component '/C/push'");
    EXPECT_EQ(lw_refusal([&] { (void)s->add_to_node("/E", nullptr, "F"); }), "no node '/E'");
}

TEST(LiveWrites, ARebuildThatFailsLeavesTheSceneAsItStood) {
    // removing the topology would leave the state 1 DOF instead of 8: refused, the text restored
    auto s = test::build(R"(<Node name="root" dt="0.01" gravity="0 -10 0"><Node name="B">
  <EulerImplicitSolver name="ode" rayleighStiffness="0" rayleighMass="0"/>
  <CGLinearSolver iterations="10" tolerance="1e-30" threshold="1e-30"/>
  <RegularGridTopology name="grid" nx="2" ny="2" nz="2" xmin="0" xmax="1" ymin="0" ymax="1" zmin="0" zmax="1"/>
  <MechanicalObject name="mo"/><UniformMass name="mass" vertexMass="1"/></Node></Node>)");
    s->step();
    s->remove({"/B/grid", false});
    s->set_data({"/B/mass", false}, "vertexMass", "2");
    try {
        s->step();
        ADD_FAILURE() << "the rebuild was accepted";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("the write changes its number of DOFs from 8 to 1 (penalty keeps a state's "
                                        "size after init)"));
    }
    EXPECT_EQ(s->generation(), 0u);
    EXPECT_EQ(s->data({"/B/mass", false}, "vertexMass").numbers, std::vector<double>{1.0});  // the write undone
    EXPECT_EQ(lw_vec3(*s).num_dofs(), 8u);
    s->step();  // the scene as it stood: the grid and 1 kg
    EXPECT_DOUBLE_EQ(lw_vec3(*s).velocity[7].y(), -0.2);
    // the next rebuild starts from that scene (the removal and the write were forgotten)
    s->set_data({"/B/ode", false}, "rayleighMass", "0.5");
    s->step();
    EXPECT_EQ(s->generation(), 1u);
    EXPECT_EQ(lw_vec3(*s).num_dofs(), 8u);
    EXPECT_EQ(s->data({"/B/mass", false}, "vertexMass").numbers, std::vector<double>{1.0});
}

TEST(LiveWrites, ResetPutsTheBuiltValuesInTheStatesMemory) {
    auto s = test::build(lw_particles());
    const Vec3* memory = lw_vec3(*s).position.data();
    s->step();
    s->step();
    s->reset();
    EXPECT_EQ(lw_vec3(*s).position.data(), memory);
    EXPECT_EQ(lw_vec3(*s).position[0], Vec3::Zero());
    EXPECT_EQ(lw_vec3(*s).velocity[0], Vec3::Zero());
    EXPECT_DOUBLE_EQ(s->simulation().time(), 0.0);
    s->step();
    EXPECT_DOUBLE_EQ(lw_vec3(*s).velocity[0].y(), -0.1);
}

TEST(LiveWrites, TheCollisionPhaseTellsItsEventsAndAWriteInItWaitsForTheNextStep) {
    auto s = test::build(lw_particles());
    std::vector<std::string> events;
    s->set_event_listener([&](std::string_view e) {
        events.emplace_back(e);
        if (e == "CollisionBeginEvent" && events.size() == 1) s->set_data({"/mass", false}, "vertexMass", "2");
    });
    s->step();
    EXPECT_EQ(events, (std::vector<std::string>{"CollisionBeginEvent", "CollisionEndEvent", "IntegrateBeginEvent"}));
    EXPECT_EQ(s->generation(), 0u);  // the write waits
    EXPECT_DOUBLE_EQ(lw_vec3(*s).velocity[0].y(), -0.1);
    s->step();
    EXPECT_EQ(s->generation(), 1u);
    EXPECT_EQ(events.size(), 6u);
}

}  // namespace
}  // namespace penalty
