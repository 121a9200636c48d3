// Newton iterations of EulerImplicitSolver with contact-geometry updates
// (ContactPipeline::attach_newton / update_geometry, beyond SOFA): stiff drop on a plane (closed-form
// backward-Euler step, resting penetration m·g/ks, no energy gain, iteration counts), curved contact
// (the end-of-step normal), contacts appearing / disappearing between iterates, contact ages
// advancing once per step, friction history, errors.

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/spheres_on_floor.hpp"
#include "penalty_test/static_floor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

namespace penalty {
namespace {

using namespace test::stiff_drop;

/// Static two-triangle floor at y = 0 (normal +y), ±10 m, contact stiffness k (N/m, physical law).
struct FloorOfStiffness : test::StaticFloor {
    FloorOfStiffness(Node& parent, double k) : StaticFloor(parent, test::floor_params(k)) {}
};

// ---- stiff drop on a plane ---------------------------------------------------------------------
// One sphere of the stiff drop (spheres_on_floor.hpp: r = 0.1 m, m = 1 kg, ks = 1e5 N/m, C = 0.005 m
// so dist = 0.105 m, dt = 0.01 s, ω·h = 3.2), A = 0.1 m. Dropped from y0 = 0.15 m at v0 = −8 m/s:
// the pair is detected at the start of step 1 (gap 0.05 < A) with pen = −0.045 (inactive), so
// SOFA's linearised step ignores the spring and falls 8 cm.
constexpr double kY0 = 0.15, kV0 = -8.0;

struct Drop : test::SpheresOnFloor {
    Drop(bool newton, bool geometry, double y0 = kY0, double v0 = kV0, double alarm = 0.1)
        : SpheresOnFloor(setup("sphere", {Vec3(0.2, y0, 0.3)}, {Vec3(0, v0, 0)}, alarm)) {
        configure_solver(*this, newton, geometry);
    }

    [[nodiscard]] double y() const { return spheres->position[0].y(); }
    [[nodiscard]] double vy() const { return spheres->velocity[0].y(); }
    /// Total energy (J): ½·m·v² + m·g·y + ½·ks·max(0, dist − y)² (the plane's closed form).
    [[nodiscard]] double energy() const {
        const double pen = std::max(0.0, kDist - y());
        return 0.5 * kMass * spheres->velocity[0].squaredNorm() + kMass * kG * y() + 0.5 * kKs * pen * pen;
    }
};

/// Backward-Euler step with the spring active at the end: m (v1 − v0) = h (−m g + ks (dist − y1)),
/// y1 = y0 + h v1  ⇒  v1 = (m v0 − h m g + h ks (dist − y0)) / (m + h² ks).
double be_velocity(double y0, double v0) {
    return (kMass * v0 - kH * kMass * kG + kH * kKs * (kDist - y0)) / (kMass + kH * kH * kKs);
}

TEST(NewtonContact, StiffDropLinearisedStepOvershootsNewtonSolvesBackwardEuler) {
    Drop lin(false, false);
    Drop nwt(true, true);
    lin.sim.init();
    nwt.sim.init();
    const double e0 = lin.energy();
    EXPECT_NEAR(e0, 0.5 * 64.0 + kG * 0.15, 1e-12);
    lin.sim.step();
    nwt.sim.step();
    // Linearised (SOFA): the spring was inactive at x_n, so the step is free flight.
    const double v_free = kV0 - kH * kG;
    EXPECT_NEAR(lin.vy(), v_free, 1e-12);
    EXPECT_NEAR(lin.y(), kY0 + kH * v_free, 1e-12);
    const double pen_lin = kDist - lin.y();
    EXPECT_NEAR(pen_lin, 0.035981, 1e-9);  // 36 mm, 367 × the resting m·g/ks
    EXPECT_GT(lin.energy(), e0 + 30.0);    // ½·ks·pen² = 64.7 J stored: energy gain
    // Newton with geometry updates: the exact backward-Euler step with the spring active.
    const double v1 = be_velocity(kY0, kV0);
    EXPECT_NEAR(v1, -53.0981 / 11.0, 1e-12);
    EXPECT_NEAR(nwt.vy(), v1, 1e-9);
    EXPECT_NEAR(nwt.y(), kY0 + kH * v1, 1e-11);
    EXPECT_GT(kDist - nwt.y(), 0.0);     // the active set is consistent
    EXPECT_LT(kDist - nwt.y(), 0.0034);  // 3.3 mm instead of 36 mm
    EXPECT_TRUE(nwt.solver->last_newton_converged());
    EXPECT_LE(nwt.solver->last_newton_residual(), 1e-10);
    // Iterate 0 (x_n: spring inactive, free fall), 1 (spring active: one exact Newton step),
    // 2 (residual at round-off).
    EXPECT_EQ(nwt.solver->last_newton_iterations(), 3);
    EXPECT_EQ(nwt.pipeline->geometry_updates_this_step(), 3);
    EXPECT_LE(nwt.energy(), e0);
}

TEST(NewtonContact, StiffDropSettlesAtRestingPenetrationWithoutEnergyGain) {
    Drop nwt(true, true);
    nwt.sim.init();
    double e_prev = nwt.energy();
    int max_iterations = 0;
    for (int k = 0; k < 200; ++k) {
        nwt.sim.step();
        ASSERT_TRUE(nwt.solver->last_newton_converged()) << "step " << k + 1;
        EXPECT_LE(nwt.solver->last_newton_residual(), 1e-10);
        max_iterations = std::max(max_iterations, nwt.solver->last_newton_iterations());
        // Backward Euler on a convex potential (gravity + one-sided spring) never gains energy.
        const double e = nwt.energy();
        EXPECT_LE(e, e_prev + 1e-9) << "step " << k + 1;
        e_prev = e;
        EXPECT_GT(nwt.y(), kRadius - 0.004) << "step " << k + 1;  // never deeper than step 1
    }
    EXPECT_GE(max_iterations, 2);
    EXPECT_LE(max_iterations, 4);
    // Rest: ks·pen = m·g  ⇒  pen = m·g/ks = 9.81e-5 m.
    EXPECT_NEAR(kDist - nwt.y(), kMass * kG / kKs, 1e-9);
    EXPECT_NEAR(nwt.vy(), 0.0, 1e-9);
    // One contact, tracked since step 1: age = steps − 1 (the iterates never advance it).
    const auto& c = nwt.pipeline->graph_entries().at(0).contact->force_field().contacts();
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].age, 199);

