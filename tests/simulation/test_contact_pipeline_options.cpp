// ContactPipelineOptions: BVH detection equals the exhaustive loop inside the pipeline (detections,
// contacts and trajectories bit for bit over a moving mesh + sphere scene, 1 and 2 threads, with
// and without Newton geometry updates), several pipelines (registered contact stages, or run by the caller),
// phase timings, bad options.

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/function_stage.hpp"
#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/same_bits.hpp"
#include "penalty_test/same_contacts.hpp"
#include "penalty_test/static_floor.hpp"

#include <gtest/gtest.h>

#include <optional>

#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

namespace penalty {
namespace {

using test::same_bits;

/// A static bumpy floor (20 × 20 quads = 800 triangles), a falling sheet (8 × 8 quads, moving
/// mesh, its vertices also a Point model of the same node), a cloud of 60 spheres with
/// self-collision and a second sphere model of 15 spheres (same type: key order matters), all
/// simulated bodies under one implicit solver node that also hosts the body–body contacts.
struct MeshScene {
    Simulation sim;
    Node* bodies;
    EulerImplicitSolver* solver;
    MeshTopology floor_topology, sheet_topology;
    std::vector<std::unique_ptr<CollisionModel>> models;
    std::unique_ptr<ContactPipeline> pipeline;
    Vec3Object* cloud = nullptr;
    Vec3Object* sheet = nullptr;
    Vec3Object* few = nullptr;

    MeshScene(const ContactPipelineOptions& options, bool newton) {
        sim.root().set_gravity(Vec3(0, -9.81, 0));
        sim.root().set_dt(0.01);
        Node& floor = sim.root().add_child("floor");
        auto& fx = floor.add_state<Vec3Types>("floor");
        test::grid_mesh(
            20, 2.0, [](const test::GridVertex& v) { return 0.05 * std::sin(3.0 * v.x) * std::cos(2.0 * v.z); },
            fx.position, floor_topology);
        bodies = &sim.root().add_child("bodies");
        solver = &bodies->set_ode_solver<EulerImplicitSolver>();
        solver->cg.iterations = 50;
        solver->cg.tolerance = 1e-12;
        solver->cg.threshold = 1e-20;
        solver->newton.enabled = newton;
        solver->newton.max_iterations = 6;
        solver->newton.tolerance = 1e-9;

        std::mt19937_64 rng(1234);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        Node& cloud_node = bodies->add_child("cloud");
        cloud = &cloud_node.add_state<Vec3Types>("cloud");
        for (int i = 0; i < 60; ++i) {
            cloud->position.emplace_back(1.5 * u(rng), 0.18 + 0.15 * (u(rng) + 1.0), 1.5 * u(rng));
            cloud->velocity.emplace_back(0.5 * u(rng), -1.0 + 0.5 * u(rng), 0.5 * u(rng));
        }
        cloud_node.set_mass<UniformMass<Vec3Types>>(*cloud).set_vertex_mass(0.1);
        Node& few_node = bodies->add_child("few");
        few = &few_node.add_state<Vec3Types>("few");
        for (int i = 0; i < 15; ++i) {
            few->position.emplace_back(1.5 * u(rng), 0.2 + 0.2 * (u(rng) + 1.0), 1.5 * u(rng));
            few->velocity.emplace_back(0.0, -0.5, 0.0);
        }
        few_node.set_mass<UniformMass<Vec3Types>>(*few).set_vertex_mass(0.1);
        Node& sheet_node = bodies->add_child("sheet");
        sheet = &sheet_node.add_state<Vec3Types>("sheet");
        test::grid_mesh(
            8, 0.6, [](const test::GridVertex&) { return 0.45; }, sheet->position, sheet_topology);
        sheet->velocity.assign(sheet->position.size(), Vec3(0.2, -1.5, 0.0));
        sheet_node.set_mass<UniformMass<Vec3Types>>(*sheet).set_vertex_mass(0.05);

        CollisionModelParams p;
        p.contact_stiffness = 50.0;
        p.name = "floor";
        p.simulated = false;
        p.moving = false;
        auto floor_model = std::make_unique<TriangleModel>(fx, floor_topology, p);
        p.simulated = true;
        p.moving = true;
        p.name = "cloud";
        p.self_collision = true;
        auto cloud_model = std::make_unique<SphereModel>(*cloud, 0.08, std::vector<double>{}, p);
        p.self_collision = false;
        p.name = "few";
        auto few_model = std::make_unique<SphereModel>(*few, 0.1, std::vector<double>{}, p);
        p.name = "sheet";
        auto sheet_model = std::make_unique<TriangleModel>(*sheet, sheet_topology, p);
        p.name = "sheet_points";
        auto sheet_points = std::make_unique<PointModel>(*sheet, &sheet_topology, p);

        IntersectionParams ip = IntersectionParams::new_proximity();
        ip.alarm_distance = 0.05;
        ip.contact_distance = 0.01;
        pipeline = std::make_unique<ContactPipeline>(sim, ip, CollisionResponse(), bodies, options);
        pipeline->add_model(*floor_model, floor);
        pipeline->add_model(*cloud_model, cloud_node);
        pipeline->add_model(*few_model, few_node);
        pipeline->add_model(*sheet_model, sheet_node);
        pipeline->add_model(*sheet_points, sheet_node);
        models.push_back(std::move(floor_model));
        models.push_back(std::move(cloud_model));
        models.push_back(std::move(few_model));
        models.push_back(std::move(sheet_model));
        models.push_back(std::move(sheet_points));
        if (newton) pipeline->attach_newton(*solver);
    }
    ~MeshScene() { pipeline.reset(); }

