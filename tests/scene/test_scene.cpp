// Scene (scene/scene.cpp), what a built scene offers: its steps (the cube on the floor after 20
// steps is SOFA HEAD's state, 2a278d8, `sofa-head SCENE 20 OUT`, %.17g, bit for bit), the contact
// records of the live pairs, the solvers' statistics, the energies in closed form (kinetic,
// gravity with each node's gravity, springs, the drop energy of the moving masses), the warnings
// (with each pipeline's skipped pairs), the tunnelling guard's refusal and removal, the blocked
// reductions, roles and origins, the overrides (and their refusal naming what a type reads), and
// load_scene.
#include "builder_scenes.hpp"

#include "penalty/mechanics/state.hpp"
#include "penalty/output/contact_records.hpp"
#include "penalty/simulation/ode_solver.hpp"
#include "penalty_test/cubes_in_bowl.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace {

using namespace penalty::test_builder_scenes;
using ::testing::ElementsAre;

const penalty::Vec3Object& scene_state_at(const scene::Scene& s, const std::string& node_path) {
    for (const auto& r : s.states())
        if (r.node_path == node_path) return dynamic_cast<const penalty::Vec3Object&>(*r.state);
    throw std::logic_error("no state at " + node_path);
}

TEST(Scene, TheCubeOnTheFloorStepsAsSofaHead) {
    auto s = build(kCubeOnFloor);
    EXPECT_EQ(s->dt(), 0.01);
    for (int k = 0; k < 20; ++k) s->step();
    EXPECT_NEAR(s->simulation().time(), 0.2, 1e-15);
    const std::vector<Vec3>& x = scene_state_at(*s, "/Cube").position;
    ASSERT_EQ(x.size(), 8u);
    // SOFA HEAD after 20 steps (the cube's 8 points)
    const std::vector<Vec3> sofa = {{0.29916406159153625, 0.096040267808735924, 0.099164051160723368},
                                    {1.3008359622503212, 0.096040267808735924, 0.099164051160723354},
                                    {0.2991640615915363, 1.0886250210832058, 0.099164051160723424},
                                    {1.3008359622503212, 1.0886250210832058, 0.099164051160723451},
                                    {0.29916406159153613, 0.096040267808735924, 1.1008359518195083},
                                    {1.3008359622503212, 0.096040267808735966, 1.1008359518195083},
                                    {0.2991640615915363, 1.0886250210832058, 1.1008359518195083},
                                    {1.3008359622503212, 1.0886250210832056, 1.1008359518195083}};
    for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(x[i], sofa[i]) << "point " << i;
}

TEST(Scene, ContactsAreTheLivePairsNamedAfterTheirModelsAndKeptWhileThePairsStay) {
    auto s = build(kCubeOnFloor);
    EXPECT_TRUE(s->contacts().empty());  // no step yet: no contact
    s->step();
    ASSERT_EQ(s->contacts().size(), 1u);  // the floor's triangles against the cube's points
    const output::ContactRecord& r = s->contacts()[0];
    EXPECT_EQ(r.name, "floor_triangles-cube_points");  // SOFA's registered order: Triangle, then Point
    ASSERT_NE(r.field, nullptr);
    EXPECT_EQ(r.field->size(), 4u);  // the four bottom points, 0.15 m up: within the alarm distance 0.2
    const output::ContactRecord* record = s->contacts().data();
    const PenaltyForceField* field = r.field;
    for (int k = 0; k < 5; ++k) s->step();
    ASSERT_EQ(s->contacts().size(), 1u);
    EXPECT_EQ(s->contacts().data(), record);  // the same pair: the records stand
    EXPECT_EQ(s->contacts()[0].field, field);
    ASSERT_EQ(s->pipelines().size(), 1u);
    const auto& entries = s->pipelines()[0].pipeline->graph_entries();
    ASSERT_EQ(entries.size(), 1u);
    EXPECT_EQ(s->contacts()[0].state1, entries[0].point_states[0]);
    EXPECT_EQ(s->contacts()[0].state2, entries[0].point_states[1]);
}

