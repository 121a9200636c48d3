// Simulation::step runs solvers next to each other in the plan concurrently when their touched
// states do not meet (OdeSolver::list_touched_states) and two of them have at least
// kMinUnknownsPerConcurrentSolve unknowns: same bits as in plan order, the first failing solver's
// error, and solvers that share a state (another solver's or a static one) kept in order. Explicit
// force fields next to each other whose states do not meet run as tasks too
// (Simulation::find_explicit_run). At a node without solver only SOFA's interaction force fields
// are explicit (SolveVisitor::processNodeTopDown); a plain force field there is never evaluated.
//
// Whether two solves overlap in time is observed with a rendezvous force field: on its first
// force evaluation it waits (up to a timeout) until another one has arrived. Concurrent solves
// meet; solves in order cannot, and time out.

#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <chrono>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <thread>

namespace penalty {
namespace {

using namespace std::chrono_literals;

/// `met` once an arrival finds another one still waiting (each waits up to `timeout`).
struct Rendezvous {
    explicit Rendezvous(std::chrono::milliseconds wait) : timeout(wait) {}
    std::chrono::milliseconds timeout;
    bool armed = true;  ///< the fields arrive only while armed
    std::mutex mutex;
    std::condition_variable arrived;
    int waiting = 0;
    bool met = false;

    void arrive() {
        std::unique_lock lock(mutex);
        if (waiting > 0) {
            met = true;
            arrived.notify_all();
            return;
        }
        ++waiting;
        arrived.wait_for(lock, timeout, [this] { return met; });
        --waiting;
    }
};

/// No force; its first add_force while the rendezvous is armed arrives at it.
class RendezvousField final : public ForceField<Vec3Types> {
public:
    RendezvousField(Vec3Object& state, Rendezvous& rendezvous) : ForceField(state), rendezvous_(&rendezvous) {}
    void add_force(std::span<Vec3>, std::span<const Vec3>, std::span<const Vec3>) override {
        if (rendezvous_->armed && std::exchange(first_, false)) rendezvous_->arrive();
    }
    void add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, double) const override {}

private:
    Rendezvous* rendezvous_;
    bool first_ = true;
};

/// The same between two states (an interaction field: the node lists it among the springs, in
/// the order added).
class RendezvousPairField final : public Vec3InteractionForceField {
public:
    RendezvousPairField(Vec3Object& s1, Vec3Object& s2, Rendezvous& rendezvous)
        : Vec3InteractionForceField(s1, s2), rendezvous_(&rendezvous) {}
    void add_force(Vec3Span, Vec3Span, ConstVec3Span, ConstVec3Span, ConstVec3Span, ConstVec3Span) override {
        if (rendezvous_->armed && std::exchange(first_, false)) rendezvous_->arrive();
    }
    void add_dforce(Vec3Span, Vec3Span, ConstVec3Span, ConstVec3Span, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, Index, double) const override {}

private:
    Rendezvous* rendezvous_;
    bool first_ = true;
};

/// A NaN force on point 0, after `delay`.
class NanField final : public ForceField<Vec3Types> {
public:
    NanField(Vec3Object& state, std::chrono::milliseconds delay) : ForceField(state), delay_(delay) {}
    void add_force(std::span<Vec3> f, std::span<const Vec3>, std::span<const Vec3>) override {
        std::this_thread::sleep_for(delay_);
        f[0].x() += std::numeric_limits<double>::quiet_NaN();
    }
    void add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, double) const override {}

private:
    std::chrono::milliseconds delay_;
};

/// `steps` steps of `sim` at `threads` threads; then the positions and velocities of `states`.
std::vector<Vec3> run_states(Simulation& sim, const std::vector<Vec3Object*>& states, int threads, int steps) {
    sim.set_threads(threads);
    sim.init();
    for (int s = 0; s < steps; ++s) sim.step();
    std::vector<Vec3> out;
    for (const Vec3Object* x : states) {
        out.insert(out.end(), x->position.begin(), x->position.end());
        out.insert(out.end(), x->velocity.begin(), x->velocity.end());
    }
    return out;
}

/// One chain per entry of `points` (its number of points) of masses under gravity, each in its own node with its own
/// implicit solver: neighbours joined by springs (ks 500, rest 1), point 0 hanging from a static
/// anchor by a spring when `anchored` (one anchor state per body, or one for all when
/// `shared_anchor`), body 0 tied to body 1 by a spring in body 0's node when `tie_bodies`.
struct Chains {
    Simulation sim;
    std::vector<Vec3Object*> states;
    std::vector<Node*> nodes;

