// SubtreeSystem's products in chains on TBB's threads (src/simulation/step_chains.hpp): a pile of
// 125 FEM cubes in a bowl under one solver has about 300 force steps a product (more than
// SubtreeSystem::kMinStepsForConcurrentProducts) in 125 chains of disjoint written states, so
// under a FixedReaders its products run concurrently (the first one finding each mapped state's
// read rows in its chain). Every result must be the bits of the same product
// on one thread, and a whole run the same state files at 1, 2 and 8 threads.
#include "penalty/io/scene_file.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/cubes_in_bowl.hpp"
#include "penalty_test/same_bits.hpp"
#include "penalty_test/sanitizer.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace penalty;
namespace bowl = penalty::test::cubes_in_bowl;

// Under the sanitizers (about 40× slower) the pile starts with its corner cubes 2 mm from the bowl
// instead of 20, so that contacts come within the first steps, and runs fewer steps: the same
// products in chains, checked for memory errors; the release suite runs the settled pile.
constexpr bool kShortPile = test::kUnderSanitizer;
constexpr int kStepsToContact = kShortPile ? 30 : 150;

std::unique_ptr<scene::Scene> pile(int threads) {
    bowl::Setup s;
    s.k = 5;
    if (kShortPile) s.clearance = 0.002;
    scene::BuildOptions options;
    options.threads = threads;
    return scene::build_scene(io::parse_scene_string(bowl::scene_xml(s), "cubes_in_bowl_k5.scn"), options);
}

Node& cubes_node(scene::Scene& s) {
    for (const auto& child : s.simulation().root().children())
        if (child->name() == "Cubes") return *child;
    throw std::logic_error("no /Cubes node");
}

std::vector<double> flat_positions(const scene::Scene& s) {
    std::vector<double> out;
    for (const auto& r : s.states())
        if (const auto* v = dynamic_cast<const Vec3Object*>(r.state))
            for (const Vec3& p : v->position) out.insert(out.end(), {p.x(), p.y(), p.z()});
    return out;
}

TEST(ConcurrentProducts, ProductsInChainsAreTheBitsOfOneThread) {
    auto scene = pile(1);
    for (int i = 0; i < kStepsToContact; ++i) scene->step();  // the cubes touch the bowl (and each other)
    const SubtreeSystem system(cubes_node(*scene), true, true);
    ASSERT_GE(system.product_chains(), 8u);
    ASSERT_FALSE(scene->contacts().empty());
    std::mt19937 rng(54);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    long compared = 0, differing = 0;
    for (int trial = 0; trial < 4; ++trial) {
        Eigen::VectorXd dx(system.size());
        for (Eigen::Index i = 0; i < dx.size(); ++i) dx[i] = unit(rng);
        const double m = 1.02, b = -0.01, k = -1.01e-4;  // an implicit-Euler operator
        Eigen::VectorXd one, many, first_many;
        {
            const SubtreeSystem::FixedReaders fixed(system);
            tbb::task_arena(1).execute([&] {
                Eigen::VectorXd first;
                system.apply_mbk(dx, first, m, b, k, true);  // finds the read rows
                system.apply_mbk(dx, one, m, b, k, true);
            });
            const std::size_t before = system.concurrent_products();
            tbb::task_arena(4).execute([&] { system.apply_mbk(dx, many, m, b, k, true); });
            EXPECT_EQ(system.concurrent_products(), before + 1) << "the product did not run in chains";
        }
        {
            // a new solve's first product finds the read rows in its chains, each with its
            // thread's row lists
            const SubtreeSystem::FixedReaders fixed(system);
            const std::size_t before = system.concurrent_products();
            tbb::task_arena(4).execute([&] { system.apply_mbk(dx, first_many, m, b, k, true); });
            EXPECT_EQ(system.concurrent_products(), before + 1) << "the first product did not run in chains";
        }
        ASSERT_EQ(one.size(), many.size());
        ASSERT_EQ(one.size(), first_many.size());
        for (Eigen::Index i = 0; i < one.size(); ++i) {
            compared += 2;
            differing += (test::same_bits(one[i], many[i]) ? 0 : 1) + (test::same_bits(one[i], first_many[i]) ? 0 : 1);
        }
    }
    EXPECT_EQ(differing, 0) << "of " << compared;
}

// compute_force runs the same chains: its force vector, at the pile's state, is the bits of one
// thread's.
TEST(ConcurrentProducts, ForceEvaluationsInChainsAreTheBitsOfOneThread) {
    auto scene = pile(1);
    for (int i = 0; i < kStepsToContact; ++i) scene->step();
    const SubtreeSystem system(cubes_node(*scene), true, true);
    ASSERT_GE(system.product_chains(), 8u);
    Eigen::VectorXd one, many;
    tbb::task_arena(1).execute([&] { system.compute_force(one); });
    EXPECT_EQ(system.concurrent_force_evaluations(), 0u);
    tbb::task_arena(4).execute([&] { system.compute_force(many); });
    EXPECT_EQ(system.concurrent_force_evaluations(), 1u) << "the forces were not computed in chains";
    ASSERT_EQ(one.size(), many.size());
    long differing = 0;
    for (Eigen::Index i = 0; i < one.size(); ++i) differing += test::same_bits(one[i], many[i]) ? 0 : 1;
    EXPECT_EQ(differing, 0) << "of " << one.size();
    EXPECT_GT(one.norm(), 0.0);
}

// The contacts are fed, and their contact states sized (ContactPipeline::init_contact_states),
// in parallel at two threads and more, and the map-back plan is built beside the solve plan.
TEST(ConcurrentProducts, RunsAreTheSameBitsAtOneTwoAndEightThreads) {
    // Under the sanitizers one and eight threads only; the release suite compares all three.
    const std::vector<int> thread_counts = test::thread_counts_to_compare({1, 2, 8});
    std::vector<std::vector<double>> runs;
    for (const int threads : thread_counts) {
        auto scene = pile(threads);
        int concurrent_feeds = 0;
        for (int i = 0; i < kStepsToContact + 30; ++i) {
            scene->step();
            concurrent_feeds += scene->pipelines().at(0).pipeline->response().last_feed_concurrent() ? 1 : 0;
        }
        // contacts come and go: the map-back plan is built again beside the solve plan
        const std::size_t map_back_builds = scene->simulation().concurrent_map_back_builds();
        if (threads == 1) {
            EXPECT_EQ(concurrent_feeds, 0);
            EXPECT_EQ(map_back_builds, 0u);
        } else {
            EXPECT_GT(concurrent_feeds, 10) << threads << " threads";
            EXPECT_GT(map_back_builds, 10u) << threads << " threads";
        }
        runs.push_back(flat_positions(*scene));
    }
    for (std::size_t r = 1; r < runs.size(); ++r) {
        ASSERT_EQ(runs[r].size(), runs[0].size());
        long differing = 0;
        for (std::size_t i = 0; i < runs[0].size(); ++i) differing += test::same_bits(runs[0][i], runs[r][i]) ? 0 : 1;
        EXPECT_EQ(differing, 0) << "run " << r;
    }
}

}  // namespace
