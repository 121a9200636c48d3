#pragma once
// Spheres dropped on the static floor (static_floor.hpp) through a ContactPipeline: SOFA's worked
// example E (the defaults of SpheresOnFloorSetup) and the stiff drop of the Newton tests and
// benchmark (namespace stiff_drop). Header-only; include it only from suites that link
// penalty::simulation (tests/simulation, bench).
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/static_floor.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace penalty::test {

/// What SpheresOnFloor builds; the defaults are worked example E (one sphere, vertexMass 1,
/// radius 0.5, k 10 on both models, NewProximity, the default penalty response).
struct SpheresOnFloorSetup {
    double gravity = 9.81;          ///< m/s², along −y
    double dt = 0.01;               ///< s
    double floor_stiffness = 10.0;  ///< contactStiffness of the floor model
    bool floor_simulated = false;   ///< a simulated floor moves the contact to the root (explicit)
    std::string name = "sphere";    ///< of the body node, its state and its model
    std::vector<Vec3> positions = {Vec3(0.2, 0.9, 0.3)};  ///< sphere centres (m), one DOF each
    std::vector<Vec3> velocities;                         ///< m/s (empty: at rest)
    double vertex_mass = 1.0;                             ///< kg per sphere
    double radius = 0.5;                                  ///< m
    double contact_stiffness = 10.0;                      ///< contactStiffness of the sphere model
    IntersectionParams intersection = IntersectionParams::new_proximity();
    CollisionResponse response;
};

/// The floor, then a body node under the root with an EulerImplicit solver (default options: the
/// caller sets its CG and Newton options), a Vec3 state of the sphere centres, a UniformMass and
/// a SphereModel, and one ContactPipeline with the floor registered first.
struct SpheresOnFloor {
    Simulation sim;
    StaticFloor floor;
    Node* body;
    EulerImplicitSolver* solver;
    Vec3Object* spheres;
    std::unique_ptr<SphereModel> model;
    std::unique_ptr<ContactPipeline> pipeline;

    explicit SpheresOnFloor(SpheresOnFloorSetup setup)
        : floor(sim.root(), floor_params(setup.floor_stiffness, setup.floor_simulated)) {
        sim.root().set_gravity(Vec3(0, -setup.gravity, 0));
        sim.root().set_dt(setup.dt);
        body = &sim.root().add_child(setup.name);
        solver = &body->set_ode_solver<EulerImplicitSolver>();
        spheres = &body->add_state<Vec3Types>(setup.name);
        spheres->position = setup.positions;
        spheres->velocity = setup.velocities;
        body->set_mass<UniformMass<Vec3Types>>(*spheres).set_vertex_mass(setup.vertex_mass);
        CollisionModelParams p;
        p.name = setup.name;
        p.contact_stiffness = setup.contact_stiffness;
        model = std::make_unique<SphereModel>(*spheres, setup.radius, std::vector<double>{}, p);
        pipeline = std::make_unique<ContactPipeline>(sim, setup.intersection, std::move(setup.response));
        pipeline->add_model(*floor.model, *floor.node);
        pipeline->add_model(*model, *body);
    }
    ~SpheresOnFloor() { pipeline.reset(); }  // first: it removes what it added to the graph
    SpheresOnFloor(const SpheresOnFloor&) = delete;
    SpheresOnFloor& operator=(const SpheresOnFloor&) = delete;
};

/// The stiff drop: spheres r = 0.1 m, m = 1 kg, ks = 1e5 N/m (contactStiffness 2e5 on both
/// models, physical law), C = 0.005 m so dist = C + r = 0.105 m, dt = 0.01 s (ω·h = √(ks/m)·h =
/// 3.2: stiff), CG to round-off.
namespace stiff_drop {

constexpr double kG = 9.81;             ///< gravity, m/s² along −y
constexpr double kRadius = 0.1;         ///< m
constexpr double kMass = 1.0;           ///< kg
constexpr double kKs = 1e5;             ///< spring stiffness of a contact, N/m
constexpr double kC = 0.005;            ///< contact distance, m
constexpr double kDist = kC + kRadius;  ///< rest length of a contact spring, m
constexpr double kH = 0.01;             ///< time step, s

/// NewProximity with alarm distance A and contact distance C (m).
inline IntersectionParams proximity(double alarm, double contact) {
    IntersectionParams ip = IntersectionParams::new_proximity();
    ip.alarm_distance = alarm;
    ip.contact_distance = contact;
    return ip;
}

/// Physical stiffness law: ks = k1·k2/(k1 + k2) (N/m), independent of dist.
inline CollisionResponse physical_response(const PenaltyParameters& penalty = {}) {
    ContactResponseParameters base;
    base.stiffness_law = StiffnessLaw::physical;
    base.penalty = penalty;
    return CollisionResponse(std::string(kPenaltyResponseName), "", base);
}

/// CG solved to round-off: 100 iterations, tolerance 1e-15, threshold 1e-30.
inline void tight_cg(EulerImplicitSolver& s) {
    s.cg.iterations = 100;
    s.cg.tolerance = 1e-15;
    s.cg.threshold = 1e-30;
}

/// Spheres `name` at `positions` with `velocities`, alarm distance A = `alarm` (m).
inline SpheresOnFloorSetup setup(std::string name, std::vector<Vec3> positions, std::vector<Vec3> velocities,
                                 double alarm) {
    SpheresOnFloorSetup s;
    s.gravity = kG;
    s.dt = kH;
    s.floor_stiffness = 2.0 * kKs;
    s.name = std::move(name);
    s.positions = std::move(positions);
    s.velocities = std::move(velocities);
    s.vertex_mass = kMass;
    s.radius = kRadius;
    s.contact_stiffness = 2.0 * kKs;
    s.intersection = proximity(alarm, kC);
    s.response = physical_response();
    return s;
}

/// Tight CG; Newton iterations if `newton` (20 at most, tolerance 1e-10), re-detecting the
/// contacts at each iterate if `geometry` (ContactPipeline::attach_newton).
inline void configure_solver(SpheresOnFloor& scene, bool newton, bool geometry) {
    tight_cg(*scene.solver);
    scene.solver->newton.enabled = newton;
    scene.solver->newton.max_iterations = 20;
    scene.solver->newton.tolerance = 1e-10;
    if (geometry) scene.pipeline->attach_newton(*scene.solver);
}

}  // namespace stiff_drop

}  // namespace penalty::test
