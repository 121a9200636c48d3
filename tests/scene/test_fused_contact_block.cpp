// SubtreeSystem's fused contact block (solver.hpp): under a FixedReaders, the contact fields whose
// contact points only they read are applied by apply_mbk on flat copies of the mappings' rows,
// and the contact mappings nobody reads add their zeros once per parent row. Both must give the
// bits of the products through the objects, for every (m, b, k), including the signs of zeros:
// products with m = b = k = 0 accumulated onto signed zeros exercise exactly the additions of ±0
// that the unread mappings stand for. Scenes:
//  - a pile of 8 FEM cubes in a static bowl (cubes_in_bowl, k = 2): the cube–bowl fields are in
//    the cubes' solver (one side fused, the bowl's side external), the cube–cube fields above it
//    (explicit, SOFA's §2.1), so their contact mappings are read by nobody in the solve;
//  - the pile with damped contact springs (each field its own product) and with a force evaluation
//    inside one FixedReaders (the flat spring list made again);
//  - a spring cube sliding over static points, its bottom face a triangle surface carried by a
//    BarycentricMapping (a fused mapping whose parent is a mapped state of selected rows), and
//    spheres on its own corners (an identity side: that field is not fused and keeps its place);
//  - a spring cube resting on a bed of 6 400 static points: one contact field of thousands of
//    springs, whose J and springs run in ranges on TBB's threads and whose mapping's Jᵀ runs as
//    gathers by parent row (FusedContactBlock::kMinItemsOnThreads).
#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/penalty_interaction.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/cubes_in_bowl.hpp"
#include "penalty_test/same_bits.hpp"
#include "penalty_test/sanitizer.hpp"
#include "penalty_test/sliding_cube.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <sstream>
#include <string>

namespace {

using namespace penalty;
namespace bowl = penalty::test::cubes_in_bowl;

// Two spring cubes of 0.4 m under one solver, pushed at each other (0.05 m/s each, 0.04 m apart): no
// static model, so their contact field lies at the root (explicit) and the solve has only unread
// contact mappings.
std::string stacked_cubes_xml() {
    const auto cube = [](const std::string& name, double y, double vy) {
        std::ostringstream s;
        s << "    <Node name=\"" << name << "\">\n      <MechanicalObject position=\"";
        for (int k = 0; k < 8; ++k)
            s << 0.4 * (k & 1) + 0.01 * y << ' ' << y + 0.4 * ((k >> 1) & 1) << ' ' << 0.4 * (k >> 2) << "  ";
        s << "\" velocity=\"";
        for (int k = 0; k < 8; ++k) s << "0 " << vy << " 0  ";
        // the 12 outer triangles of the hexahedron (vertex k at bits x, y, z of k)
        s << R"("/>
      <MeshTopology hexas="0 1 3 2 4 5 7 6" triangles="0 2 1  1 2 3  4 5 6  5 7 6  0 1 4  1 5 4  2 6 3  3 6 7  0 4 2  2 4 6  1 3 5  3 7 5"/>
      <UniformMass totalMass="1"/>
      <MeshSpringForceField stiffness="800" damping="1"/>
      <TriangleCollisionModel contactStiffness="30"/>
    </Node>
)";
        return s.str();
    };
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <NewProximityIntersection alarmDistance="0.06" contactDistance="0.03"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Bodies">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-10" threshold="1e-12"/>
)" + cube("Lower", 0.0, 0.05) +
           cube("Upper", 0.44, -0.05) + R"(  </Node>
</Node>
)";
}

std::unique_ptr<scene::Scene> cubes_in_bowl(int k) {
    bowl::Setup s;
    s.k = k;
    return scene::build_scene(io::parse_scene_string(bowl::scene_xml(s), "cubes_in_bowl.scn"));
}

Node& child(Node& parent, const std::string& name) {
    for (const auto& c : parent.children())
        if (c->name() == name) return *c;
    throw std::runtime_error("no node " + name);
}

struct Tally {
    int steps_with_fields = 0;       ///< steps whose system fused a contact field
    int steps_with_unread = 0;       ///< steps whose system fused an unread contact mapping
    int steps_with_plain_field = 0;  ///< steps with a contact field the block does not take
    long compared = 0;
    long differing = 0;
    long signed_zeros = 0;  ///< −0 results of the zero products (the signs are exercised)
};

