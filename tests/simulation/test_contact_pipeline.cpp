// ContactPipeline: penalty contacts in the scene graph (spec §2, §2.1), worked example E end to
// end (detection → response → graph → solver), explicit contacts, the CG threshold quirk, pair
// removal/recreation, rigid parents (rigid mapper and RigidMapping chain).

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/spheres_on_floor.hpp"
#include "penalty_test/static_floor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>

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

/// Two-triangle static floor at y = 0 (normal +y), ±10 m, contact stiffness 10.
struct Floor : test::StaticFloor {
    Floor(Node& parent, bool simulated) : StaticFloor(parent, test::floor_params(10.0, simulated)) {}
};

/// Example E's setup (the fixture's defaults), the floor simulated or not.
test::SpheresOnFloorSetup example_e(bool floor_simulated) {
    test::SpheresOnFloorSetup setup;
    setup.floor_simulated = floor_simulated;
    return setup;
}

/// Example E scene: a Vec3 sphere (vertexMass 1, radius 0.5, k 10) at (0.2, 0.9, 0.3), v = 0,
/// EulerImplicit rs = rm = 0, CG 25 iterations with tolerance = threshold = `cg_eps`.
struct SphereOnFloor : test::SpheresOnFloor {
    Vec3Object* sphere = spheres;  // the one sphere's state

    explicit SphereOnFloor(bool explicit_contact, double cg_eps = 1e-9) : SpheresOnFloor(example_e(explicit_contact)) {
        solver->cg.iterations = 25;
        solver->cg.tolerance = cg_eps;
        solver->cg.threshold = cg_eps;
    }
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
        if (k > 0) {
            EXPECT_EQ(s.solver->last_cg_stats().end_condition, CgEndCondition::threshold);
        }
    }
}

TEST(ContactPipeline, PairWithoutOutputsIsRemovedFromTheGraphAndRecreated) {
    // The sphere starts inside the alarm zone (|c − p| = 1.45 < A + r = 1.5), leaves it at step 2
    // (y = 1.509) and falls back under gravity. While the pair lives the graph holds one
    // contact-point node (barycentric, under the floor) and one force field (in the sphere's node).
    SphereOnFloor s(/*explicit_contact=*/false);
    s.sphere->position = {Vec3(0.2, 1.45, 0.3)};
    s.sphere->velocity = {Vec3(0, 6.0, 0)};
    s.sim.init();
    int nodes0 = 0, ffs0 = 0;
    count(s.sim.root(), nodes0, ffs0);
    ASSERT_EQ(nodes0, 3);  // root, floor, sphere
    ASSERT_EQ(ffs0, 0);
    std::vector<int> events;  // +step: created, −step: destroyed
    bool live_before = false;
    double v = 6.0;
    for (int k = 0; k < 400; ++k) {
        const double y_detect = s.sphere->position[0].y();
        s.sim.step();
        const bool live = !s.pipeline->graph_entries().empty();
        EXPECT_EQ(live, y_detect < 1.5) << "step " << k + 1 << " y " << y_detect;
        int nodes = 0, ffs = 0;
        count(s.sim.root(), nodes, ffs);
        EXPECT_EQ(nodes, live ? 4 : 3) << "step " << k + 1;
        EXPECT_EQ(ffs, live ? 1 : 0) << "step " << k + 1;
        EXPECT_EQ(s.body->force_fields().size(), live ? 1u : 0u);
        EXPECT_EQ(s.floor.node->children().size(), live ? 1u : 0u);
        EXPECT_EQ(s.pipeline->response().pairs().size(), live ? 1u : 0u);
        if (live) {
            const ContactGraphEntry& e = s.pipeline->graph_entries()[0];
            ASSERT_EQ(e.contact->force_field().size(), 1u);
            EXPECT_EQ(e.point_states[0]->position.size(), 1u);
            // A recreated pair starts from scratch (SOFA): its spring is new (age 0).
            if (!live_before) {
                EXPECT_EQ(e.contact->force_field().contacts()[0].age, 0) << "step " << k + 1;
            }
        }
        if (live != live_before) events.push_back(live ? k + 1 : -(k + 1));
        live_before = live;
        // Out of reach of the spring (y > dist = 1): free flight, Δv = h·g exactly.
        if (y_detect > 1.0) {
            v -= 0.01 * 9.81;
            EXPECT_NEAR(s.sphere->velocity[0].y(), v, 1e-11) << "step " << k + 1;
        } else {
            v = s.sphere->velocity[0].y();
        }
    }
    // Created at step 1, destroyed at step 2 (y = 1.509 > 1.5), recreated on the way down
    // (step 122: free flight from the apex), then bounces (implicit Euler loses a little energy
    // each contact, so the sphere keeps leaving the alarm zone).
    EXPECT_EQ(events, (std::vector<int>{1, -2, 122, -175, 266, -325, 389}));
}

