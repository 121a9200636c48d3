// Worked example E (spec §11), free fall, harmonic oscillator energy, solver subtrees (implicit vs
// explicit interaction, static side), FixedProjectiveConstraint.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace penalty {
namespace {

/// Test stand-in for a penalty contact with frozen geometry: pen = dist − (x2[0] − x1[0])·n;
/// when pen > 0: f2 += ks·pen·n, f1 −= ks·pen·n; K = −ks n nᵀ on (dx2 − dx1) (SOFA sign).
class PlanarContact final : public Vec3InteractionForceField {
public:
    PlanarContact(Vec3Object& a, Vec3Object& b, Vec3 n, double dist, double ks)
        : Vec3InteractionForceField(a, b), n_(std::move(n)), dist_(dist), ks_(ks) {}
    void add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span,
                   ConstVec3Span) override {
        const double pen = dist_ - (x2[0] - x1[0]).dot(n_);
        active_ = pen > 0;
        last_pen_ = pen;
        if (!active_) return;
        f2[0] += ks_ * pen * n_;
        f1[0] -= ks_ * pen * n_;
    }
    void add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k, double) const override {
        if (!active_) return;
        const Vec3 d = -ks_ * n_ * n_.dot(dx2[0] - dx1[0]) * k;
        df2[0] += d;
        df1[0] -= d;
    }
    void add_stiffness_triplets(TripletList& t, Index o1, Index o2, double factor) const override {
        if (!active_) return;
        const Mat3 m = -ks_ * factor * n_ * n_.transpose();
        for (Index r = 0; r < 3; ++r)
            for (Index c = 0; c < 3; ++c) {
                t.emplace_back(o2 + r, o2 + c, m(r, c));
                t.emplace_back(o1 + r, o1 + c, m(r, c));
                t.emplace_back(o2 + r, o1 + c, -m(r, c));
                t.emplace_back(o1 + r, o2 + c, -m(r, c));
            }
    }
    double last_pen_ = 0;

private:
    Vec3 n_;
    double dist_, ks_;
    bool active_ = false;
};

struct ExampleE {
    Simulation sim;
    Vec3Object* sphere = nullptr;
    Vec3Object* floor = nullptr;
    EulerImplicitSolver* solver = nullptr;
    PlanarContact* contact = nullptr;

    ExampleE(bool implicit_contact, double cg_tolerance, double cg_threshold) {
        Node& root = sim.root();
        Node& body = root.add_child("sphere");
        solver = &body.set_ode_solver<EulerImplicitSolver>();
        solver->cg.iterations = 25;
        solver->cg.tolerance = cg_tolerance;
        solver->cg.threshold = cg_threshold;
        sphere = &body.add_state<Vec3Types>("sphere");
        sphere->position = {Vec3(0.2, 0.9, 0.3)};
        body.set_mass<UniformMass<Vec3Types>>(*sphere).set_vertex_mass(1.0);
        Node& fl = root.add_child("floor");
        floor = &fl.add_state<Vec3Types>("floor");
        floor->position = {Vec3(0.2, 0.0, 0.3)};
        Node& holder = implicit_contact ? body : root;
        contact = &holder.add_force_field<PlanarContact>(*floor, *sphere, Vec3(0, 1, 0), 1.0, 100.0);
        sim.init();
    }
};