    [[nodiscard]] std::size_t index_of(const CollisionModel* m) const {
        for (std::size_t i = 0; i < models.size(); ++i)
            if (models[i].get() == m) return i;
        return models.size();
    }
};

/// Detections (unless `detections` is false), contacts and positions of two scenes agree bit for
/// bit; returns the number of outputs compared.
std::size_t expect_identical(const MeshScene& a, const MeshScene& b, int step, bool detections = true) {
    const auto& da = a.pipeline->detections();
    const auto& db = b.pipeline->detections();
    EXPECT_EQ(da.size(), db.size()) << "step " << step;
    std::size_t outputs = 0;
    for (std::size_t k = 0; detections && k < std::min(da.size(), db.size()); ++k) {
        EXPECT_EQ(a.index_of(da[k].model1), b.index_of(db[k].model1)) << "step " << step << " pair " << k;
        EXPECT_EQ(a.index_of(da[k].model2), b.index_of(db[k].model2)) << "step " << step << " pair " << k;
        EXPECT_EQ(da[k].support, db[k].support);
        EXPECT_EQ(da[k].skipped, db[k].skipped);
        EXPECT_EQ(da[k].outputs.size(), db[k].outputs.size()) << "step " << step << " pair " << k;
        if (da[k].outputs.size() != db[k].outputs.size()) continue;
        for (std::size_t i = 0; i < da[k].outputs.size(); ++i) {
            const DetectionOutput& oa = da[k].outputs[i];
            const DetectionOutput& ob = db[k].outputs[i];
            EXPECT_EQ(oa.elem1, ob.elem1);
            EXPECT_EQ(oa.elem2, ob.elem2);
            EXPECT_EQ(oa.id, ob.id);
            EXPECT_TRUE(same_bits(oa.point[0], ob.point[0]) && same_bits(oa.point[1], ob.point[1]) &&
                        same_bits(oa.normal, ob.normal) && same_bits(oa.value, ob.value))
                << "step " << step << " pair " << k << " output " << i;
        }
        outputs += da[k].outputs.size();
    }
    test::expect_same_contacts(*a.pipeline, *b.pipeline, step);
    for (std::size_t i = 0; i < a.cloud->position.size(); ++i)
        EXPECT_TRUE(same_bits(a.cloud->position[i], b.cloud->position[i])) << "step " << step << " sphere " << i;
    for (std::size_t i = 0; i < a.sheet->position.size(); ++i)
        EXPECT_TRUE(same_bits(a.sheet->position[i], b.sheet->position[i])) << "step " << step << " vertex " << i;
    return outputs;
}

// The exhaustive loop and the BVH with every output give the same detections; the BVH with only
// the outputs a contact may be made of (the default) gives the same contacts and trajectories
// (here no pair reaches the 8 candidates per element 2 for which the candidates are pruned:
// test_contact_outputs_only.cpp has scenes where they are).
void run_bvh_vs_exhaustive(bool newton, int threads) {
    ContactPipelineOptions exhaustive;
    exhaustive.detection = ContactDetection::exhaustive;
    ContactPipelineOptions bvh;
    bvh.detection = ContactDetection::bvh;
    bvh.threads = threads;
    bvh.all_detection_outputs = true;
    ContactPipelineOptions contact_outputs = bvh;
    contact_outputs.all_detection_outputs = false;
    MeshScene a(exhaustive, newton);
    MeshScene b(bvh, newton);
    MeshScene c(contact_outputs, newton);
    a.sim.init();
    b.sim.init();
    c.sim.init();
    std::size_t outputs = 0, max_entries = 0;
    for (int step = 1; step <= 25; ++step) {
        a.sim.step();
        b.sim.step();
        c.sim.step();
        outputs += expect_identical(a, b, step);
        expect_identical(a, c, step, false);
        max_entries = std::max(max_entries, a.pipeline->graph_entries().size());
        if (newton) {
            EXPECT_EQ(a.solver->last_newton_iterations(), b.solver->last_newton_iterations());
            EXPECT_GT(b.pipeline->geometry_updates_this_step(), 0);
        }
    }
    // The scene exercises the pipeline: many outputs, several live pairs (floor–cloud,
    // floor–few, floor–sheet, cloud self, cloud–few, sheet–cloud, ...).
    EXPECT_GT(outputs, 500u);
    EXPECT_GE(max_entries, 4u);
    // 5 models: 15 pairs i ≤ j minus those keep_model_pair drops (floor with itself, few and
    // the sheet with themselves, sheet–sheet_points of the same node) minus skipped ones.
    EXPECT_EQ(a.pipeline->detections().size(), b.pipeline->detections().size());
    EXPECT_EQ(a.pipeline->skipped_pairs(), b.pipeline->skipped_pairs());
}

TEST(ContactPipelineOptions, BvhDetectionEqualsExhaustiveOverAMovingMeshScene) { run_bvh_vs_exhaustive(false, 2); }
TEST(ContactPipelineOptions, BvhDetectionEqualsExhaustiveOneThread) { run_bvh_vs_exhaustive(false, 1); }
TEST(ContactPipelineOptions, BvhDetectionEqualsExhaustiveWithNewtonGeometryUpdates) { run_bvh_vs_exhaustive(true, 0); }

// ---- several pipelines: registered stages, or run by the caller ---------------------------------
struct TwoSpheres {
    Simulation sim;
    test::StaticFloor floor{sim.root(), test::floor_params(10.0)};
    std::array<Node*, 2> nodes{};
    std::array<Vec3Object*, 2> states{};
    std::array<std::unique_ptr<SphereModel>, 2> spheres;