    // SOFA's linearised step from the same start bounces and also ends at rest, but its first
    // step stored 35 J more than the drop had.
    Drop lin(false, false);
    lin.sim.init();
    const double e0 = lin.energy();
    double e_max = e0;
    for (int k = 0; k < 200; ++k) {
        lin.sim.step();
        e_max = std::max(e_max, lin.energy());
    }
    EXPECT_GT(e_max - e0, 30.0);
}

TEST(NewtonContact, NewtonWithoutGeometryUpdateMatchesOnAPlaneButNeedsALivePair) {
    // On a plane the contact's normal and point do not change, so Newton re-evaluating the frozen
    // spring (no geometry update) reaches the same step — as long as the pair exists at x_n.
    Drop frozen(true, false);
    frozen.sim.init();
    frozen.sim.step();
    EXPECT_NEAR(frozen.vy(), be_velocity(kY0, kV0), 1e-9);
    // Out of the alarm zone at x_n (gap 0.1 > A = 0.02): no pair, nothing to re-detect; the
    // pair that would appear mid-solve is created at the next step's update().
    Drop far(true, true, kY0 + 0.05, kV0 - 5.0, 0.02);
    far.sim.init();
    far.sim.step();
    EXPECT_TRUE(far.pipeline->graph_entries().empty());
    EXPECT_NEAR(far.vy(), kV0 - 5.0 - kH * kG, 1e-12);  // free flight
    far.sim.step();
    EXPECT_EQ(far.pipeline->graph_entries().size(), 1u);
}