    explicit Chains(const std::vector<int>& points_per_body, bool shared_anchor = false, bool tie_bodies = false) {
        Node& statics = sim.root().add_child("anchors");
        Vec3Object* shared = nullptr;
        for (int b = 0; b < int(points_per_body.size()); ++b) {
            const int points = points_per_body[std::size_t(b)];
            Node& n = sim.root().add_child("body" + std::to_string(b));
            auto& solver = n.set_ode_solver<EulerImplicitSolver>();
            solver.cg.iterations = 40;
            solver.cg.tolerance = 1e-12;
            solver.cg.threshold = 1e-20;
            solver.rayleigh_stiffness = 0.05 * b;
            Vec3Object& x = n.add_state<Vec3Types>();
            for (int i = 0; i < points; ++i)
                x.position.push_back(Vec3(3.0 * b + 0.1 * i * i / points, -1.0 * i, 0.2 * b));
            n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(0.5 + 0.25 * b);
            auto& springs = n.add_force_field<SpringForceField>(x);
            for (int i = 0; i + 1 < points; ++i) springs.add_spring({i, i + 1, 500.0 + 10.0 * b, 0.0, 1.0});
            Vec3Object* anchor = shared;
            if (anchor == nullptr) {
                anchor = &statics.add_child("anchor" + std::to_string(b)).add_state<Vec3Types>();
                anchor->position = {Vec3(3.0 * b, 1.0, 0.2 * b)};
                if (shared_anchor) shared = anchor;
            }
            n.add_force_field<SpringForceField>(*anchor, x).add_spring({0, 0, 800.0, 0.0, 1.0});
            states.push_back(&x);
            nodes.push_back(&n);
        }
        if (tie_bodies)
            nodes[0]->add_force_field<SpringForceField>(*states[0], *states[1]).add_spring({1, 1, 300.0, 0.0, 3.0});
    }

    /// Adds a rendezvous field to every body.
    void meet_at(Rendezvous& r) {
        for (std::size_t b = 0; b < nodes.size(); ++b) nodes[b]->add_force_field<RendezvousField>(*states[b], r);
    }

    std::vector<Vec3> run(int threads, int steps) { return run_states(sim, states, threads, steps); }
};

void expect_same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    ASSERT_EQ(a.size(), b.size());
    int differing = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differing += test::same_bits(a[i], b[i]) ? 0 : 1;
    EXPECT_EQ(differing, 0);
}

// Enough workers for a two-thread arena even on a one-core machine.
class ConcurrentSolvers : public ::testing::Test {
protected:
    tbb::global_control two_workers_{tbb::global_control::max_allowed_parallelism, 2};
};

TEST_F(ConcurrentSolvers, IndependentSolversMeetAndGiveTheBitsOfOneThread) {
    // 3 chains of 40 points: 120 unknowns each (≥ kMinUnknownsPerConcurrentSolve), one anchor each.
    static_assert(3 * 40 >= kMinUnknownsPerConcurrentSolve);
    Rendezvous in_order(200ms);
    Chains one({40, 40, 40});
    one.meet_at(in_order);
    const std::vector<Vec3> sequential = one.run(1, 30);
    EXPECT_FALSE(in_order.met);

    Rendezvous together(10s);  // long: a loaded machine may be slow to wake the worker
    Chains two({40, 40, 40});
    two.meet_at(together);
    const std::vector<Vec3> concurrent = two.run(2, 30);
    EXPECT_TRUE(together.met);
    expect_same_bits(sequential, concurrent);
    // the chains moved: the comparison is not of initial states
    EXPECT_GT((two.states[0]->position[39] - Vec3(0.1 * 39 * 39 / 40, -39.0, 0.0)).norm(), 1e-2);

    Chains automatic({40, 40, 40});  // threads 0: TBB's default
    expect_same_bits(sequential, automatic.run(0, 30));
}

TEST_F(ConcurrentSolvers, SolversSharingAStateRunInOrder) {
    for (const bool shared_anchor : {true, false}) {
        // shared_anchor: both read the same static anchor (and write its scratch force and dx);
        // otherwise body 0's tie spring reads body 1's state.
        Rendezvous r(300ms);
        Chains c({40, 40}, shared_anchor, /*tie_bodies=*/!shared_anchor);
        c.meet_at(r);
        const std::vector<Vec3> two = c.run(2, 10);
        EXPECT_FALSE(r.met) << "shared_anchor " << shared_anchor;
        Chains one({40, 40}, shared_anchor, !shared_anchor);
        expect_same_bits(one.run(1, 10), two);
    }
}

