// Simulation::map_back in waves (src/simulation/map_back_plan.hpp): a mapping waits for the
// mappings that write what it reads, for the earlier readers of what it writes, and for every
// node with a projective constraint; the mappings of a wave run at once with more than one thread
// and the states are the same bits as the depth-first pass's.

#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/simulation/simulation.hpp"
#include "simulation/map_back_plan.hpp"

#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

namespace penalty {
namespace {

Vec3Object& add_points(Node& node, std::vector<Vec3> positions) {
    auto& x = node.add_state<Vec3Types>(node.name());
    x.velocity.assign(positions.size(), Vec3::Zero());  // sized before init: c maps b's state before b's init
    x.position = std::move(positions);
    return x;
}

TEST(MapBackWaves, AMappingWaitsForItsInputsWriterItsOutputsEarlierReaderAndEveryConstraint) {
    Simulation sim;
    Node& root = sim.root();
    auto& body = add_points(root, {Vec3(1, 2, 3), Vec3(4, 5, 6)});
    Node& a = root.add_child("a");
    auto& ax = add_points(a, {Vec3::Zero(), Vec3::Zero()});
    a.set_mapping<IdentityMapping>(body, ax);
    Node& a1 = a.add_child("a1");  // reads a's output: after a
    auto& a1x = add_points(a1, {Vec3::Zero(), Vec3::Zero()});
    a1.set_mapping<IdentityMapping>(ax, a1x);
    Node& c = root.add_child("c");  // reads b's state before b maps it (depth first): b after c
    auto& cx = add_points(c, {Vec3::Zero(), Vec3::Zero()});
    Node& b = root.add_child("b");
    auto& bx = add_points(b, {Vec3(-7, -8, -9), Vec3(-1, -1, -1)});
    c.set_mapping<IdentityMapping>(bx, cx);
    b.set_mapping<IdentityMapping>(body, bx);
    Node& k = root.add_child("k");  // a constraint: a wave of its own
    auto& kx = add_points(k, {Vec3::Zero()});
    k.add_constraint<FixedProjectiveConstraint>(kx).set_fix_all(true);
    Node& d = root.add_child("d");  // after the constraint, although it reads only the body
    auto& dx = add_points(d, {Vec3::Zero(), Vec3::Zero()});
    d.set_mapping<IdentityMapping>(body, dx);
    sim.init();

    detail::MapBackPlan plan;
    plan.update(root);
    std::vector<std::vector<const Node*>> waves;
    for (std::size_t w = 0; w < plan.waves(); ++w) waves.push_back(plan.wave_nodes(w));
    const std::vector<std::vector<const Node*>> expected = {{&a, &c}, {&a1, &b}, {&k}, {&d}};
    EXPECT_EQ(waves, expected);

    // c reads b's positions of before b's mapping, as the depth-first pass does
    bx.position = {Vec3(-7, -8, -9), Vec3(-1, -1, -1)};
    for (const int threads : {1, 4}) {
        sim.set_threads(threads);
        sim.map_back();
        EXPECT_EQ(cx.position[0], Vec3(-7, -8, -9)) << threads << " threads";
        EXPECT_EQ(bx.position[1], Vec3(4, 5, 6)) << threads << " threads";
        EXPECT_EQ(a1x.position[1], Vec3(4, 5, 6)) << threads << " threads";
        bx.position = {Vec3(-7, -8, -9), Vec3(-1, -1, -1)};
    }
}

/// A body of 500 points and 400 contact-like children (4 barycentric points each), each with a
/// mapped grandchild: two waves of 400 mappings.
struct ManyMappedStates {
    Simulation sim;
    std::vector<Vec3Object*> mapped;

    ManyMappedStates() {
        std::mt19937 rng(54);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        std::uniform_int_distribution<Index> point(0, 499);
        Node& root = sim.root();
        std::vector<Vec3> positions(500);
        for (Vec3& p : positions) p = Vec3(u(rng), u(rng), u(rng));
        auto& body = add_points(root, positions);
        body.velocity.assign(500, Vec3(0.5, -0.25, 0.125));
        for (int i = 0; i < 400; ++i) {
            Node& child = root.add_child("contact" + std::to_string(i));
            auto& cx = add_points(child, std::vector<Vec3>(4, Vec3::Zero()));
            std::vector<std::vector<BarycentricMapping::Entry>> rows(4);
            for (auto& row : rows)
                for (int e = 0; e < 3; ++e) row.push_back({point(rng), 0.1 + 0.3 * std::abs(u(rng))});
            child.set_mapping<BarycentricMapping>(body, cx).set_weights(rows);
            Node& grandchild = child.add_child("point" + std::to_string(i));
            auto& gx = add_points(grandchild, {Vec3::Zero()});
            grandchild.set_mapping<BarycentricMapping>(cx, gx).set_weights({{{0, 0.3}, {3, 0.7}}});
            mapped.push_back(&cx);
            mapped.push_back(&gx);
        }
        sim.init();
    }
};

TEST(MapBackWaves, ManyMappingsAreTheSameBitsAtAnyThreadCount) {
    ManyMappedStates one;
    one.sim.set_threads(1);
    one.sim.map_back();
    detail::MapBackPlan plan;
    plan.update(one.sim.root());
    ASSERT_EQ(plan.waves(), 2u);  // the children, then the grandchildren: tasks at 2 and 8 threads
    EXPECT_EQ(plan.wave_nodes(0).size(), 400u);
    EXPECT_GE(plan.wave_nodes(1).size(), detail::kMinStepsForConcurrentMapBack);
    for (const int threads : {2, 8}) {
        ManyMappedStates many;
        many.sim.set_threads(threads);
        many.sim.map_back();
        for (std::size_t s = 0; s < one.mapped.size(); ++s) {
            for (std::size_t i = 0; i < one.mapped[s]->position.size(); ++i) {
                ASSERT_TRUE(test::same_bits(one.mapped[s]->position[i], many.mapped[s]->position[i]))
                    << threads << " threads, state " << s << " point " << i;
                ASSERT_TRUE(test::same_bits(one.mapped[s]->velocity[i], many.mapped[s]->velocity[i]))
                    << threads << " threads, state " << s << " point " << i;
            }
        }
        EXPECT_NE(one.mapped.back()->position[0], Vec3::Zero());  // mapped, not left as made
    }
}

}  // namespace
}  // namespace penalty