TEST(WorkedExampleE, ImplicitContactMatchesSpecTable) {
    ExampleE e(true, 1e-9, 1e-9);
    const double pen[5] = {0.1, 0.0999811881188119, 0.0999439368689344, 0.0998887976426307, 0.0998164934815118};
    const double dv[5] = {0.0018811881188119, 0.0018439368689344, 0.0017887976426307, 0.0017164934815118,
                          0.0016279102182108};
    const double v[5] = {0.0018811881188119, 0.0037251249877462, 0.0055139226303769, 0.0072304161118887,
                         0.0088583263300995};
    const double y[5] = {0.9000188118811882, 0.9000560631310656, 0.9001112023573693, 0.9001835065184882,
                         0.9002720897817892};
    double v_prev = 0.0;
    for (int s = 0; s < 5; ++s) {
        e.sim.step();
        EXPECT_NEAR(e.contact->last_pen_, pen[s], 1e-12) << "step " << s + 1;
        EXPECT_NEAR(e.sphere->velocity[0].y() - v_prev, dv[s], 1e-12) << "step " << s + 1;
        EXPECT_NEAR(e.sphere->velocity[0].y(), v[s], 1e-12) << "step " << s + 1;
        EXPECT_NEAR(e.sphere->position[0].y(), y[s], 1e-12) << "step " << s + 1;
        EXPECT_NEAR(e.sphere->position[0].x(), 0.2, 1e-15);
        EXPECT_NEAR(e.sphere->velocity[0].z(), 0.0, 1e-15);
        v_prev = e.sphere->velocity[0].y();
    }
    // The static side never moves.
    EXPECT_EQ(e.floor->position[0], Vec3(0.2, 0.0, 0.3));
    EXPECT_NEAR(e.sim.time(), 0.05, 1e-15);
}

TEST(WorkedExampleE, ExplicitContactMatchesSpecValues) {
    ExampleE e(false, 1e-9, 1e-9);
    const double v[3] = {0.0019, 0.003781, 0.00562419};
    const double y[3] = {0.900019, 0.90005681, 0.9001130519};
    for (int s = 0; s < 3; ++s) {
        e.sim.step();
        EXPECT_NEAR(e.sphere->velocity[0].y(), v[s], 1e-12) << "step " << s + 1;
        EXPECT_NEAR(e.sphere->position[0].y(), y[s], 1e-12) << "step " << s + 1;
        // External forces are cleared at the end of the step.
        EXPECT_EQ(e.sphere->external_force[0], Vec3::Zero());
    }
}

TEST(WorkedExampleE, CgThresholdQuirkFreezesVelocityAfterFirstSolve) {
    ExampleE e(true, 1e-5, 1e-5);
    e.sim.step();
    EXPECT_NEAR(e.sphere->velocity[0].y(), 0.0018811881188118586, 1e-15);
    for (int s = 2; s <= 4; ++s) {
        e.sim.step();
        EXPECT_EQ(e.solver->last_cg_stats().end_condition, CgEndCondition::threshold);
        EXPECT_EQ(e.solver->last_cg_stats().iterations, 1);
        EXPECT_NEAR(e.sphere->velocity[0].y(), 0.0018811881188118586, 1e-15) << "step " << s;
    }
}

/// Oscillator: unit mass on a spring (ks = 100, L = 1) to a fixed anchor, no gravity. Returns
/// E_final / E_0 and the maximum relative energy excursion.
struct EnergyHistory {
    double final_ratio;
    double max_excursion;
    bool monotone;
};

template <class Configure>
EnergyHistory run_oscillator(const Configure& configure, int steps) {
    Simulation sim;
    sim.root().set_gravity(Vec3::Zero());
    Node& anchor = sim.root().add_child("anchor");
    auto& a = anchor.add_state<Vec3Types>();
    a.position = {Vec3::Zero()};
    Node& body = sim.root().add_child("body");
    configure(body);
    auto& x = body.add_state<Vec3Types>();
    x.position = {Vec3(1.1, 0, 0)};
    body.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(1.0);
    auto& spring = body.add_force_field<SpringForceField>(a, x);
    spring.add_spring({0, 0, 100.0, 0.0, 1.0});
    sim.init();
    auto energy = [&] {
        const double d = x.position[0].norm() - 1.0;
        return 0.5 * x.velocity[0].squaredNorm() + 0.5 * 100.0 * d * d;
    };
    const double e0 = energy();
    EnergyHistory h{1.0, 0.0, true};
    double prev = e0;
    for (int s = 0; s < steps; ++s) {
        sim.step();
        const double e = energy();
        h.max_excursion = std::max(h.max_excursion, std::abs(e / e0 - 1.0));
        if (e > prev * (1 + 1e-12)) h.monotone = false;
        prev = e;
    }
    h.final_ratio = prev / e0;
    return h;
}