// ---- curved contact: the end-of-step normal -----------------------------------------------------
TEST(NewtonContact, CurvedContactUsesTheEndOfStepNormal) {
    // A small sphere (r = 0.1, m = 1) hits a static sphere (R = 1 at the origin) off-axis while
    // moving sideways. Backward Euler with the contact at the end of the step:
    //   m (v1 − v0) = h (m g + ks·pen(x1)·n(x1)),  n = (x1 − c)/|x1 − c|,  pen = C + R + r − |x1 − c|.
    // Newton with geometry updates satisfies it with n(x1); without updates the normal stays n(x_n).
    auto run = [](bool geometry, Vec3& x1, Vec3& v1, Vec3& x0, Vec3& v0, bool& converged) {
        Simulation sim;
        sim.root().set_gravity(Vec3(0, -kG, 0));
        sim.root().set_dt(kH);
        Node& ball_node = sim.root().add_child("ball");
        auto& ball_state = ball_node.add_state<Vec3Types>("ball");
        ball_state.position = {Vec3(0, 0, 0)};
        CollisionModelParams pb;
        pb.name = "ball";
        pb.simulated = false;
        pb.moving = false;
        pb.contact_stiffness = 2.0 * kKs;
        SphereModel ball(ball_state, 1.0, {}, pb);
        Node& body = sim.root().add_child("body");
        auto& solver = body.set_ode_solver<EulerImplicitSolver>();
        tight_cg(solver);
        solver.newton.enabled = true;
        solver.newton.max_iterations = 30;
        auto& x = body.add_state<Vec3Types>("sphere");
        const double a = 0.6;  // polar angle of the start position (rad)
        x0 = (1.0 + kRadius + 0.03) * Vec3(std::sin(a), std::cos(a), 0.0);
        v0 = Vec3(1.0, -6.0, 0.0);
        x.position = {x0};
        x.velocity = {v0};
        body.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(kMass);
        CollisionModelParams ps;
        ps.name = "sphere";
        ps.contact_stiffness = 2.0 * kKs;
        SphereModel sphere(x, kRadius, {}, ps);
        ContactPipeline pipeline(sim, proximity(0.2, kC), physical_response());
        pipeline.add_model(ball, ball_node);
        pipeline.add_model(sphere, body);
        if (geometry) pipeline.attach_newton(solver);
        sim.init();
        sim.step();
        x1 = x.position[0];
        v1 = x.velocity[0];
        converged = solver.last_newton_converged();
    };
    // Both sides are identity mappers (the contact points are the centres), so the spring is
    // pen = dist − (x1 − c)·n with dist = C + R + r and the normal n of the detection.
    auto residual = [](const Vec3& x1, const Vec3& v1, const Vec3& v0, const Vec3& normal) {
        const double pen = kC + 1.0 + kRadius - x1.dot(normal);
        const Vec3 f = Vec3(0, -kMass * kG, 0) + (pen > 0 ? kKs * pen : 0.0) * normal;
        return (kMass * (v1 - v0) - kH * f).norm();
    };
    Vec3 x1, v1, x0, v0;
    bool converged = false;
    run(true, x1, v1, x0, v0, converged);
    EXPECT_TRUE(converged);
    EXPECT_NEAR((x1 - x0 - kH * v1).norm(), 0.0, 1e-14);  // x1 = x0 + h·v1
    EXPECT_GT(kC + 1.0 + kRadius - x1.norm(), 0.0);       // in contact at the end
    EXPECT_LT(residual(x1, v1, v0, x1.normalized()), 1e-8);
    const double with_updates = residual(x1, v1, v0, x0.normalized());

    Vec3 y1, w1;
    run(false, y1, w1, x0, v0, converged);
    EXPECT_TRUE(converged);
    // Frozen normal n(x_n): the solver solves the equation with n(x_n), which violates the
    // end-of-step one, and the end states differ by millimetres.
    EXPECT_GT(residual(y1, w1, v0, y1.normalized()), 1e-3);
    EXPECT_LT(residual(y1, w1, v0, x0.normalized()), 1e-8);
    EXPECT_GT((y1 - x1).norm(), 1e-3);
    EXPECT_GT(with_updates, 1e-3);  // and the updated solution does not satisfy the frozen one
}