// A pile whose pairs come and go: after every step the records are the pipelines' live pairs as
// output::contact_records makes them (names, fields, point states, in order), those of the pairs
// that stayed moved from the last list.
TEST(Scene, ContactsFollowPairsThatComeAndGo) {
    test::cubes_in_bowl::Setup setup;
    setup.k = 2;
    auto s = scene::build_scene(io::parse_scene_string(test::cubes_in_bowl::scene_xml(setup), "bowl.scn"));
    int changed = 0, kept = 0;
    std::vector<const PenaltyForceField*> last;
    for (int step = 0; step < 150; ++step) {
        s->step();
        std::vector<output::ContactRecord> expected;
        for (const auto& p : s->pipelines())
            for (output::ContactRecord& r : output::contact_records(*p.pipeline)) expected.push_back(std::move(r));
        ASSERT_EQ(s->contacts().size(), expected.size()) << "step " << step;
        std::vector<const PenaltyForceField*> fields;
        for (std::size_t i = 0; i < expected.size(); ++i) {
            const output::ContactRecord& r = s->contacts()[i];
            EXPECT_EQ(r.name, expected[i].name) << "step " << step << ", pair " << i;
            EXPECT_EQ(r.field, expected[i].field) << "step " << step << ", pair " << i;
            EXPECT_EQ(r.state1, expected[i].state1) << "step " << step << ", pair " << i;
            EXPECT_EQ(r.state2, expected[i].state2) << "step " << step << ", pair " << i;
            fields.push_back(r.field);
        }
        if (fields != last && !last.empty()) {
            ++changed;
            kept += std::any_of(fields.begin(), fields.end(),
                                [&](const PenaltyForceField* f) {
                                    return std::find(last.begin(), last.end(), f) != last.end();
                                })
                        ? 1
                        : 0;
        }
        last = fields;
    }
    EXPECT_GE(changed, 5);  // the cubes land, bounce and touch one another
    EXPECT_GE(kept, 5);     // with pairs that stayed
}

TEST(Scene, StepRecordsTheImplicitSolversStatisticsAndPhaseTimes) {
    auto s = build(kCubeOnFloor);
    EXPECT_TRUE(s->uses_cg());
    EXPECT_FALSE(s->uses_newton());
    const auto solvers = s->implicit_solvers();
    ASSERT_EQ(solvers.size(), 1u);
    EXPECT_EQ(solvers[0].first, "/Cube");
    for (int k = 0; k < 3; ++k) {
        s->step();
        EXPECT_EQ(s->last_solver_stats().cg_iterations, solvers[0].second->last_step_cg_iterations());
        EXPECT_GT(s->last_solver_stats().cg_iterations, 0);
        EXPECT_EQ(s->last_solver_stats().cg_limit_reached, solvers[0].second->last_step_cg_limit_reached());
        EXPECT_EQ(s->last_solver_stats().newton_iterations, 0);
        const scene::StepTimings& t = s->last_timings();
        EXPECT_GE(t.detection_seconds, 0.0);
        EXPECT_GE(t.response_seconds, 0.0);
        EXPECT_GE(t.solve_seconds, 0.0);
        EXPECT_EQ(t.guard_seconds, 0.0);  // no guard
    }
    // one CG iteration allowed: the limit is reached, and said
    std::string capped = kCubeOnFloor;
    capped.replace(capped.find("iterations=\"25\""), 15, "iterations=\"1\"");
    auto c = build(capped);
    c->step();
    EXPECT_EQ(c->last_solver_stats().cg_iterations, 1);
    EXPECT_TRUE(c->last_solver_stats().cg_limit_reached);
}

// Two moving points of 2 kg (velocities (1, 0, 0) and (0, 2, 0), at y = 1) under the root's
// gravity 10, a static 3 kg point at y = −1 (no solver), and a 5 kg point at y = 2 in a node whose
// Gravity component gives 1.6.
const std::string kMasses = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Ball">
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="dofs" position="0 1 0  1 1 0" velocity="1 0 0  0 2 0"/>
    <UniformMass totalMass="4"/>
  </Node>
  <Node name="Floor">
    <MechanicalObject name="dofs" position="0 -1 0"/>
    <UniformMass totalMass="3"/>
  </Node>
  <Node name="Moon">
    <Gravity gravity="0 -1.6 0"/>
    <EulerImplicitSolver/>
    <CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
    <MechanicalObject name="dofs" position="0 2 0"/>
    <UniformMass vertexMass="5"/>
  </Node>
</Node>)";