TEST(ContactPipeline, RigidSphereOnFloorThroughRigidMapper) {
    // RigidSphereModel on a Rigid3 body (mass 1): the contact point is a Vec3 node under the body
    // mapped by the rigid contact mapper, point1 = c − n·r, local L = (0, −0.5, 0). SOFA HEAD:
    // dist = C + r = 1.0, ks = 100, pen = dist − (x_c − p)·n = 1.0 − (y − 0.5) (radius twice).
    Simulation sim;
    sim.root().set_gravity(Vec3(0, -9.81, 0));
    sim.root().set_dt(0.01);
    Floor floor(sim.root(), false);
    Node& body = sim.root().add_child("ball");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    solver.cg.tolerance = 1e-12;
    solver.cg.threshold = 1e-20;
    auto& ball = body.add_state<Rigid3Types>("ball");
    RigidFrame f0;
    f0.center = Vec3(0.2, 0.9, 0.3);
    f0.orientation = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
    ball.position = {f0};
    auto& mass = body.set_mass<UniformMass<Rigid3Types>>(ball);
    mass.set_vertex_mass(1.0);
    mass.set_inertia(Mat3::Identity() * 0.1);
    CollisionModelParams p;
    p.name = "ball";
    p.contact_stiffness = 10.0;
    RigidSphereModel model(ball, 0.5, {}, p);
    {
        ContactPipeline pipeline(sim);
        pipeline.add_model(*floor.model, *floor.node);
        pipeline.add_model(model, body);
        sim.init();
        sim.step();
        ASSERT_EQ(pipeline.graph_entries().size(), 1u);
        const ContactGraphEntry& e = pipeline.graph_entries()[0];
        EXPECT_EQ(e.host, &body);  // floor not simulated → model2's node
        ASSERT_NE(e.point_nodes[1], nullptr);
        EXPECT_EQ(e.point_nodes[1]->parent(), &body);  // rigid contact point under the body
        const PenaltyContact& c = e.contact->force_field().contacts()[0];
        EXPECT_DOUBLE_EQ(c.dist, 1.0);
        EXPECT_DOUBLE_EQ(c.ks, 100.0);
        EXPECT_NEAR(c.pen, 0.6, 1e-12);
        // Force reaching the body at the start of step 1 (compute_force leaves it in `force`):
        // gravity + 60 N up; torque (R·L) × F = (0, −0.5, 0) × (0, 60, 0) = 0.
        EXPECT_NEAR(ball.force[0].linear.y(), -9.81 + 60.0, 1e-12);
        EXPECT_NEAR(ball.force[0].linear.x(), 0.0, 1e-12);
        EXPECT_NEAR(ball.force[0].angular.norm(), 0.0, 1e-12);
        // Implicit step, no linear/angular coupling (R·L ∥ n): Δv_y = h (f_y)/(m + h² ks).
        EXPECT_NEAR(ball.velocity[0].linear.y(), 0.01 * 50.19 / 1.01, 1e-12);
        EXPECT_NEAR(ball.velocity[0].angular.norm(), 0.0, 1e-12);

        // Settle from y = 1.45 (always in contact): energy never increases (backward Euler on the
        // linear lagged system), x/z momentum and spin stay 0, rest at ks·pen = m·g.
        ball.position[0].center = Vec3(0.2, 1.45, 0.3);
        ball.velocity[0] = RigidDeriv{};
        auto energy = [&] {
            const double y = ball.position[0].center.y();
            const double pen = std::max(0.0, 1.5 - y);
            const double vy = ball.velocity[0].linear.y();
            return 0.5 * vy * vy + 9.81 * y + 0.5 * 100.0 * pen * pen;
        };
        double e_prev = energy();
        for (int k = 0; k < 1500; ++k) {
            sim.step();
            const double en = energy();
            EXPECT_LE(en, e_prev + 1e-12) << "step " << k + 1;
            e_prev = en;
            ASSERT_EQ(pipeline.graph_entries().size(), 1u) << "step " << k + 1;
            EXPECT_NEAR(ball.velocity[0].linear.x(), 0.0, 1e-12);
            EXPECT_NEAR(ball.velocity[0].linear.z(), 0.0, 1e-12);
            EXPECT_NEAR(ball.velocity[0].angular.norm(), 0.0, 1e-12);
        }
        // Backward Euler damps the oscillation (ω = √(ks/m) = 10 rad/s) by 1/√(1 + h²ω²) per
        // step: amplitude 0.0481 m (0.481 m/s) times that factor to the 1500th power.
        const double decay = std::pow(1.0 / std::sqrt(1.0 + 0.01), 1500);
        EXPECT_NEAR(ball.position[0].center.y(), 1.5 - 0.0981, 1.05 * 0.0481 * decay);
        EXPECT_NEAR(ball.velocity[0].linear.y(), 0.0, 1.05 * 0.481 * decay);
    }
    // The pipeline's destructor removed what it added.
    int nodes = 0, ffs = 0;
    count(sim.root(), nodes, ffs);
    EXPECT_EQ(nodes, 3);
    EXPECT_EQ(ffs, 0);
    EXPECT_TRUE(sim.contact_stages().empty());
}