// ---- contacts appearing / disappearing between iterates ----------------------------------------
TEST(NewtonContact, ContactsAppearAndDisappearBetweenIterates) {
    // Floor + one body of three free spheres (model "trio") + a second body "leaver" + a third
    // body "newcomer". At x_n: sphere 0 of the trio in contact, moving up fast (leaves the alarm
    // zone A = 0.02 within the step); spheres 1 and 2 above the alarm zone falling fast (enter
    // it). The leaver is in the alarm zone and leaves; the newcomer is out of it and enters.
    Simulation sim;
    sim.root().set_gravity(Vec3(0, -kG, 0));
    sim.root().set_dt(kH);
    FloorOfStiffness floor(sim.root(), 2.0 * kKs);
    Node& bodies = sim.root().add_child("bodies");
    auto& solver = bodies.set_ode_solver<EulerImplicitSolver>();
    tight_cg(solver);
    solver.newton.enabled = true;
    solver.newton.max_iterations = 20;
    auto add_body = [&](const char* name, std::vector<Vec3> x, std::vector<Vec3> v) -> std::pair<Node*, Vec3Object*> {
        Node& n = bodies.add_child(name);
        auto& s = n.add_state<Vec3Types>(name);
        s.position = std::move(x);
        s.velocity = std::move(v);
        n.set_mass<UniformMass<Vec3Types>>(s).set_vertex_mass(kMass);
        return {&n, &s};
    };
    const double r = kRadius;
    auto [trio_node, trio] = add_body("trio", {Vec3(0, r + 0.001, 0), Vec3(1, r + 0.03, 0), Vec3(2, r + 0.04, 0)},
                                      {Vec3(0, 5.0, 0), Vec3(0, -6.0, 0), Vec3(0, -7.0, 0)});
    auto [leaver_node, leaver] = add_body("leaver", {Vec3(3, r + 0.01, 0)}, {Vec3(0, 4.0, 0)});
    auto [newcomer_node, newcomer] = add_body("newcomer", {Vec3(4, r + 0.05, 0)}, {Vec3(0, -6.0, 0)});
    CollisionModelParams p;
    p.contact_stiffness = 2.0 * kKs;
    p.name = "trio";
    SphereModel trio_model(*trio, r, {}, p);
    p.name = "leaver";
    SphereModel leaver_model(*leaver, r, {}, p);
    p.name = "newcomer";
    SphereModel newcomer_model(*newcomer, r, {}, p);
    // Spheres of different bodies never meet here (2 m apart in x); only floor pairs matter.
    ContactPipeline pipeline(sim, proximity(0.02, kC), physical_response());
    pipeline.add_model(*floor.model, *floor.node);
    pipeline.add_model(trio_model, *trio_node);
    pipeline.add_model(leaver_model, *leaver_node);
    pipeline.add_model(newcomer_model, *newcomer_node);
    pipeline.attach_newton(solver);
    struct Snapshot {
        std::size_t trio, leaver, trio_points;
    };
    std::vector<Snapshot> iterates;
    bool recording = true;
    auto inner = solver.newton.update_geometry;
    solver.newton.update_geometry = [&] {
        inner();
        if (!recording) return;
        const ContactGraphEntry* t = pipeline.find(*floor.model, trio_model);
        const ContactGraphEntry* l = pipeline.find(*floor.model, leaver_model);
        ASSERT_NE(t, nullptr);
        ASSERT_NE(l, nullptr);
        iterates.push_back(
            {t->contact->force_field().size(), l->contact->force_field().size(), t->point_states[0]->position.size()});
        EXPECT_EQ(pipeline.find(*floor.model, newcomer_model), nullptr);  // never created mid-solve
    };
    sim.init();
    int nodes_before = 0;
    const auto count_nodes = [](const auto& self, const Node& n) -> int {
        int c = 1;
        for (const auto& ch : n.children()) c += self(self, *ch);
        return c;
    };
    sim.step();
    nodes_before = count_nodes(count_nodes, sim.root());
    ASSERT_GE(iterates.size(), 3u);
    // x_n: the trio has one contact (sphere 0), the leaver one.
    EXPECT_EQ(iterates[0].trio, 1u);
    EXPECT_EQ(iterates[0].leaver, 1u);
    // Later iterates: sphere 0 gone, spheres 1 and 2 in; the leaver's pair is empty (kept alive
    // until the next update), its contact-point state resized to 0.
    EXPECT_EQ(iterates.back().trio, 2u);
    EXPECT_EQ(iterates.back().trio_points, 2u);
    EXPECT_EQ(iterates.back().leaver, 0u);
    EXPECT_TRUE(solver.last_newton_converged());
    // Spheres 1 and 2 were stopped by the springs in the step: backward Euler with the spring
    // active at the end (closed form per sphere: independent 1-DOF problems along y).
    for (int i = 1; i <= 2; ++i) {
        const double y0 = i == 1 ? r + 0.03 : r + 0.04;
        const double v0 = i == 1 ? -6.0 : -7.0;
        EXPECT_NEAR(trio->velocity[std::size_t(i)].y(), be_velocity(y0, v0), 1e-9) << "sphere " << i;
    }
    // Sphere 0 and the leaver fly freely; the newcomer fell through the alarm zone unseen.
    EXPECT_NEAR(trio->velocity[0].y(), 5.0 - kH * kG, 1e-12);
    EXPECT_NEAR(leaver->velocity[0].y(), 4.0 - kH * kG, 1e-12);
    EXPECT_NEAR(newcomer->velocity[0].y(), -6.0 - kH * kG, 1e-12);
    // The graph did not change during the solve; the next update() creates the newcomer's pair and
    // destroys the leaver's, and the trio's two contacts are one step old.
    const ContactGraphEntry* t = pipeline.find(*floor.model, trio_model);
    ASSERT_NE(t, nullptr);
    for (const PenaltyContact& c : t->contact->force_field().contacts()) EXPECT_EQ(c.age, 0);
    recording = false;
    sim.step();
    EXPECT_EQ(pipeline.find(*floor.model, leaver_model), nullptr);
    EXPECT_NE(pipeline.find(*floor.model, newcomer_model), nullptr);
    t = pipeline.find(*floor.model, trio_model);
    ASSERT_NE(t, nullptr);
    ASSERT_EQ(t->contact->force_field().size(), 2u);
    for (const PenaltyContact& c : t->contact->force_field().contacts()) EXPECT_EQ(c.age, 1);
    // Graph after step 2: root, floor, bodies, trio, leaver, newcomer + one barycentric
    // contact-point node under the floor per live pair (trio, newcomer); after step 1 it had the
    // trio's and the leaver's.
    EXPECT_EQ(nodes_before, 8);
    EXPECT_EQ(count_nodes(count_nodes, sim.root()), 8);
    for (int k = 0; k < 30; ++k) sim.step();
    for (const Vec3& x : trio->position) EXPECT_TRUE(x.allFinite());
}