TEST(Scene, EnergiesAreTheClosedFormsOfTheMassesAndTheirNodesGravity) {
    auto s = build(kMasses);
    // ½·2·1² + ½·2·2²
    EXPECT_DOUBLE_EQ(s->kinetic_energy(), 5.0);
    // −Σ m g·x: 2·10·1 + 2·10·1 (Ball), −3·10·1 (Floor), 5·1.6·2 (Moon)
    EXPECT_DOUBLE_EQ(s->potential_energy(), 40.0 - 30.0 + 16.0);
    EXPECT_EQ(s->stored_energy(), 0.0);  // no force field
    EXPECT_EQ(s->potential_energy_from(0.0), s->potential_energy());
    EXPECT_DOUBLE_EQ(s->potential_energy_from(2.5), 40.0 - 30.0 + 16.0 + 2.5);  // a stored part first
    // the masses a step moves (not the floor's) dropped through the box along their gravity:
    // 4 kg·10·3 m + 5 kg·1.6·3 m
    EXPECT_DOUBLE_EQ(s->gravity_energy_scale(Vec3(0, 0, 0), Vec3(1, 3, 2)), 120.0 + 24.0);
    // a box without extent along gravity: its diagonal
    const double diagonal = std::sqrt(5.0);
    EXPECT_DOUBLE_EQ(s->gravity_energy_scale(Vec3(0, 0, 0), Vec3(1, 0, 2)), 4 * 10 * diagonal + 5 * 1.6 * diagonal);
}

TEST(Scene, StoredEnergyIsTheSpringsAsOfTheirLastForceEvaluation) {
    // a spring of rest length 1 stretched to 1.5, in no solver's node: ks = 100 / 1, its energy
    // ½·100·0.5² once the step evaluated its force
    auto s = build(R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Spring">
    <MechanicalObject name="dofs" position="0 0 0  1.5 0 0" rest_position="0 0 0  1 0 0"/>
    <MeshTopology edges="0 1"/>
    <MeshSpringForceField stiffness="100"/>
  </Node>
</Node>)");
    s->step();
    EXPECT_DOUBLE_EQ(s->stored_energy(), 12.5);
    EXPECT_DOUBLE_EQ(s->potential_energy(), 12.5);  // no mass: no gravity part
    EXPECT_EQ(s->kinetic_energy(), 0.0);
}

TEST(Scene, WarningsAddEachPipelinesSkippedPairsUnderItsName) {
    // MinProximity ignores Triangle–Triangle pairs: said once the pipeline has met the pair
    std::string text = kCubeOnFloor;
    text.replace(text.find("<CollisionPipeline/>"), 20, "<CollisionPipeline name=\"pipe\"/>");
    text.replace(text.find("<PointCollisionModel name=\"cube_points\"/>"), 41,
                 "<PointCollisionModel name=\"cube_points\"/><TriangleCollisionModel name=\"cube_faces\"/>");
    text.replace(text.find("<MeshTopology hexas=\"0 1 3 2 4 5 7 6\"/>"), 39,
                 "<MeshTopology hexas=\"0 1 3 2 4 5 7 6\" triangles=\"0 1 2\"/>");
    auto s = build(text);
    const std::vector<std::string> before = s->warnings();
    s->step();
    std::vector<std::string> after = s->warnings();
    ASSERT_EQ(after.size(), before.size() + 1);
    EXPECT_EQ(
        after.back(),
        "pipe: ContactPipeline: models 'floor_triangles' (Triangle) and 'cube_faces' (Triangle): pair ignored for "
        "this intersection method, no contact");
}

