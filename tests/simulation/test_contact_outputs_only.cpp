// CollisionPipelineOptions::contact_outputs_only (ContactPipeline's default): spheres and points
// over a static grid (Triangle, Line and Point models) with an alarm distance of several grid
// cells, so that each sphere or point has tens of candidates and the tracker keeps one output of
// each. For every proximity method the contacts and the trajectories are those of all outputs,
// bit for bit, from far fewer outputs; the spheres and points start exactly above grid vertices,
// where several lines (and triangles) give the same least value: those ties must all be kept.

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/same_bits.hpp"
#include "penalty_test/same_contacts.hpp"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace penalty {
namespace {

using test::same_bits;

struct GridScene {
    Simulation sim;
    MeshTopology grid_topology;
    std::vector<std::unique_ptr<CollisionModel>> models;
    std::unique_ptr<ContactPipeline> pipeline;
    Vec3Object* spheres = nullptr;
    Vec3Object* probes = nullptr;

    GridScene(const IntersectionParams& ip, bool all_outputs) {
        sim.root().set_gravity(Vec3(0, -9.81, 0));
        sim.root().set_dt(0.01);
        Node& grid = sim.root().add_child("grid");
        auto& gx = grid.add_state<Vec3Types>("grid");
        // 8 × 8 quads over [−2, 2]²: vertices at multiples of 0.5, flat at y = 0 (exact ties)
        test::grid_mesh(
            8, 2.0, [](const test::GridVertex&) { return 0.0; }, gx.position, grid_topology);
        Node& bodies = sim.root().add_child("bodies");
        auto& solver = bodies.set_ode_solver<EulerImplicitSolver>();
        solver.cg.iterations = 50;
        solver.cg.tolerance = 1e-12;
        solver.cg.threshold = 1e-20;
        Node& sphere_node = bodies.add_child("spheres");
        spheres = &sphere_node.add_state<Vec3Types>("spheres");
        spheres->position = {Vec3(0.0, 0.45, 0.0), Vec3(0.5, 0.5, -1.0), Vec3(-1.0, 0.55, 1.0)};
        spheres->velocity = {Vec3(0.1, -0.5, 0.0), Vec3(0.0, -0.6, 0.05), Vec3(-0.05, -0.4, 0.0)};
        sphere_node.set_mass<UniformMass<Vec3Types>>(*spheres).set_vertex_mass(0.2);
        Node& probe_node = bodies.add_child("probes");
        probes = &probe_node.add_state<Vec3Types>("probes");
        probes->position = {Vec3(1.0, 0.3, 1.0), Vec3(-0.5, 0.35, -0.5), Vec3(1.5, 0.25, 0.0), Vec3(-1.5, 0.3, -1.5)};
        probes->velocity.assign(probes->position.size(), Vec3(0.05, -0.5, 0.02));
        probe_node.set_mass<UniformMass<Vec3Types>>(*probes).set_vertex_mass(0.1);

        CollisionModelParams p;
        p.contact_stiffness = 20.0;
        p.simulated = false;
        p.moving = false;
        p.name = "grid_triangles";
        models.push_back(std::make_unique<TriangleModel>(gx, grid_topology, p));
        p.name = "grid_lines";
        models.push_back(std::make_unique<LineModel>(gx, grid_topology, p));
        p.simulated = true;
        p.moving = true;
        p.name = "spheres";
        models.push_back(std::make_unique<SphereModel>(*spheres, 0.2, std::vector<double>{}, p));
        p.name = "probes";
        models.push_back(std::make_unique<PointModel>(*probes, nullptr, p));

        ContactPipelineOptions options;
        options.detection = ContactDetection::bvh;
        options.all_detection_outputs = all_outputs;
        pipeline = std::make_unique<ContactPipeline>(sim, ip, CollisionResponse(), &bodies, options);
        pipeline->add_model(*models[0], grid);
        pipeline->add_model(*models[1], grid);
        pipeline->add_model(*models[2], sphere_node);
        pipeline->add_model(*models[3], probe_node);
    }
    ~GridScene() { pipeline.reset(); }