// ---- contact tracking and friction across iterates ---------------------------------------------
TEST(NewtonContact, FrictionHistoryAndDissipationCountedOncePerStep) {
    // A sphere sliding on the floor with Coulomb friction (mu = 0.4 summed from both models):
    // Newton with geometry updates re-detects at each iterate, but the ages, the tangential
    // spring history and the energy dissipated by sliding advance once per step. Sliding
    // (kinetic) friction on a flat floor: v_x decreases by mu·g·h per step while sliding, exactly
    // as backward Euler with the dynamic cap mu·ks·pen gives once the normal force is m·g.
    PenaltyParameters friction;
    friction.friction = FrictionModel::coulomb;
    friction.time_step = kH;
    Simulation sim;
    sim.root().set_gravity(Vec3(0, -kG, 0));
    sim.root().set_dt(kH);
    FloorOfStiffness floor(sim.root(), 2.0 * kKs);
    floor.model->params().contact_friction = 0.2;
    Node& body = sim.root().add_child("body");
    auto& solver = body.set_ode_solver<EulerImplicitSolver>();
    tight_cg(solver);
    solver.newton.enabled = true;
    solver.newton.max_iterations = 30;
    solver.newton.tolerance = 1e-9;
    auto& x = body.add_state<Vec3Types>("sphere");
    x.position = {Vec3(0, kDist - kMass * kG / kKs, 0)};  // at the resting penetration
    x.velocity = {Vec3(2.0, 0, 0)};
    body.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(kMass);
    CollisionModelParams p;
    p.name = "sphere";
    p.contact_stiffness = 2.0 * kKs;
    p.contact_friction = 0.2;
    SphereModel sphere(x, kRadius, {}, p);
    ContactPipeline pipeline(sim, proximity(0.02, kC), physical_response(friction));
    pipeline.add_model(*floor.model, *floor.node);
    pipeline.add_model(sphere, body);
    pipeline.attach_newton(solver);
    sim.init();
    double dissipated_prev = 0.0;
    double ke_prev = 0.5 * kMass * 4.0;
    for (int k = 0; k < 20; ++k) {
        const double vx0 = x.velocity[0].x();
        sim.step();
        EXPECT_TRUE(solver.last_newton_converged()) << "step " << k + 1;
        const auto& e = pipeline.graph_entries().at(0);
        const PenaltyForceField& ff = e.contact->force_field();
        ASSERT_EQ(ff.size(), 1u);
        EXPECT_EQ(ff.contacts()[0].age, k) << "step " << k + 1;
        EXPECT_EQ(ff.contacts()[0].friction_state, FrictionState::sliding) << "step " << k + 1;
        // Kinetic friction: Δv_x = −mu·g·h (normal force m·g at rest in y).
        EXPECT_NEAR(x.velocity[0].x() - vx0, -0.4 * kG * kH, 1e-6) << "step " << k + 1;
        // Dissipation counted once per step, at the start-of-step anchor. Step 1: a new contact
        // has no spring, nothing slips at its first evaluation. Step 2: the spring is the motion
        // of step 1, ξ = h·v_x(1), cut back to the cap kt·|ξ| = mu·f_n: the slip dissipates
        // mu·f_n·(h·v_x − mu·f_n/kt), the rest stays stored. From step 3 on the spring starts at
        // the cap, is stretched by h·v_x(n) and cut back: mu·m·g·h·v_x(n). (The step's own
        // motion, seen by the Newton iterates, is carried once: by the next step's h·P·v.)
        const double cap = 0.4 * kMass * kG;
        const double kt = ff.parameters().tangential_stiffness_ratio * ff.contacts()[0].ks;
        const double expected = k == 0 ? 0.0 : k == 1 ? cap * (kH * vx0 - cap / kt) : cap * kH * vx0;
        const double dissipated = ff.dissipated_by_sliding() - dissipated_prev;
        EXPECT_NEAR(dissipated, expected, 1e-9) << "step " << k + 1;
        dissipated_prev = ff.dissipated_by_sliding();
        const double ke = 0.5 * kMass * x.velocity[0].squaredNorm();
        EXPECT_LT(ke, ke_prev);
        ke_prev = ke;
    }
}