TEST(ContactPipeline, SpheresCarriedByARigidMappingGetTheTorque) {
    // Mapper chain: a Vec3 SphereModel (identity contact mapper) on two points mapped by a
    // RigidMapping from a Rigid3 body, local (±0.5, 0, 0), body rotated 30° about z at
    // c = (0, 0.9, 0): point 1 is at c − (0.433, 0.25, 0), y = 0.65, pen = 1 − 0.65 = 0.35,
    // F = 35 N; point 0 (y = 1.15) is detected but inactive. Torque on the body about its centre:
    // τ = r × F, r = (−0.5 cos30°, −0.25, 0): τ_z = −0.5 cos30°·35.
    Simulation sim;
    sim.root().set_gravity(Vec3(0, -9.81, 0));
    sim.root().set_dt(0.01);
    Floor floor(sim.root(), false);
    Node& body = sim.root().add_child("body");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    solver.cg.tolerance = 1e-14;
    solver.cg.threshold = 1e-30;
    auto& frame = body.add_state<Rigid3Types>("frame");
    const double th = std::numbers::pi / 6.0;
    RigidFrame f0;
    f0.center = Vec3(0.0, 0.9, 0.0);
    f0.orientation = Quat(Eigen::AngleAxisd(th, Vec3::UnitZ()));
    frame.position = {f0};
    auto& mass = body.set_mass<UniformMass<Rigid3Types>>(frame);
    mass.set_vertex_mass(2.0);
    mass.set_inertia(Mat3::Identity() * 0.125);
    Node& pts = body.add_child("spheres");
    auto& sph = pts.add_state<Vec3Types>("spheres");
    pts.set_mapping<RigidMapping>(frame, sph).set_points({Vec3(0.5, 0, 0), Vec3(-0.5, 0, 0)});
    CollisionModelParams p;
    p.name = "spheres";
    p.contact_stiffness = 10.0;
    SphereModel model(sph, 0.5, {}, p);
    ContactPipeline pipeline(sim);
    pipeline.add_model(*floor.model, *floor.node);
    pipeline.add_model(model, pts);
    sim.init();
    sim.step();
    ASSERT_EQ(pipeline.graph_entries().size(), 1u);
    const ContactGraphEntry& e = pipeline.graph_entries()[0];
    EXPECT_EQ(e.host, &pts);
    EXPECT_EQ(e.point_states[1], &sph);
    ASSERT_EQ(e.contact->force_field().size(), 2u);
    const double F = 100.0 * (1.0 - (0.9 - 0.5 * std::sin(th)));
    EXPECT_NEAR(F, 35.0, 1e-12);
    // Body force at the start of step 1: gravity + F up; torque closed form.
    EXPECT_NEAR(frame.force[0].linear.y(), -2.0 * 9.81 + F, 1e-11);
    EXPECT_NEAR(frame.force[0].linear.x(), 0.0, 1e-12);
    EXPECT_NEAR(frame.force[0].angular.z(), -0.5 * std::cos(th) * F, 1e-11);
    EXPECT_NEAR(frame.force[0].angular.x(), 0.0, 1e-12);
    EXPECT_NEAR(frame.force[0].angular.y(), 0.0, 1e-12);
    // Same torque by central finite differences of the contact energy under a rotation about z
    // (normal, dist and ks frozen): E(φ) = ½ ks pen(φ)², τ_z = −dE/dφ.
    auto contact_energy = [&](double phi) {
        const double pen = 1.0 - (0.9 - 0.5 * std::sin(th + phi));
        return 0.5 * 100.0 * std::max(0.0, pen) * std::max(0.0, pen);
    };
    const double eps = 1e-6;
    EXPECT_NEAR(frame.force[0].angular.z(), -(contact_energy(eps) - contact_energy(-eps)) / (2 * eps), 1e-6);
    // The assembled matrix (Jacobian triplets of the contact mappings through the RigidMapping)
    // equals the matrix-free operator M + k·K at the step's active set.
    {
        SubtreeSystem sys(body);
        ASSERT_EQ(sys.size(), 6);
        const Eigen::VectorXd dx = (Eigen::VectorXd(6) << 0.3, -0.7, 0.2, 0.5, -0.1, 0.9).finished();
        Eigen::VectorXd free;
        sys.apply_mbk(dx, free, 1.0, 0.0, -1e-4, false);
        const Eigen::VectorXd assembled = sys.assemble(1.0, -1e-4) * dx;
        EXPECT_LT((free - assembled).norm(), 1e-12 * free.norm());
        // K ≠ 0: the contact stiffness enters (the angular/linear coupling of the lower point).
        Eigen::VectorXd mdx;
        sys.apply_mbk(dx, mdx, 1.0, 0.0, 0.0, false);
        EXPECT_GT((free - mdx).norm(), 1e-4);
    }
    // The body starts turning the right way (clockwise, ω_z < 0) and rising.
    EXPECT_LT(frame.velocity[0].angular.z(), 0.0);
    EXPECT_GT(frame.velocity[0].linear.y(), 0.0);
    // Linear momentum balance of the step: m Δv = h f at the end-of-step state of the implicit
    // system is not closed form; check it against the explicit bound instead: 0 < Δv_y < h f_y / m.
    EXPECT_LT(frame.velocity[0].linear.y(), 0.01 * (-2.0 * 9.81 + F) / 2.0);
}