// After each step: two systems of `node`, fused and not, each under a FixedReaders; the same
// random products, and products with m = b = k = 0 accumulated onto signed zeros, compared bit
// for bit.
void compare_products(scene::Scene& scene, Node& node, int steps, std::uint32_t seed, Tally& t) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::bernoulli_distribution coin(0.5);
    const auto draw = [&](Eigen::Index n, bool zeros) {
        Eigen::VectorXd v(n);
        for (Eigen::Index i = 0; i < n; ++i) v[i] = zeros ? (coin(rng) ? -0.0 : 0.0) : (coin(rng) ? unit(rng) : -0.0);
        return v;
    };
    const double m = 1.02, b = -0.01, k = -1.01e-4;  // an implicit-Euler operator
    for (int step = 0; step < steps; ++step) {
        scene.step();
        const SubtreeSystem fused(node, true, true), plain(node, true, false);
        ASSERT_EQ(fused.size(), plain.size());
        const SubtreeSystem::FusedContactCounts counts = fused.fused_contact_counts();
        t.steps_with_fields += counts.force_fields > 0 ? 1 : 0;
        t.steps_with_unread += counts.unread_mappings > 0 ? 1 : 0;
        std::size_t contact_fields = 0;
        for (const BaseForceField* ff : fused.force_fields())
            contact_fields += dynamic_cast<const Vec3InteractionForceField*>(ff) ? 1 : 0;
        t.steps_with_plain_field += contact_fields > counts.force_fields ? 1 : 0;
        EXPECT_EQ(plain.fused_contact_counts().force_fields + plain.fused_contact_counts().unread_mappings, 0u);

        const Eigen::VectorXd dx1 = draw(fused.size(), false), dx2 = draw(fused.size(), false);
        const Eigen::VectorXd zeros = draw(fused.size(), true);
        Eigen::VectorXd f1, f2, p1, p2, fz = zeros, pz = zeros, fa = dx2, pa = dx2;
        {
            const SubtreeSystem::FixedReaders fixed_f(fused);
            const SubtreeSystem::FixedReaders fixed_p(plain);
            fused.apply_mbk(dx1, fa, -0.1, 0.0, 0.05, false, /*accumulate=*/true);  // a right-hand side
            plain.apply_mbk(dx1, pa, -0.1, 0.0, 0.05, false, true);
            fused.apply_mbk(dx1, f1, m, b, k, true);
            plain.apply_mbk(dx1, p1, m, b, k, true);
            fused.apply_mbk(dx2, f2, m, b, k, true);
            plain.apply_mbk(dx2, p2, m, b, k, true);
            fused.apply_mbk(dx1, fz, 0.0, 0.0, 0.0, false, true);
            plain.apply_mbk(dx1, pz, 0.0, 0.0, 0.0, false, true);
        }
        for (const auto& [x, y] : {std::pair{&f1, &p1}, {&f2, &p2}, {&fz, &pz}, {&fa, &pa}}) {
            ASSERT_EQ(x->size(), y->size());
            for (Eigen::Index i = 0; i < x->size(); ++i) {
                ++t.compared;
                t.differing += test::same_bits((*x)[i], (*y)[i]) ? 0 : 1;
            }
        }
        for (Eigen::Index i = 0; i < pz.size(); ++i) t.signed_zeros += pz[i] == 0.0 && std::signbit(pz[i]) ? 1 : 0;
    }
}

TEST(FusedContactProducts, PileInABowlGivesTheProductsThroughTheObjectsBitForBit) {
    const auto scene = cubes_in_bowl(2);
    Tally t;
    compare_products(*scene, child(scene->simulation().root(), "Cubes"), 120, 20261127, t);
    EXPECT_EQ(t.differing, 0) << "of " << t.compared;
    // the cubes land at step ~10 and pile up: fused fields (cube–bowl) and unread mappings
    // (cube–cube contacts above the solver) at most steps, and zeros of both signs
    EXPECT_GE(t.steps_with_fields, 100);
    EXPECT_GE(t.steps_with_unread, 80);
    EXPECT_GT(t.signed_zeros, 0);  // without the unread mappings' zeros, some of these differ
}

