// The broad phase (collision/broad_phase.cpp): SOFA's BruteForceBroadPhase order and filters.
#include "collision/broad_phase.hpp"
#include "pipeline_references.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <random>

namespace penalty {
namespace {

using namespace test_pipeline;

TEST(BroadPhase, FollowsBruteForceBroadPhaseOrderAndFilters) {
    std::mt19937 g(11);
    Vec3State s = random_cloud(10, 1.0, g);
    auto tm = test::make_torus(8, 6, 0.5, 0.2, Vec3::Zero(), g);
    SphereModel a(s, 0.1, {}, mp("a", 0, true));             // self pair
    TriangleModel t(tm->state, tm->topo, mp("t", 1, true));  // self pair (Triangle-Triangle NP)
    PointModel p(tm->state, &tm->topo, mp("p", 1, true));    // same node as t: kept (self_collision)
    SphereModel off(s, 0.1, {}, mp("off"));
    off.params().active = false;
    SphereModel ns1(s, 0.1, {}, mp("ns1", 5, true));
    ns1.params().simulated = false;  // no self pair (non-simulated)
    SphereModel ns2(s, 0.1, {}, mp("ns2"));
    ns2.params().simulated = false;  // ns1-ns2 never pair
    SphereModel g1(s, 0.1, {}, mp("g1", -1, false, {4, 7}));
    SphereModel g2(s, 0.1, {}, mp("g2", -1, false, {7}));     // shares group 7 with g1
    PointModel p2(tm->state, &tm->topo, mp("p2", 1, false));  // same node as t, self_collision off
    std::vector<CollisionModel*> models = {&a, &t, &p, &off, &ns1, &ns2, &g1, &g2, &p2};
    std::vector<ModelPair> pairs, unsupported;
    broad_phase(IntersectionParams::new_proximity(), models, pairs, &unsupported);
    std::vector<std::string> got;
    for (const auto& q : pairs) got.push_back(q.model1->name() + "-" + q.model2->name());
    // SOFA's BruteForceBroadPhase::addCollisionModel: per model j, the self pair first, then the
    // earlier models in order; each pair (model j, earlier model) swapped only into registered
    // order (Triangle before Sphere and Point, Sphere before Point), so two models of one type
    // are keyed (later, earlier)
    const std::vector<std::string> expected = {"a-a",    "t-t",    "t-a",    "p-p",    "a-p",   "t-p",  "ns1-a",
                                               "t-ns1",  "ns1-p",  "ns2-a",  "t-ns2",  "ns2-p", "g1-a", "t-g1",
                                               "g1-p",   "g1-ns1", "g1-ns2", "g2-a",   "t-g2",  "g2-p", "g2-ns1",
                                               "g2-ns2", "a-p2",   "ns1-p2", "ns2-p2", "g1-p2", "g2-p2"};
    EXPECT_EQ(got, expected);
    EXPECT_TRUE(unsupported.empty());  // NewProximity detects every pair of these types
    // `indices`: the places (ModelIndex) of each pair's model1 and model2 in `models`, swapped
    // with the pair ("t-a": t is model 1, a model 0)
    std::vector<std::array<ModelIndex, 2>> places;
    broad_phase(IntersectionParams::new_proximity(), models, pairs, nullptr, &places);
    ASSERT_EQ(places.size(), expected.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        EXPECT_EQ(models[places[k][0].slot()], pairs[k].model1) << got[k];
        EXPECT_EQ(models[places[k][1].slot()], pairs[k].model2) << got[k];
    }
    EXPECT_EQ(places[2][0], ModelIndex(1));
    EXPECT_EQ(places[2][1], ModelIndex(0));
    EXPECT_EQ(places[4][0], ModelIndex(0));  // "a-p": p (place 2) added later, swapped into registered order
    EXPECT_EQ(places[4][1], ModelIndex(2));
    // MinProximity ignores Triangle-Triangle: the kept pair goes to `unsupported`, not `pairs`
    broad_phase(IntersectionParams::min_proximity(), models, pairs, &unsupported);
    ASSERT_EQ(unsupported.size(), 1u);
    EXPECT_EQ(unsupported[0], (ModelPair{&t, &t}));
    EXPECT_EQ(pairs.size(), expected.size() - 1);
}

TEST(BroadPhase, SofaPairOrderIsEachPairsPlaceAmongEveryPair) {
    // nine models of three types, every pair kept: the k-th pair of broad_phase() is the pair of
    // places j >= i with sofa_pair_order(j, i) == k, whichever model is model 1; filtering pairs
    // out keeps the order of the others increasing
    std::mt19937 g(5);
    Vec3State s = random_cloud(4, 1.0, g);
    auto tm = test::make_torus(6, 4, 0.5, 0.2, Vec3::Zero(), g);
    std::vector<std::unique_ptr<CollisionModel>> owned;
    std::vector<CollisionModel*> models;
    const std::vector<std::string> names = {"s0", "t1", "p2", "s3", "t4", "p5", "s6", "t7", "p8"};
    for (std::size_t m = 0; m < names.size(); ++m) {
        const CollisionModelParams params = mp(names[m].c_str(), int(m), true);
        if (m % 3 == 0) owned.push_back(std::make_unique<SphereModel>(s, 0.1, std::vector<double>{}, params));
        else if (m % 3 == 1) owned.push_back(std::make_unique<TriangleModel>(tm->state, tm->topo, params));
        else owned.push_back(std::make_unique<PointModel>(tm->state, &tm->topo, params));
        models.push_back(owned.back().get());
    }
    std::vector<ModelPair> pairs;
    std::vector<std::array<ModelIndex, 2>> places;
    broad_phase(IntersectionParams::new_proximity(), models, pairs, nullptr, &places);
    ASSERT_EQ(pairs.size(), 45u);
    for (std::size_t k = 0; k < places.size(); ++k) {
        const std::size_t j = std::max(places[k][0], places[k][1]).slot();
        const std::size_t i = std::min(places[k][0], places[k][1]).slot();
        EXPECT_EQ(detail::sofa_pair_order(j, i), k) << pairs[k].model1->name() << "-" << pairs[k].model2->name();
    }
    EXPECT_EQ(detail::sofa_pair_order(0, 0), 0u);
    EXPECT_EQ(detail::sofa_pair_order(3, 3), 6u);  // after (0,0) (1,1) (1,0) (2,2) (2,0) (2,1)
    EXPECT_EQ(detail::sofa_pair_order(3, 0), 7u);
    EXPECT_EQ(detail::sofa_pair_order(100000, 99999), 5000150000u);  // past 32 bits
    // groups filter pairs out: the orders of the kept ones still increase
    owned[4]->params().group = {1};
    owned[7]->params().group = {1};
    broad_phase(IntersectionParams::new_proximity(), models, pairs, nullptr, &places);
    ASSERT_EQ(pairs.size(), 44u);
    for (std::size_t k = 1; k < places.size(); ++k) {
        const auto order = [&](std::size_t q) {
            return detail::sofa_pair_order(std::max(places[q][0], places[q][1]).slot(),
                                           std::min(places[q][0], places[q][1]).slot());
        };
        EXPECT_LT(order(k - 1), order(k));
    }
}

// ---------------------------------------------------------------------------------------------
// Narrow phase: equality with the exhaustive loop

}  // namespace
}  // namespace penalty