TEST_F(ConcurrentSolvers, SmallOrNewtonSolversRunInOrder) {
    {
        Rendezvous r(300ms);
        Chains small({4, 4});  // 12 unknowns each
        small.meet_at(r);
        small.run(2, 3);
        EXPECT_FALSE(r.met);
    }
    {
        Rendezvous r(300ms);
        Chains newton({40, 40});
        for (Node* n : newton.nodes) static_cast<EulerImplicitSolver*>(n->ode_solver())->newton.enabled = true;
        newton.meet_at(r);
        newton.run(2, 2);
        EXPECT_FALSE(r.met);
    }
    {
        // Newton turned on after the plan (and its runs) were made: no graph change, yet the
        // solvers run alone from the next step on
        Rendezvous r(300ms);
        r.armed = false;
        Chains late({40, 40});
        late.meet_at(r);
        late.run(2, 2);
        ASSERT_EQ(late.sim.concurrent_solver_runs().size(), 1u);
        for (Node* n : late.nodes) static_cast<EulerImplicitSolver*>(n->ode_solver())->newton.enabled = true;
        EXPECT_TRUE(late.sim.concurrent_solver_runs().empty());
        r.armed = true;
        late.run(2, 2);
        EXPECT_FALSE(r.met);
    }
    {
        // one large solver among small ones: nothing to share the work with
        Rendezvous r(300ms);
        Chains mixed({40, 4, 4});
        mixed.meet_at(r);
        mixed.run(2, 3);
        EXPECT_FALSE(r.met);
    }
}

TEST_F(ConcurrentSolvers, ErrorIsTheFirstFailingSolverInPlanOrder) {
    // Body 0 fails late, body 1 at once: the error raised is body 0's, as in plan order.
    Rendezvous r(10s);
    Chains c({40, 40});
    c.meet_at(r);
    auto& late = c.nodes[0]->add_force_field<NanField>(*c.states[0], 300ms);
    c.nodes[1]->add_force_field<NanField>(*c.states[1], 0ms);
    c.sim.set_threads(2);
    c.sim.init();
    try {
        c.sim.step();
        FAIL() << "no error";
    } catch (const NonFiniteSolveError& e) {
        EXPECT_EQ(e.force_field(), &late) << e.what();
    }
    EXPECT_TRUE(r.met);
}

/// `pairs` pairs of one-point bodies under one implicit solver, each pair joined by a spring
/// field at the root (explicit: no solver above it, SOFA's interaction fields above every
/// solver). `chained`: a second field joins each pair's second body to the next pair's first, so
/// every field meets the next one. A rendezvous field at the root before and after the springs,
/// each between two bodies of its own.
struct ExplicitPairs {
    Simulation sim;
    std::vector<Vec3Object*> states;

    ExplicitPairs(int pairs, bool chained, Rendezvous& r) {
        Node& bodies = sim.root().add_child("bodies");
        auto& solver = bodies.set_ode_solver<EulerImplicitSolver>();
        solver.cg.iterations = 20;
        solver.cg.tolerance = 1e-12;
        solver.cg.threshold = 1e-20;
        for (int i = 0; i < 2 * pairs + 4; ++i) {
            Node& n = bodies.add_child("body" + std::to_string(i));
            Vec3Object& x = n.add_state<Vec3Types>();
            x.position = {Vec3(0.3 * i, 0.01 * (i % 7), 0.5 * (i % 2))};
            n.set_mass<UniformMass<Vec3Types>>(x).set_vertex_mass(0.5 + 0.01 * i);
            states.push_back(&x);
        }
        const std::size_t extra = 2 * std::size_t(pairs);
        sim.root().add_force_field<RendezvousPairField>(*states[extra], *states[extra + 1], r);
        for (int p = 0; p < pairs; ++p) {
            const std::size_t a = 2 * std::size_t(p), b = a + 1;
            sim.root()
                .add_force_field<SpringForceField>(*states[a], *states[b])
                .add_spring({0, 0, 200.0 + p, 0.0, 0.4});
            if (chained)
                sim.root()
                    .add_force_field<SpringForceField>(*states[b], *states[b + 1])
                    .add_spring({0, 0, 50.0, 0.0, 0.3});
        }
        sim.root().add_force_field<RendezvousPairField>(*states[extra + 2], *states[extra + 3], r);
    }

    std::vector<Vec3> run(int threads, int steps) { return run_states(sim, states, threads, steps); }
};

TEST_F(ConcurrentSolvers, ExplicitFieldsOnDisjointStatesMeetAndGiveTheBitsOfOneThread) {
    constexpr int kPairs = 80;  // 82 explicit fields, above kMinExplicitFieldsPerConcurrentRun
    static_assert(kPairs + 2 >= Simulation::kMinExplicitFieldsPerConcurrentRun);
    Rendezvous in_order(200ms);
    ExplicitPairs one(kPairs, false, in_order);
    const std::vector<Vec3> sequential = one.run(1, 20);
    EXPECT_FALSE(in_order.met);
    EXPECT_EQ(one.sim.concurrent_explicit_fields(), 82u);  // the plan's runs (tasks need threads)

    Rendezvous together(10s);
    ExplicitPairs two(kPairs, false, together);
    const std::vector<Vec3> concurrent = two.run(2, 20);
    EXPECT_TRUE(together.met);
    expect_same_bits(sequential, concurrent);
    // the springs moved the bodies: the comparison is not of initial states
    EXPECT_GT((two.states[0]->position[0] - Vec3(0.0, 0.0, 0.0)).norm(), 1e-3);
}

