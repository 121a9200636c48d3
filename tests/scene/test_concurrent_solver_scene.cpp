// A scene whose bodies have their own solvers (like SOFA's MeshSpringForceField and Gravity
// scenes): three spring grids, each under its own EulerImplicitSolver, fall onto a static floor
// one after the other. Their solvers touch disjoint states (each pair's contact points are its
// own), so Simulation::step runs them concurrently on two threads (their 16 contacts each are
// too few to detect the pairs or feed the contacts in parallel: CollisionPipeline::detect,
// CollisionResponse::set_detections). The trajectory, the contacts and the CG counts must be
// the bits of one thread (tests/simulation/test_solve_plan.cpp checks that the solves
// do overlap).
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/response/penalty_force_field.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace penalty;

// Grid b: 4×4×4 points (192 unknowns, above kMinUnknownsPerConcurrentSolve), 0.3 m wide, its
// lowest face 0.05 + 0.35·b m above the floor: the grids land at steps 25–100 or so.
std::string scene_xml() {
    std::ostringstream s;
    s << R"(<Node name="root" dt="0.004" gravity="0 -9.81 0">
  <CollisionPipeline depth="6"/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.02" contactDistance="0.01"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Floor">
    <MeshTopology position="-2 0 -2  -2 0 2  2 0 2  2 0 -2" triangles="0 1 2  0 2 3"/>
    <MechanicalObject/>
    <TriangleCollisionModel simulated="0" moving="0" contactStiffness="100"/>
  </Node>
)";
    for (int b = 0; b < 3; ++b) {
        const double x = 0.25 * b - 0.25;
        const double y = 0.05 + 0.35 * b;
        s << "  <Node name=\"Grid" << b << "\">\n"
          << "    <EulerImplicitSolver rayleighStiffness=\"0.05\" rayleighMass=\"0.1\"/>\n"
          << "    <CGLinearSolver iterations=\"60\" tolerance=\"1e-10\" threshold=\"1e-20\"/>\n"
          << "    <RegularGridTopology n=\"4 4 4\" min=\"" << x << " " << y << " " << 0.01 * b << "\" max=\"" << x + 0.3
          << " " << y + 0.3 << " " << 0.3 + 0.01 * b << "\"/>\n"
          << "    <MechanicalObject/>\n"
          << "    <UniformMass totalMass=\"" << 4.0 + 0.5 * b << "\"/>\n"
          << "    <RegularGridSpringForceField stiffness=\"" << 800 + 100 * b << "\" damping=\"0\"/>\n"
          << "    <PointCollisionModel contactStiffness=\"100\"/>\n"
          << "  </Node>\n";
    }
    s << "</Node>\n";
    return s.str();
}

struct GridsRun {
    std::size_t concurrent_solvers = 0;  // in the one run of concurrent solvers, at the last step
    int concurrent_detections = 0;       // steps whose model pairs were detected in parallel
    int concurrent_feeds = 0;            // steps whose contacts were fed in parallel
    std::vector<Vec3> states;            // positions then velocities of every grid
    std::vector<std::size_t> contacts;   // per step
    std::vector<int> cg_iterations;      // per step
};

GridsRun run(int threads, int steps) {
    scene::BuildOptions options;
    options.threads = threads;
    const auto scene = scene::build_scene(io::parse_scene_string(scene_xml(), "grids.scn"), options);
    GridsRun r;
    for (int s = 0; s < steps; ++s) {
        scene->step();
        const ContactPipeline& pipeline = *scene->pipelines().at(0).pipeline;
        r.concurrent_detections += pipeline.collision().last_detection_concurrent() ? 1 : 0;
        r.concurrent_feeds += pipeline.response().last_feed_concurrent() ? 1 : 0;
        std::size_t contacts = 0;
        for (const auto& c : scene->contacts()) contacts += c.field->size();
        r.contacts.push_back(contacts);
        r.cg_iterations.push_back(scene->last_solver_stats().cg_iterations);
    }
    const auto runs = scene->simulation().concurrent_solver_runs();
    if (runs.size() == 1) r.concurrent_solvers = runs[0].size();
    for (const auto& st : scene->states()) {
        if (st.node_path.rfind("/Grid", 0) != 0) continue;
        const auto& x = dynamic_cast<const Vec3Object&>(*st.state);
        r.states.insert(r.states.end(), x.position.begin(), x.position.end());
        r.states.insert(r.states.end(), x.velocity.begin(), x.velocity.end());
    }
    return r;
}

TEST(ConcurrentSolverScene, GridsOnTheirOwnSolversGiveTheBitsOfOneThread) {
    const tbb::global_control two_workers(tbb::global_control::max_allowed_parallelism, 2);
    const int steps = 200;
    const GridsRun one = run(1, steps);
    const GridsRun two = run(2, steps);
    // the scene does what it is for: the three grids resting on the floor (a bottom layer of 16
    // points each), at rest, CG working
    EXPECT_EQ(one.contacts.back(), 48u);
    EXPECT_GT(one.cg_iterations.back(), 3 * 3);
    ASSERT_EQ(one.states.size(), 3u * 64u * 2u);
    for (int b = 0; b < 3; ++b) {
        EXPECT_NEAR(one.states[std::size_t(b) * 128].y(), 0.0, 0.02) << "grid " << b;   // a bottom corner
        EXPECT_LT(one.states[std::size_t(b) * 128 + 64].norm(), 0.05) << "grid " << b;  // its velocity
    }
    // the three solvers form one run (contact pairs between grids are in the root, explicit)
    EXPECT_EQ(two.concurrent_solvers, 3u);
    // the pairs detected and their contacts fed in order (too few candidates and outputs)
    EXPECT_EQ(one.concurrent_feeds, 0);
    EXPECT_EQ(two.concurrent_feeds, 0);
    EXPECT_EQ(one.concurrent_detections, 0);
    EXPECT_EQ(two.concurrent_detections, 0);
    EXPECT_EQ(one.contacts, two.contacts);
    EXPECT_EQ(one.cg_iterations, two.cg_iterations);
    int differing = 0;
    for (std::size_t i = 0; i < one.states.size(); ++i)
        differing += test::same_bits(one.states[i], two.states[i]) ? 0 : 1;
    EXPECT_EQ(differing, 0);
}

}  // namespace