    TwoSpheres() {
        sim.root().set_dt(0.01);
        CollisionModelParams p;
        for (int i = 0; i < 2; ++i) {
            Node& n = sim.root().add_child(i == 0 ? "s0" : "s1");
            n.set_ode_solver<EulerImplicitSolver>().cg.tolerance = 1e-12;
            auto& x = n.add_state<Vec3Types>("x");
            x.position = {Vec3(3.0 * i, 0.9 + 0.2 * i, 0)};
            n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(1.0);
            p.name = i == 0 ? "s0" : "s1";
            p.simulated = true;
            p.moving = true;
            spheres[std::size_t(i)] = std::make_unique<SphereModel>(x, 0.5, std::vector<double>{}, p);
            nodes[std::size_t(i)] = &n;
            states[std::size_t(i)] = &x;
        }
    }
};

TEST(ContactPipelineOptions, SeveralPipelinesGiveTheTrajectoryOfOne) {
    // Reference: one pipeline over the three models (registered as the contact stage).
    TwoSpheres ref;
    std::vector<Vec3> ref_positions;
    {
        ContactPipeline p(ref.sim);
        p.add_model(*ref.floor.model, *ref.floor.node);
        p.add_model(*ref.spheres[0], *ref.nodes[0]);
        p.add_model(*ref.spheres[1], *ref.nodes[1]);
        for (int k = 0; k < 60; ++k) ref.sim.step();
        EXPECT_EQ(p.graph_entries().size(), 2u);
        ref_positions = {ref.states[0]->position[0], ref.states[1]->position[0]};
    }
    EXPECT_TRUE(ref.sim.contact_stages().empty());  // unregistered by the destructor

    // Two sub-pipelines (floor–s0 and floor–s1): registered stages (the step detects with both,
    // then responds with both), or run by the caller's own stage (update() of one, then of the
    // other).
    for (const bool registered : {true, false}) {
        TwoSpheres two;
        ContactPipelineOptions options;
        options.register_stage = registered;
        ContactPipeline p0(two.sim, IntersectionParams::new_proximity(), CollisionResponse(), nullptr, options);
        ContactPipeline p1(two.sim, IntersectionParams::new_proximity(), CollisionResponse(), nullptr, options);
        p0.add_model(*two.floor.model, *two.floor.node);
        p0.add_model(*two.spheres[0], *two.nodes[0]);
        p1.add_model(*two.floor.model, *two.floor.node);
        p1.add_model(*two.spheres[1], *two.nodes[1]);
        EXPECT_EQ(p0.options().register_stage, registered);
        EXPECT_EQ(two.sim.contact_stages().size(), registered ? 2u : 0u);
        int caller_updates = 0;
        std::optional<test::FunctionStage> caller;
        if (!registered)
            caller.emplace(two.sim, [&] {
                ++caller_updates;
                p0.update();
                p1.update();
            });
        for (int k = 0; k < 60; ++k) two.sim.step();
        EXPECT_EQ(caller_updates, registered ? 0 : 60);
        ASSERT_EQ(p0.graph_entries().size(), 1u);
        ASSERT_EQ(p1.graph_entries().size(), 1u);
        EXPECT_EQ(&p1.graph_entries()[0].contact->model2(), two.spheres[1].get());
        // Same springs, same nodes, same order of force fields: the same trajectories, bit for bit.
        EXPECT_TRUE(same_bits(two.states[0]->position[0], ref_positions[0])) << "registered " << registered;
        EXPECT_TRUE(same_bits(two.states[1]->position[0], ref_positions[1])) << "registered " << registered;
    }
}

// ---- timings -------------------------------------------------------------------------------------
TEST(ContactPipelineOptions, PhaseTimingsAreMeasuredEachUpdate) {
    ContactPipelineOptions opt;
    opt.detection = ContactDetection::bvh;
    MeshScene s(opt, false);
    EXPECT_EQ(s.pipeline->last_timings().detection_seconds, 0.0);
    EXPECT_EQ(s.pipeline->last_timings().response_seconds, 0.0);
    s.sim.init();
    double total_response = 0.0;
    for (int k = 0; k < 10; ++k) {
        s.sim.step();
        const ContactPipelineTimings t = s.pipeline->last_timings();
        EXPECT_TRUE(std::isfinite(t.detection_seconds));
        EXPECT_TRUE(std::isfinite(t.response_seconds));
        EXPECT_GT(t.detection_seconds, 0.0);  // 5 models, 800-triangle floor: never 0 ns
        EXPECT_GE(t.response_seconds, 0.0);
        total_response += t.response_seconds;
    }
    EXPECT_GT(total_response, 0.0);  // contacts were created and fed
    // A direct update() is timed too.
    s.pipeline->update();
    EXPECT_GT(s.pipeline->last_timings().detection_seconds, 0.0);
}

TEST(ContactPipelineOptions, BadOptionsThrow) {
    Simulation sim;
    ContactPipelineOptions opt;
    opt.threads = -1;
    EXPECT_THROW(ContactPipeline(sim, IntersectionParams::new_proximity(), CollisionResponse(), nullptr, opt),
                 std::invalid_argument);
    opt.threads = 0;
    opt.bvh.leaf_size = 0;
    EXPECT_THROW(ContactPipeline(sim, IntersectionParams::new_proximity(), CollisionResponse(), nullptr, opt),
                 std::invalid_argument);
    EXPECT_TRUE(sim.contact_stages().empty());  // a pipeline that failed to build registered nothing
    // A stage is registered once.
    ContactPipeline p(sim);
    EXPECT_EQ(sim.contact_stages().size(), 1u);
    EXPECT_THROW(sim.add_contact_stage(p), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
