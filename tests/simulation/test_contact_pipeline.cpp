// ContactPipeline: penalty contacts in the scene graph (spec §2, §2.1), worked example E end to
// end (detection → response → graph → solver), explicit contacts, the CG threshold quirk, pair
// removal/recreation, rigid parents (rigid mapper and RigidMapping chain).

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>

namespace penalty {
namespace {

constexpr double kEv[5] = {0.0018811881188119, 0.0037251249877462, 0.0055139226303769, 0.0072304161118887,
                           0.0088583263300995};
constexpr double kEy[5] = {0.9000188118811882, 0.9000560631310656, 0.9001112023573693, 0.9001835065184882,
                           0.9002720897817892};

/// Counts nodes and force fields of a subtree.
void count(const Node& n, int& nodes, int& ffs) {
    ++nodes;
    ffs += static_cast<int>(n.force_fields().size());
    for (const auto& c : n.children()) count(*c, nodes, ffs);
}

/// Two-triangle static floor at y = 0 (normal +y), ±10 m.
struct Floor {
    Node* node;
    Vec3Object* state;
    MeshTopology topology;
    std::unique_ptr<TriangleModel> model;

    Floor(Node& parent, bool simulated) {
        node = &parent.add_child("floor");
        state = &node->add_state<Vec3Types>("floor");
        state->position = {Vec3(-10, 0, -10), Vec3(-10, 0, 10), Vec3(10, 0, 10), Vec3(10, 0, -10)};
        topology.set_num_points(4);
        topology.set_triangles({Triangle{0, 1, 2}, Triangle{0, 2, 3}});
        CollisionModelParams p;
        p.name = "floor";
        p.contact_stiffness = 10.0;
        p.simulated = simulated;
        p.moving = false;
        model = std::make_unique<TriangleModel>(*state, topology, p);
    }
};

/// Example E scene: a Vec3 sphere (vertexMass 1, radius 0.5, k 10) at (0.2, 0.9, 0.3), v = 0,
/// EulerImplicit rs = rm = 0, CG 25 iterations with tolerance = threshold = `cg_eps`.
struct SphereOnFloor {
    Simulation sim;
    Floor floor;
    Node* body;
    EulerImplicitSolver* solver;
    Vec3Object* sphere;
    std::unique_ptr<SphereModel> model;
    std::unique_ptr<ContactPipeline> pipeline;

    explicit SphereOnFloor(bool explicit_contact, double cg_eps = 1e-9) : floor(sim.root(), explicit_contact) {
        sim.root().set_gravity(Vec3(0, -9.81, 0));
        sim.root().set_dt(0.01);
        body = &sim.root().add_child("sphere");
        solver = &body->set_ode_solver<EulerImplicitSolver>();
        solver->cg.iterations = 25;
        solver->cg.tolerance = cg_eps;
        solver->cg.threshold = cg_eps;
        sphere = &body->add_state<Vec3Types>("sphere");
        sphere->position = {Vec3(0.2, 0.9, 0.3)};
        body->set_mass<UniformMass<Vec3Types>>(*sphere).set_vertex_mass(1.0);
        CollisionModelParams p;
        p.name = "sphere";
        p.contact_stiffness = 10.0;
        model = std::make_unique<SphereModel>(*sphere, 0.5, std::vector<double>{}, p);
        pipeline = std::make_unique<ContactPipeline>(sim, IntersectionParams::new_proximity());
        pipeline->add_model(*floor.model, *floor.node);
        pipeline->add_model(*model, *body);
    }
    ~SphereOnFloor() { pipeline.reset(); }
};

TEST(ContactPipeline, WorkedExampleEImplicitEndToEnd) {
    SphereOnFloor s(/*explicit_contact=*/false);
    s.sim.init();
    for (int k = 0; k < 5; ++k) {
        s.sim.step();
        EXPECT_NEAR(s.sphere->velocity[0].y(), kEv[k], 1e-12) << "step " << k + 1;
        EXPECT_NEAR(s.sphere->position[0].y(), kEy[k], 1e-12) << "step " << k + 1;
        EXPECT_NEAR(s.sphere->position[0].x(), 0.2, 1e-14);
        EXPECT_NEAR(s.sphere->position[0].z(), 0.3, 1e-14);
        // One live pair (floor, sphere) in registered order Triangle–Sphere, one spring
        // dist = 1, ks = 100, stored in the sphere's node (floor not simulated → model2's node).
        ASSERT_EQ(s.pipeline->graph_entries().size(), 1u);
        const ContactGraphEntry& e = s.pipeline->graph_entries()[0];
        EXPECT_EQ(&e.contact->model1(), s.floor.model.get());
        EXPECT_EQ(e.host, s.body);
        ASSERT_EQ(e.contact->force_field().size(), 1u);
        EXPECT_DOUBLE_EQ(e.contact->force_field().contacts()[0].dist, 1.0);
        EXPECT_DOUBLE_EQ(e.contact->force_field().contacts()[0].ks, 100.0);
        EXPECT_EQ(e.point_nodes[0]->parent(), s.floor.node);  // barycentric point on the floor
        EXPECT_EQ(e.point_nodes[1], nullptr);                 // identity: the sphere's own DOF
        EXPECT_EQ(e.point_states[1], s.sphere);
    }
    // The floor never moves.
    EXPECT_EQ(s.floor.state->position[0], Vec3(-10, 0, -10));
}

TEST(ContactPipeline, WorkedExampleEExplicitContactAtRoot) {
    // Both models simulated, the sphere's solver in a child node, the contact at the root
    // (no solver): Δv = h·f/m with f from the start-of-step positions.
    SphereOnFloor s(/*explicit_contact=*/true);
    s.sim.init();
    const double v[3] = {0.0019, 0.003781, 0.00562419};
    const double y[3] = {0.900019, 0.90005681, 0.9001130519};
    for (int k = 0; k < 3; ++k) {
        s.sim.step();
        ASSERT_EQ(s.pipeline->graph_entries().size(), 1u);
        EXPECT_EQ(s.pipeline->graph_entries()[0].host, &s.sim.root());
        EXPECT_NEAR(s.sphere->velocity[0].y(), v[k], 1e-12) << "step " << k + 1;
        EXPECT_NEAR(s.sphere->position[0].y(), y[k], 1e-12) << "step " << k + 1;
    }
    EXPECT_EQ(s.floor.state->position[2], Vec3(10, 0, 10));  // outside every solver
}

TEST(ContactPipeline, WorkedExampleECgThresholdQuirk) {
    // CG tolerance = threshold = 1e-5: pᵀAp ≈ 3.6e-6 ≤ threshold, so from the second solve on CG
    // stops before updating x (Δv = 0): SOFA HEAD keeps v_y = 0.0018811881188118586.
    SphereOnFloor s(/*explicit_contact=*/false, 1e-5);
    s.sim.init();
    double y = 0.9;
    for (int k = 0; k < 5; ++k) {
        s.sim.step();
        EXPECT_NEAR(s.sphere->velocity[0].y(), 0.0018811881188118586, 1e-15) << "step " << k + 1;
        y += 0.01 * 0.0018811881188118586;
        EXPECT_NEAR(s.sphere->position[0].y(), y, 1e-13) << "step " << k + 1;
        if (k > 0) EXPECT_EQ(s.solver->last_cg_stats().end_condition, "threshold");
    }
}

}  // namespace
}  // namespace penalty