TEST(Scene, TheTunnellingGuardIsRefusedForAMultiStepLoopAndRemovedByModeOff) {
    auto s = build(kCubeOnFloor);
    EXPECT_EQ(s->tunnelling_report(), nullptr);
    EXPECT_EQ(s->tunnelling_options().mode, TunnellingMode::off);
    TunnellingOptions warn;
    warn.mode = TunnellingMode::warn;
    s->set_tunnelling(warn);
    const TunnellingReport* report = s->tunnelling_report();
    ASSERT_NE(report, nullptr);
    EXPECT_EQ(s->tunnelling_options().mode, TunnellingMode::warn);
    TunnellingOptions substep = warn;
    substep.mode = TunnellingMode::substep;
    s->set_tunnelling(substep);  // the same guard, its options changed
    EXPECT_EQ(s->tunnelling_report(), report);
    EXPECT_EQ(s->tunnelling_options().mode, TunnellingMode::substep);
    s->step();
    EXPECT_GE(s->last_timings().guard_seconds, 0.0);
    EXPECT_EQ(s->last_timings().guard_seconds, s->tunnelling_report()->guard_seconds);
    s->set_tunnelling(TunnellingOptions{});
    EXPECT_EQ(s->tunnelling_report(), nullptr);
    EXPECT_EQ(s->tunnelling_options().mode, TunnellingMode::off);
    std::string multi = kCubeOnFloor;
    multi.replace(multi.find("<CollisionPipeline/>"), 20,
                  "<MultiStepAnimationLoop collisionSteps=\"2\" integrationSteps=\"1\"/><CollisionPipeline/>");
    auto m = build(multi);
    try {
        m->set_tunnelling(warn);
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "the tunnelling guard checks single steps, not a MultiStepAnimationLoop's");
    }
    EXPECT_EQ(m->tunnelling_report(), nullptr);
}

TEST(Scene, BlockedReductionsReachEveryImplicitSolverAndTheOptions) {
    auto s = build(kMasses);
    ASSERT_EQ(s->implicit_solvers().size(), 2u);
    EXPECT_EQ(s->implicit_solvers()[0].first, "/Ball");
    EXPECT_EQ(s->implicit_solvers()[1].first, "/Moon");
    for (const bool on : {true, false}) {
        s->set_blocked_reductions(on);
        EXPECT_EQ(s->build_options().blocked_reductions, on);
        for (const auto& solver : s->implicit_solvers()) EXPECT_EQ(solver.second->blocked_reductions, on);
    }
}

TEST(Scene, RolesOriginsAndNodesLeadBackToTheFile) {
    auto s = build(kMasses);
    const io::SceneNode& root = *s->file().root;
    ASSERT_EQ(root.children.size(), 3u);
    const io::SceneNode& ball = *root.children[0];
    const Node* built = s->node_of(ball);
    ASSERT_NE(built, nullptr);
    EXPECT_EQ(built->name(), "Ball");
    EXPECT_EQ(s->node_of(root), &s->simulation().root());
    io::SceneNode stranger;
    EXPECT_EQ(s->node_of(stranger), nullptr);
    const io::SceneComponent& mass = *ball.components[3];
    ASSERT_EQ(mass.type, "UniformMass");
    EXPECT_EQ(s->role(mass), "mass 2 kg per DOF, 4 kg in all");
    EXPECT_EQ(s->component_of(built->mass()), &mass);
    EXPECT_EQ(s->component_of(nullptr), nullptr);
    io::SceneComponent unknown;
    EXPECT_EQ(s->role(unknown), "");
}

TEST(Scene, OverridesChangeTheTextBeforeTheBuildAndRefuseWhatATypeDoesNotRead) {
    scene::BuildOptions o;
    o.overrides = {"/Ball/dofs.velocity=0 0 0  3 0 0"};
    auto s = build(kMasses, o);
    EXPECT_DOUBLE_EQ(s->kinetic_energy(), 9.0);         // ½·2·3²
    EXPECT_TRUE(s->build_options().overrides.empty());  // applied to the file already
    o.overrides = {"/Ball/dofs.velocit=1 0 0"};
    try {
        (void)build(kMasses, o);
        ADD_FAILURE() << "no error";
    } catch (const io::SceneError& e) {
        EXPECT_THAT(e.what(), HasSubstr("velocit"));
        EXPECT_THAT(e.what(), HasSubstr("(it reads: position velocity rest_position src size"));
    }
}

TEST(Scene, LoadSceneReadsTheFileAsBuildSceneReadsItsText) {
    const auto dir = temp_dir("load");
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "masses.scn") << kMasses;
    auto loaded = scene::load_scene(dir / "masses.scn");
    EXPECT_EQ(loaded->file().root->children[0]->components[0]->file, (dir / "masses.scn").string());
    auto built = build(kMasses);
    for (int k = 0; k < 3; ++k) {
        loaded->step();
        built->step();
    }
    EXPECT_EQ(scene_state_at(*loaded, "/Ball").position, scene_state_at(*built, "/Ball").position);
    EXPECT_EQ(scene_state_at(*loaded, "/Moon").position, scene_state_at(*built, "/Moon").position);
    std::filesystem::remove_all(dir);
}

}  // namespace