TEST(Integrators, HarmonicOscillatorEnergyBehaviour) {
    const auto implicit = run_oscillator(
        [](Node& n) {
            auto& s = n.set_ode_solver<EulerImplicitSolver>();
            s.cg.tolerance = 1e-12;
            s.cg.threshold = 1e-30;
        },
        1000);
    const auto trapezoidal = run_oscillator(
        [](Node& n) {
            auto& s = n.set_ode_solver<EulerImplicitSolver>();
            s.trapezoidal_scheme = true;
            s.cg.tolerance = 1e-12;
            s.cg.threshold = 1e-30;
        },
        1000);
    const auto symplectic = run_oscillator([](Node& n) { n.set_ode_solver<EulerExplicitSolver>(); }, 1000);
    // Backward Euler: |amplification|² = 1/(1 + ω²h²) = 1/1.01 per step, energy decays monotonically.
    EXPECT_TRUE(implicit.monotone);
    EXPECT_NEAR(std::log(implicit.final_ratio), -1000 * std::log(1.01), 0.05 * 1000 * std::log(1.01));
    // Symplectic Euler: bounded energy error O(ωh), no drift.
    EXPECT_LT(symplectic.max_excursion, 0.06);
    EXPECT_GT(symplectic.final_ratio, 0.94);
    // Trapezoidal variant dissipates far less than backward Euler.
    EXPECT_GT(trapezoidal.final_ratio, 100 * implicit.final_ratio);
}

TEST(SolverSubtrees, SimulatedPairWithRootSpringIsExplicit) {
    // Two unit masses on a spring stored in the root (no solver there): the spring force is
    // computed once from x(t_n) and applied as a constant external force: Δv = h f / m.
    Simulation sim;
    sim.root().set_gravity(Vec3::Zero());
    Vec3Object* s[2];
    for (int i = 0; i < 2; ++i) {
        Node& n = sim.root().add_child(std::string("b").append(std::to_string(i)));
        n.set_ode_solver<EulerImplicitSolver>().cg.threshold = 0;
        s[i] = &n.add_state<Vec3Types>();
        s[i]->position = {Vec3(1.5 * i, 0, 0)};
        n.set_mass<UniformMass<Vec3Types>>(*s[i]).set_vertex_mass(1.0);
    }
    sim.root().add_force_field<SpringForceField>(*s[0], *s[1]).add_spring({0, 0, 1000.0, 0.0, 1.0});
    sim.init();
    sim.step();
    // f on b0 = +1000·0.5 along x -> Δv = 0.01·500 = 5 exactly (explicit); implicit would be 5/(1+0.2).
    EXPECT_NEAR(s[0]->velocity[0].x(), 5.0, 1e-12);
    EXPECT_NEAR(s[1]->velocity[0].x(), -5.0, 1e-12);
}