TEST(FusedContactProducts, SurfaceOnAMappedStateAndAnIdentitySideGiveTheSameBits) {
    const std::string xml = test::sliding_cube_xml({.floor_rows_z = {0.0, 0.11, 0.29, 0.4}, .corner_spheres = true});
    const auto scene = scene::build_scene(io::parse_scene_string(xml, "sliding_cube.scn"), {});
    Tally t;
    compare_products(*scene, child(scene->simulation().root(), "Body"), 60, 20261128, t);
    EXPECT_EQ(t.differing, 0) << "of " << t.compared;
    // the surface's contacts with the points are fused at most steps; the spheres' field (on
    // the body's own state) is not. (No −0 survives here: the springs add zeros of both signs to
    // every vertex; the pile's test covers the signs.)
    EXPECT_GE(t.steps_with_fields, 40);
    EXPECT_GE(t.steps_with_plain_field, 40);
}

TEST(FusedContactProducts, OnlyUnreadContactMappingsGiveTheSameBits) {
    const auto scene = scene::build_scene(io::parse_scene_string(stacked_cubes_xml(), "stacked_cubes.scn"), {});
    Tally t;
    compare_products(*scene, child(scene->simulation().root(), "Bodies"), 40, 20261129, t);
    EXPECT_EQ(t.differing, 0) << "of " << t.compared;
    EXPECT_GE(t.steps_with_unread, 10);  // the cubes meet (the contact field at the root)
    EXPECT_EQ(t.steps_with_fields, 0);
}

// A whole run: the solve's products fused or not, the same states at every step.
TEST(FusedContactProducts, RunsOfAPileAreTheSameBitsWithAndWithoutFusion) {
    const auto fused = cubes_in_bowl(2);
    const auto plain = cubes_in_bowl(2);
    auto* solver = dynamic_cast<EulerImplicitSolver*>(child(plain->simulation().root(), "Cubes").ode_solver());
    ASSERT_NE(solver, nullptr);
    solver->fuse_contact_products = false;
    const auto* fused_solver =
        dynamic_cast<const EulerImplicitSolver*>(child(fused->simulation().root(), "Cubes").ode_solver());
    ASSERT_NE(fused_solver, nullptr);
    ASSERT_TRUE(fused_solver->fuse_contact_products);
    long compared = 0, differing = 0;
    for (int step = 0; step < 200; ++step) {
        fused->step();
        plain->step();
        ASSERT_EQ(fused->states().size(), plain->states().size());
        for (std::size_t s = 0; s < fused->states().size(); ++s) {
            const auto& a = dynamic_cast<const Vec3Object&>(*fused->states()[s].state);
            const auto& b = dynamic_cast<const Vec3Object&>(*plain->states()[s].state);
            ASSERT_EQ(a.position.size(), b.position.size());
            for (std::size_t i = 0; i < a.position.size(); ++i) {
                ++compared;
                differing +=
                    test::same_bits(a.position[i], b.position[i]) && test::same_bits(a.velocity[i], b.velocity[i]) ? 0
                                                                                                                   : 1;
            }
        }
    }
    EXPECT_EQ(differing, 0) << "of " << compared;
    EXPECT_GT(compared, 200 * 64);
}

// Contact springs with normal damping (responseParams): their fields are fused, but each keeps
// its own product (the flat spring list holds SOFA's path only); b ≠ 0 makes the damping count.
TEST(FusedContactProducts, DampedContactFieldsKeepTheirOwnProductAndTheSameBits) {
    bowl::Setup setup;
    setup.k = 2;
    std::string xml = bowl::scene_xml(setup);
    const std::string response = R"(response="PenalityContactForceField")";
    const std::size_t at = xml.find(response);
    ASSERT_NE(at, std::string::npos);
    xml.insert(at + response.size(), R"( responseParams="damping=2")");
    const auto scene = scene::build_scene(io::parse_scene_string(xml, "damped_bowl.scn"));
    Tally t;
    compare_products(*scene, child(scene->simulation().root(), "Cubes"), 60, 20261130, t);
    EXPECT_EQ(t.differing, 0) << "of " << t.compared;
    EXPECT_GE(t.steps_with_fields, 40);
}