    [[nodiscard]] std::size_t outputs() const {
        std::size_t n = 0;
        for (const ModelPairDetection& d : pipeline->detections()) n += d.outputs.size();
        return n;
    }
    /// Ids of the detections whose least value is reached by more than one output.
    [[nodiscard]] std::size_t tied_ids() const {
        std::size_t tied = 0;
        for (const ModelPairDetection& d : pipeline->detections()) {
            std::map<std::int64_t, std::pair<double, int>> least;  // id → (least value, how many)
            for (const DetectionOutput& o : d.outputs) {
                auto [it, fresh] = least.try_emplace(o.id, o.value, 1);
                if (fresh) continue;
                if (o.value < it->second.first) it->second = {o.value, 1};
                else if (o.value == it->second.first) ++it->second.second;
            }
            for (const auto& [id, v] : least) tied += v.second > 1 ? 1 : 0;
        }
        return tied;
    }
};

void expect_same_contacts(const GridScene& a, const GridScene& b, int step) {
    test::expect_same_contacts(*a.pipeline, *b.pipeline, step);
    for (std::size_t i = 0; i < a.spheres->position.size(); ++i)
        EXPECT_TRUE(same_bits(a.spheres->position[i], b.spheres->position[i])) << "step " << step << " sphere " << i;
    for (std::size_t i = 0; i < a.probes->position.size(); ++i)
        EXPECT_TRUE(same_bits(a.probes->position[i], b.probes->position[i])) << "step " << step << " probe " << i;
}

/// reduction: all outputs / fewer outputs at least; ties: the scene must show exact ties (not
/// for LocalMinDistance, whose strict interior projections miss the vertices under the bodies).
void run(IntersectionParams ip, double reduction, bool ties_expected) {
    ip.alarm_distance = 1.0;  // two grid cells: tens of candidates per sphere or point
    ip.contact_distance = 0.1;
    GridScene all(ip, true);
    GridScene fewer(ip, false);
    all.sim.init();
    fewer.sim.init();
    std::size_t all_outputs = 0, fewer_outputs = 0, contacts = 0, ties = 0;
    for (int step = 1; step <= 40; ++step) {
        all.sim.step();
        fewer.sim.step();
        expect_same_contacts(all, fewer, step);
        all_outputs += all.outputs();
        fewer_outputs += fewer.outputs();
        ties += all.tied_ids();
        for (const ContactGraphEntry& e : all.pipeline->graph_entries()) contacts += e.contact->force_field().size();
        if (testing::Test::HasFailure()) return;
    }
    // every contact needs an output; the dropped ones are most of them
    EXPECT_GE(fewer_outputs, contacts);
    EXPECT_GT(double(all_outputs), reduction * double(fewer_outputs)) << fewer_outputs << " of " << all_outputs;
    EXPECT_GT(contacts, 100u);
    // the scene has ids whose least value several outputs share (exact ties)
    if (ties_expected) {
        EXPECT_GE(ties, 5u);
    }
}

TEST(ContactOutputsOnly, NewProximitySameContactsFromFewerOutputs) {
    run(IntersectionParams::new_proximity(), 5.0, true);
}

TEST(ContactOutputsOnly, NewProximityWithTheTriangleSphereEdgeRangeFixed) {
    IntersectionParams ip = IntersectionParams::new_proximity();
    ip.quirks.fix_newproximity_triangle_sphere_edge_range = true;
    run(ip, 15.0, true);
}

TEST(ContactOutputsOnly, MinProximitySameContactsFromFewerOutputs) {
    run(IntersectionParams::min_proximity(), 8.0, true);
}

TEST(ContactOutputsOnly, LocalMinDistanceSameContactsFromFewerOutputs) {
    run(IntersectionParams::local_min_distance(), 1.1, false);
}

}  // namespace
}  // namespace penalty