/// Worked example C (MinProximity Sphere–Sphere, r = 1, centres 2.2 apart, A = 1, C = 0.5:
/// dist 2.5, ks 40, pen 0.3, 12 N) between two simulated spheres of mass 1, no gravity.
/// `common_solver`: one EulerImplicit at the root (the contact, stored at the root, is inside it →
/// implicit); else one solver per sphere and none at the root (→ explicit).
void two_spheres_step(bool common_solver, double& v1, double& v2) {
    Simulation sim;
    sim.root().set_gravity(Vec3::Zero());
    sim.root().set_dt(0.01);
    if (common_solver) sim.root().set_ode_solver<EulerImplicitSolver>().cg.tolerance = 1e-14;
    std::vector<std::unique_ptr<SphereModel>> models;
    std::vector<Vec3Object*> states;
    for (int i = 0; i < 2; ++i) {
        Node& n = sim.root().add_child(i == 0 ? "a" : "b");
        if (!common_solver) n.set_ode_solver<EulerImplicitSolver>().cg.tolerance = 1e-14;
        auto& x = n.add_state<Vec3Types>(i == 0 ? "a" : "b");
        x.position = {Vec3(2.2 * i, 0, 0)};
        n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(1.0);
        CollisionModelParams p;
        p.name = i == 0 ? "a" : "b";
        models.push_back(std::make_unique<SphereModel>(x, 1.0, std::vector<double>{}, p));
        states.push_back(&x);
    }
    ContactPipeline pipeline(sim, IntersectionParams::min_proximity());
    pipeline.add_model(*models[0], *sim.root().children()[0]);
    pipeline.add_model(*models[1], *sim.root().children()[1]);
    sim.init();
    sim.step();
    ASSERT_EQ(pipeline.graph_entries().size(), 1u);
    const PenaltyContact& c = pipeline.graph_entries()[0].contact->force_field().contacts()[0];
    EXPECT_DOUBLE_EQ(c.dist, 2.5);
    EXPECT_DOUBLE_EQ(c.ks, 40.0);
    EXPECT_NEAR(c.pen, 0.3, 1e-12);
    EXPECT_EQ(pipeline.graph_entries()[0].host, &sim.root());  // both simulated → pipeline node
    v1 = states[0]->velocity[0].x();
    v2 = states[1]->velocity[0].x();
    EXPECT_DOUBLE_EQ(states[0]->velocity[0].y(), 0.0);
}