// The solver's system built again in place (SubtreeSystemCache: the layout, scratch and fused
// block refilled, their lists keeping what an earlier, larger pile left in them) against a system
// built new on the same graph, after each step of a pile whose pairs come and go: the same size,
// fused counts, forces and products, bit for bit.
TEST(FusedContactProducts, ASystemBuiltAgainInPlaceGivesTheBitsOfANewOne) {
    const auto scene = cubes_in_bowl(2);
    Node& cubes = child(scene->simulation().root(), "Cubes");
    const auto* solver = dynamic_cast<const EulerImplicitSolver*>(cubes.ode_solver());
    ASSERT_NE(solver, nullptr);
    std::mt19937 rng(20261202);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    long compared = 0, differing = 0;
    std::size_t largest_fused = 0, smaller_after_larger = 0;
    for (int step = 0; step < 150; ++step) {
        scene->step();
        const SubtreeSystem* kept = solver->system_cache().current();
        ASSERT_NE(kept, nullptr);
        const SubtreeSystem fresh(cubes, true, true);
        ASSERT_EQ(kept->size(), fresh.size());
        ASSERT_EQ(kept->mappings().size(), fresh.mappings().size());
        ASSERT_EQ(kept->force_fields().size(), fresh.force_fields().size());
        const auto kc = kept->fused_contact_counts(), fc = fresh.fused_contact_counts();
        EXPECT_EQ(kc.force_fields, fc.force_fields);
        EXPECT_EQ(kc.read_mappings, fc.read_mappings);
        EXPECT_EQ(kc.unread_mappings, fc.unread_mappings);
        EXPECT_EQ(kept->product_chains(), fresh.product_chains());
        const std::size_t fused = kc.read_mappings + kc.unread_mappings;
        smaller_after_larger += fused < largest_fused ? 1 : 0;
        largest_fused = std::max(largest_fused, fused);
        Eigen::VectorXd fk, ff;
        kept->compute_force(fk);
        fresh.compute_force(ff);
        const Eigen::VectorXd dx = Eigen::VectorXd::NullaryExpr(fresh.size(), [&] { return unit(rng); });
        Eigen::VectorXd qk, qf;
        {
            const SubtreeSystem::FixedReaders fixed_k(*kept);
            const SubtreeSystem::FixedReaders fixed_f(fresh);
            kept->apply_mbk(dx, qk, 1.02, -0.01, -1.01e-4, true);
            fresh.apply_mbk(dx, qf, 1.02, -0.01, -1.01e-4, true);
        }
        for (const auto& [x, y] : {std::pair{&fk, &ff}, {&qk, &qf}}) {
            ASSERT_EQ(x->size(), y->size());
            for (Eigen::Index i = 0; i < x->size(); ++i) {
                ++compared;
                differing += test::same_bits((*x)[i], (*y)[i]) ? 0 : 1;
            }
        }
    }
    EXPECT_EQ(differing, 0) << "of " << compared;
    // built again at many steps, some of them smaller than an earlier build (lists longer than
    // needed, left by the larger one)
    EXPECT_GE(solver->system_cache().builds(), 20);
    EXPECT_GT(largest_fused, 0u);
    EXPECT_GE(smaller_after_larger, 5u);
}

/// Contacts with pen > 0 over the contact fields of `system`.
std::size_t active_contacts(const SubtreeSystem& system) {
    std::size_t active = 0;
    for (const BaseForceField* ff : system.force_fields())
        if (const auto* contact = dynamic_cast<const PenaltyInteraction*>(ff))
            active += contact->field().active_count();
    return active;
}