TEST_F(ConcurrentSolvers, ExplicitFieldsSharingStatesRunInOrder) {
    // every field shares a body with the next: runs of one field, nothing as tasks
    Rendezvous r(300ms);
    ExplicitPairs chained(40, true, r);
    const std::vector<Vec3> two = chained.run(2, 10);
    EXPECT_FALSE(r.met);
    EXPECT_EQ(chained.sim.concurrent_explicit_fields(), 0u);
    Rendezvous r1(300ms);
    ExplicitPairs one(40, true, r1);
    expect_same_bits(one.run(1, 10), two);
}

/// Counts its force evaluations (a plain ForceField: SOFA's ForceField<Vec3>).
class CountingField final : public ForceField<Vec3Types> {
public:
    explicit CountingField(Vec3Object& state) : ForceField(state) {}
    void add_force(std::span<Vec3> f, std::span<const Vec3>, std::span<const Vec3>) override {
        ++evaluations;
        f[0].y() += 1.0;
    }
    void add_dforce(std::span<Vec3>, std::span<const Vec3>, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, double) const override {}
    int evaluations = 0;
};

/// The same between two states (SOFA's PairInteractionForceField unless set otherwise).
class CountingPairField final : public Vec3InteractionForceField {
public:
    CountingPairField(Vec3Object& s1, Vec3Object& s2) : Vec3InteractionForceField(s1, s2) {}
    void add_force(Vec3Span f1, Vec3Span, ConstVec3Span, ConstVec3Span, ConstVec3Span, ConstVec3Span) override {
        ++evaluations;
        f1[0].y() += 1.0;
    }
    void add_dforce(Vec3Span, Vec3Span, ConstVec3Span, ConstVec3Span, double, double) const override {}
    void add_stiffness_triplets(TripletList&, Index, Index, double) const override {}
    int evaluations = 0;
};

TEST(SolvePlan, OnlyInteractionFieldsOfNodesWithoutSolverAreExplicit) {
    // SOFA's SolveVisitor::processNodeTopDown: at a node without ODE solver it evaluates the
    // node's interactionForceField list only (into externalForce); a plain ForceField there (a
    // TriangularFEMForceField of a shape no solver moves) is never evaluated.
    Simulation sim;
    Node& free_node = sim.root().add_child("no_solver");
    Vec3Object& a = free_node.add_state<Vec3Types>();
    a.position = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
    Node& other = sim.root().add_child("other");
    Vec3Object& b = other.add_state<Vec3Types>();
    b.position = {Vec3(0, 2, 0)};
    Node& lone = sim.root().add_child("lone");
    Vec3Object& c = lone.add_state<Vec3Types>();
    c.position = {Vec3(0, 3, 0)};

    auto& plain = free_node.add_force_field<CountingField>(a);
    auto& pair = free_node.add_force_field<CountingPairField>(a, b);
    // a pair field SOFA derives from ForceField (TriangularBendingSprings): not explicit either
    auto& plain_pair = lone.add_force_field<CountingPairField>(c, c);
    plain_pair.set_sofa_interaction(false);
    auto& lone_plain = lone.add_force_field<CountingField>(c);

    sim.init();
    for (int step = 0; step < 3; ++step) sim.step();
    EXPECT_EQ(plain.evaluations, 0);
    EXPECT_EQ(pair.evaluations, 3);
    EXPECT_EQ(plain_pair.evaluations, 0);
    EXPECT_EQ(lone_plain.evaluations, 0);
    // the ones it skips, depth first (what `penalty info` marks "never evaluated")
    EXPECT_EQ(sim.unevaluated_force_fields(), (std::vector<const BaseForceField*>{&plain, &plain_pair, &lone_plain}));
    // states only plain fields read are static (no solve writes their scratch); the pair's are not
    EXPECT_FALSE(a.is_static());
    EXPECT_FALSE(b.is_static());
    EXPECT_TRUE(c.is_static());
    // nothing moved: no solver
    EXPECT_EQ(a.position[0], Vec3(0, 0, 0));
    EXPECT_EQ(c.position[0], Vec3(0, 3, 0));
}

}  // namespace
}  // namespace penalty