TEST(SolverSubtrees, ExternalForcesAreClearedAfterAStepExceptAStaticStates) {
    // A body under a solver, an anchor with no solver tied to it by an explicit spring (root, no
    // solver), and a static marker nothing reads. An external force on the body acts for one step
    // (Δv = h f / m) and is cleared; the anchor's, written by the explicit spring at each step, is
    // cleared too; the marker's is never applied and stays as it was set.
    Simulation sim;
    sim.root().set_gravity(Vec3::Zero());
    Node& body = sim.root().add_child("body");
    body.set_ode_solver<EulerImplicitSolver>().cg.threshold = 0;
    auto& x = body.add_state<Vec3Types>();
    x.position = {Vec3(0, 0, 0)};
    body.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(2.0);
    auto& anchor = sim.root().add_child("anchor").add_state<Vec3Types>();
    anchor.position = {Vec3(0, 3, 0)};
    auto& marker = sim.root().add_child("marker").add_state<Vec3Types>();
    marker.position = {Vec3(5, 0, 0)};
    sim.root().add_force_field<SpringForceField>(anchor, x).add_spring({0, 0, 10.0, 0.0, 1.0});
    sim.init();
    x.external_force[0] = Vec3(4, 0, 0);
    marker.external_force[0] = Vec3(0, 0, 7);
    sim.step();  // h = 0.01 (the root's default dt)
    const double h = sim.root().dt();
    // x: Δv_x = h·4/2, and the spring (stretched by 2 m, explicit) pulls it up: Δv_y = h·(10·2)/2
    EXPECT_NEAR(x.velocity[0].x(), h * 2.0, 1e-12);
    EXPECT_NEAR(x.velocity[0].y(), h * 10.0, 1e-12);
    EXPECT_EQ(x.external_force[0], Vec3::Zero());
    EXPECT_EQ(anchor.external_force[0], Vec3::Zero());
    EXPECT_EQ(marker.external_force[0], Vec3(0, 0, 7));
    EXPECT_EQ(marker.position[0], Vec3(5, 0, 0));
    // the plan marks the static states (their scratch is cleared only where solves wrote it)
    EXPECT_FALSE(x.is_static());
    EXPECT_FALSE(anchor.is_static());
    EXPECT_TRUE(marker.is_static());
    sim.step();
    EXPECT_EQ(anchor.external_force[0], Vec3::Zero());
    EXPECT_EQ(marker.external_force[0], Vec3(0, 0, 7));
}

TEST(SolverSubtrees, CommonSolverMakesTheSpringImplicit) {
    Simulation sim;
    sim.root().set_gravity(Vec3::Zero());
    sim.root().set_ode_solver<EulerImplicitSolver>().cg.threshold = 0;
    Vec3Object* s[2];
    for (int i = 0; i < 2; ++i) {
        Node& n = sim.root().add_child(std::string("b").append(std::to_string(i)));
        s[i] = &n.add_state<Vec3Types>();
        s[i]->position = {Vec3(1.5 * i, 0, 0)};
        n.set_mass<UniformMass<Vec3Types>>(*s[i]).set_vertex_mass(1.0);
    }
    sim.root().add_force_field<SpringForceField>(*s[0], *s[1]).add_spring({0, 0, 1000.0, 0.0, 1.0});
    sim.init();
    sim.step();
    // Relative mode: (1 + 2 h² k) Δv_rel = 2 h f -> Δv0 = 5 / (1 + 0.2).
    EXPECT_NEAR(s[0]->velocity[0].x(), 5.0 / 1.2, 1e-10);
    EXPECT_NEAR(s[1]->velocity[0].x(), -5.0 / 1.2, 1e-10);
}

TEST(FixedProjectiveConstraint, FixedDofsDoNotMove) {
    Simulation sim;
    Node& n = sim.root().add_child("chain");
    n.set_ode_solver<EulerImplicitSolver>().cg.threshold = 1e-20;
    auto& x = n.add_state<Vec3Types>();
    x.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(1.0);
    auto& springs = n.add_force_field<SpringForceField>(x);
    springs.add_spring({0, 1, 100, 0, 1});
    springs.add_spring({1, 2, 100, 0, 1});
    auto& fixed = n.add_constraint<FixedProjectiveConstraint>(x);
    fixed.set_indices({0});
    sim.init();
    for (int i = 0; i < 20; ++i) sim.step();
    EXPECT_EQ(x.position[0], Vec3::Zero());
    EXPECT_EQ(x.velocity[0], Vec3::Zero());
    EXPECT_LT(x.position[2].y(), -0.01);  // the free end falls
    fixed.set_indices({3});
    EXPECT_THROW(fixed.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