// A force evaluation inside one FixedReaders (a Newton iterate's) changes the contacts' active
// sets: the next fused product makes its spring list again and gives the objects' bits.
TEST(FusedContactProducts, AForceEvaluationMakesTheSpringListAgain) {
    const auto scene = cubes_in_bowl(2);
    Node& cubes = child(scene->simulation().root(), "Cubes");
    for (int step = 0; step < 40; ++step) scene->step();  // the cubes rest on the bowl
    const SubtreeSystem fused(cubes, true, true), plain(cubes, true, false);
    ASSERT_GT(fused.fused_contact_counts().force_fields, 0u);
    std::mt19937 rng(20261130);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Eigen::VectorXd dx(fused.size());
    for (Eigen::Index i = 0; i < dx.size(); ++i) dx[i] = unit(rng);
    const SubtreeSystem::FixedReaders fixed_f(fused);
    const SubtreeSystem::FixedReaders fixed_p(plain);
    const auto products_agree = [&] {
        Eigen::VectorXd f, p;
        fused.apply_mbk(dx, f, 1.02, -0.01, -1.01e-4, true);
        plain.apply_mbk(dx, p, 1.02, -0.01, -1.01e-4, true);
        long differing = 0;
        for (Eigen::Index i = 0; i < f.size(); ++i) differing += test::same_bits(f[i], p[i]) ? 0 : 1;
        return differing;
    };
    EXPECT_EQ(products_agree(), 0);
    const std::size_t before = active_contacts(fused);
    // the cubes 2 mm higher: some springs let go, some hold
    for (const auto& body : cubes.children())
        if (auto* state = dynamic_cast<Vec3Object*>(body->state()))
            for (Vec3& x : state->position) x.y() += 0.002;
    fused.propagate_positions_and_velocities();  // the contact points follow
    Eigen::VectorXd force;
    fused.compute_force(force);
    EXPECT_LT(active_contacts(fused), before);
    EXPECT_GT(active_contacts(fused), 0u);
    EXPECT_EQ(products_agree(), 0);
}

// A 0.4 m spring cube whose bottom face, a triangle grid of `quads` × `quads` squares carried by
// a BarycentricMapping (node "Body/Surface"), rests 5 mm above a bed of `points` × `points` static
// points (MinProximity, C = 1 cm: every point under a triangle's inside is an active contact, one
// spring each, 0.3 N/m: the bed carries the cube's weight at ~5 mm). The points sit off the
// grid's lines and diagonals (MinProximity drops a projection on a triangle's edge).
std::string cube_on_a_bed_of_points_xml(int quads, int points) {
    std::ostringstream s;
    s << R"(<Node name="root" dt="0.005" gravity="0 -9.81 0">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.02" contactDistance="0.01"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Body">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-15"/>
    <MechanicalObject position="0 0.005 0  0.4 0.005 0  0 0.405 0  0.4 0.405 0  0 0.005 0.4  0.4 0.005 0.4  0 0.405 0.4  0.4 0.405 0.4"
                      velocity="0.01 0 0  0.01 0 0  0.01 0 0  0.01 0 0  0.01 0 0  0.01 0 0  0.01 0 0  0.01 0 0"/>
    <MeshTopology hexas="0 1 3 2 4 5 7 6"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="500" damping="1"/>
    <Node name="Surface">
      <MeshTopology position=")";
    const double h = 0.4 / quads;
    for (int k = 0; k <= quads; ++k)
        for (int i = 0; i <= quads; ++i) s << h * i << " 0.005 " << h * k << "  ";
    s << R"(" triangles=")";
    const auto v = [quads](int i, int k) { return (quads + 1) * k + i; };
    for (int k = 0; k < quads; ++k)  // facing down (−y)
        for (int i = 0; i < quads; ++i)
            s << v(i, k) << ' ' << v(i + 1, k) << ' ' << v(i, k + 1) << "  " << v(i + 1, k) << ' ' << v(i + 1, k + 1)
              << ' ' << v(i, k + 1) << "  ";
    s << R"("/>
      <MechanicalObject/>
      <TriangleCollisionModel contactStiffness="0.0548"/>
      <BarycentricMapping/>
    </Node>
  </Node>
  <Node name="Bed">
    <MechanicalObject position=")";
    const double spacing = 0.4 / points;
    for (int k = 0; k < points; ++k)
        for (int i = 0; i < points; ++i) s << spacing * (i + 0.3) << " 0 " << spacing * (k + 0.3) << "  ";
    s << R"("/>
    <PointCollisionModel simulated="0" moving="0" contactStiffness="0.0548"/>
  </Node>
</Node>
)";
    return s.str();
}