TEST(NewtonContact, AttachingMidRunKeepsTheContactAges) {
    // Linearised steps first (SOFA), then attach_newton: the live pair's outputs come from the
    // last update, so tracking continues (age = steps − 1) instead of restarting.
    Drop d(false, false, kDist - kMass * kG / kKs, 0.0);  // at rest on the floor
    d.sim.init();
    for (int k = 0; k < 5; ++k) d.sim.step();
    const auto age = [&] { return d.pipeline->graph_entries().at(0).contact->force_field().contacts()[0].age; };
    EXPECT_EQ(age(), 4);
    d.solver->newton.enabled = true;
    d.pipeline->attach_newton(*d.solver);
    for (int k = 0; k < 5; ++k) {
        d.sim.step();
        EXPECT_EQ(age(), 5 + k);
        EXPECT_GE(d.pipeline->geometry_updates_this_step(), 2);
        EXPECT_TRUE(d.solver->last_newton_converged());
        EXPECT_NEAR(kDist - d.y(), kMass * kG / kKs, 1e-12);  // stays at rest
    }
}

TEST(NewtonContact, ErrorsAndHooks) {
    Drop d(true, false);
    // update_geometry without attach_newton: the pre-step state was not kept.
    EXPECT_THROW(d.pipeline->update_geometry(), std::invalid_argument);
    // attach_newton on a solver outside the simulation.
    EulerImplicitSolver stray;
    EXPECT_THROW(d.pipeline->attach_newton(stray), std::invalid_argument);
    d.pipeline->attach_newton(*d.solver);
    EXPECT_TRUE(static_cast<bool>(d.solver->newton.update_geometry));
    // Attached but no update() since: no pre-step state yet.
    EXPECT_THROW(d.pipeline->update_geometry(), std::invalid_argument);
    d.sim.step();
    EXPECT_NO_THROW(d.pipeline->update_geometry());
    // The destructor detaches the solver.
    d.pipeline.reset();
    EXPECT_FALSE(static_cast<bool>(d.solver->newton.update_geometry));
}

}  // namespace
}  // namespace penalty