TEST(ContactPipeline, TwoSimulatedModelsContactAtPipelineNodeImplicitOrExplicit) {
    double v1 = 0, v2 = 0;
    two_spheres_step(/*common_solver=*/false, v1, v2);
    EXPECT_NEAR(v2, 0.12, 1e-14);  // explicit: Δv = h·f/m
    EXPECT_NEAR(v1, -0.12, 1e-14);
    two_spheres_step(/*common_solver=*/true, v1, v2);
    // implicit: (m + 2h²ks)·Δv = h·ks·pen for the symmetric pair
    EXPECT_NEAR(v2, 0.12 / (1.0 + 2.0 * 1e-4 * 40.0), 1e-14);
    EXPECT_NEAR(v1, -0.12 / (1.0 + 2.0 * 1e-4 * 40.0), 1e-14);
}

TEST(ContactPipeline, PairsTheMethodDoesNotDetectAreReportedNotSilentlySkipped) {
    // MinProximity registers Triangle–Triangle as ignored (spec §5.2): the pair is reported once
    Simulation sim;
    Floor a(sim.root(), true);
    Floor b(sim.root(), true);
    b.model->params().name = "lid";
    ContactPipeline pipeline(sim, IntersectionParams::min_proximity());
    pipeline.add_model(*a.model, *a.node);
    pipeline.add_model(*b.model, *b.node);
    pipeline.update();
    ASSERT_EQ(pipeline.skipped_pairs().size(), 1u);
    EXPECT_EQ(pipeline.skipped_pairs()[0],
              "ContactPipeline: models 'lid' (Triangle) and 'floor' (Triangle): pair ignored for this "
              "intersection method, no contact");
    EXPECT_TRUE(pipeline.detections().empty());
    pipeline.update();
    EXPECT_EQ(pipeline.skipped_pairs().size(), 1u);  // once per pair, not once per step
}

TEST(ContactPipeline, BadInputThrows) {
    Simulation sim;
    Floor floor(sim.root(), false);
    Node& other = sim.root().add_child("other");
    other.add_state<Vec3Types>("other");
    ContactPipeline pipeline(sim);
    EXPECT_THROW(pipeline.add_model(*floor.model, other), std::invalid_argument);  // wrong node
    pipeline.add_model(*floor.model, *floor.node);
    EXPECT_THROW(pipeline.add_model(*floor.model, *floor.node), std::invalid_argument);  // twice
    {
        // a second pipeline is the simulation's second contact stage, gone with it
        const ContactPipeline second(sim);
        ASSERT_EQ(sim.contact_stages().size(), 2u);
        EXPECT_EQ(sim.contact_stages()[1], &second);
    }
    EXPECT_EQ(sim.contact_stages().size(), 1u);
    Node& rigid = sim.root().add_child("rigid");
    auto& rs = rigid.add_state<Rigid3Types>("rigid");
    RigidSphereModel rsm(rs, 0.5);
    EXPECT_THROW(pipeline.add_model(rsm, other), std::invalid_argument);  // Vec3 node for Rigid3
    try {
        pipeline.add_model(rsm, *floor.node);
        ADD_FAILURE() << "no throw";
    } catch (const std::invalid_argument& ex) {
        EXPECT_NE(std::string(ex.what()).find("floor"), std::string::npos) << ex.what();
    }
}

}  // namespace
}  // namespace penalty