std::unique_ptr<scene::Scene> cube_on_a_bed_of_points(int threads) {
    scene::BuildOptions o;
    o.threads = threads;
    return scene::build_scene(io::parse_scene_string(cube_on_a_bed_of_points_xml(40, 80), "bed_of_points.scn"), o);
}

// The field's springs and its J on threads, its mapping's Jᵀ as gathers: the products through the
// objects, bit for bit, with the block on 4 threads and on 1.
TEST(FusedContactProducts, ALargeFieldOnThreadsGivesTheProductsThroughTheObjects) {
    const auto scene = cube_on_a_bed_of_points(4);
    Node& body = child(scene->simulation().root(), "Body");
    for (int step = 0; step < 3; ++step) scene->step();
    const SubtreeSystem fused(body, true, true), plain(body, true, false);
    ASSERT_EQ(fused.fused_contact_counts().force_fields, 1u);
    ASSERT_GE(active_contacts(fused), 4096u);  // FusedContactBlock::kMinItemsOnThreads
    std::mt19937 rng(20261201);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    long compared = 0, differing = 0;
    for (const int threads : {4, 1, 2}) {
        tbb::task_arena(threads).execute([&] {
            Eigen::VectorXd dx(fused.size());
            for (Eigen::Index i = 0; i < dx.size(); ++i) dx[i] = unit(rng);
            const SubtreeSystem::FixedReaders fixed_f(fused);
            const SubtreeSystem::FixedReaders fixed_p(plain);
            Eigen::VectorXd f, p, fa = dx, pa = dx;
            fused.apply_mbk(dx, f, 1.02, -0.01, -1.01e-4, true);
            plain.apply_mbk(dx, p, 1.02, -0.01, -1.01e-4, true);
            fused.apply_mbk(dx, fa, -0.1, 0.0, 0.05, false, /*accumulate=*/true);
            plain.apply_mbk(dx, pa, -0.1, 0.0, 0.05, false, true);
            for (const auto& [x, y] : {std::pair{&f, &p}, {&fa, &pa}})
                for (Eigen::Index i = 0; i < x->size(); ++i) {
                    ++compared;
                    differing += test::same_bits((*x)[i], (*y)[i]) ? 0 : 1;
                }
            const SubtreeSystem::FusedContactCounts counts = fused.fused_contact_counts();
            EXPECT_EQ(counts.fields_on_threads, threads > 1 ? 1u : 0u) << threads << " threads";
            EXPECT_EQ(counts.gathered_mappings, threads > 1 ? 1u : 0u) << threads << " threads";
        });
    }
    EXPECT_EQ(differing, 0) << "of " << compared;
    EXPECT_EQ(compared, 3 * 2 * fused.size());
}

// Whole runs: the cube's states after 20 steps are the same bits on 1, 2 and 8 threads.
TEST(FusedContactProducts, RunsWithALargeFieldOnThreadsAreTheBitsOfOneThread) {
    std::vector<Vec3> one;
    for (const int threads : test::thread_counts_to_compare({1, 2, 8})) {
        const auto scene = cube_on_a_bed_of_points(threads);
        Node& body = child(scene->simulation().root(), "Body");
        for (int step = 0; step < 20; ++step) scene->step();
        const auto& x = dynamic_cast<const Vec3Object&>(*body.state()).position;
        const auto* solver = dynamic_cast<const EulerImplicitSolver*>(body.ode_solver());
        ASSERT_NE(solver, nullptr);
        ASSERT_NE(solver->system_cache().current(), nullptr);
        const SubtreeSystem::FusedContactCounts counts = solver->system_cache().current()->fused_contact_counts();
        EXPECT_EQ(counts.fields_on_threads, threads > 1 ? 1u : 0u) << threads << " threads";
        EXPECT_EQ(counts.gathered_mappings, threads > 1 ? 1u : 0u) << threads << " threads";
        EXPECT_GT(x[0].y(), 0.0);  // carried by the bed
        if (threads == 1) {
            one = x;
            continue;
        }
        ASSERT_EQ(x.size(), one.size());
        EXPECT_EQ(std::memcmp(x.data(), one.data(), x.size() * sizeof(Vec3)), 0) << threads << " threads";
    }
}

}  // namespace
