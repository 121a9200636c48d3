// CollisionResponse: response names, responseParams, per-model override, "nullptr", registered
// pairs, lifecycle (a pair without outputs for one step is destroyed and recreated from scratch),
// time scales.
#include "penalty/response/collision_response.hpp"

#include "../collision/fixtures.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <string>

namespace penalty {
namespace {

using test::make_state;
using test::named;

struct FloorAndBall {
    std::unique_ptr<test::Mesh> mesh = test::triangle_mesh({{-5, 0, -5}, {5, 0, -5}, {0, 0, 5}}, {{0, 2, 1}});
    Vec3State ball = make_state({{0.2, 0.9, 0.3}});
    TriangleModel floor{mesh->state, mesh->topo, named("floor")};
    SphereModel sphere{ball, 0.5, {}, named("ball")};
    IntersectionParams params = IntersectionParams::new_proximity();
    std::vector<ModelPairDetection> detect() { return {detect_model_pair(params, floor, sphere)}; }
};

TEST(CollisionResponse, NameResolution) {
    Vec3State s = make_state({{0, 0, 0}});
    PointModel a(s, nullptr, named("a")), b(s, nullptr, named("b"));
    CollisionResponse r("PenalityContactForceField", "damping=2");
    EXPECT_EQ(r.response_name(a, b), "PenalityContactForceField?damping=2");
    a.params().contact_response = "nullptr";
    EXPECT_EQ(r.response_name(a, b), "nullptr");
    EXPECT_EQ(r.response_name(b, a), "nullptr");
    b.params().contact_response = "nullptr";
    EXPECT_EQ(r.response_name(a, b), "nullptr");
    b.params().contact_response = "PenalityContactForceField?damping=5";
    EXPECT_EQ(r.response_name(a, b), "PenalityContactForceField?damping=2");  // differ → base
    EXPECT_THROW(CollisionResponse("default"), std::invalid_argument);        // removed in SOFA (§1)
    EXPECT_THROW(CollisionResponse("FrictionContactConstraint"), std::invalid_argument);
    CollisionResponse none("");
    EXPECT_EQ(none.warnings().size(), 1u);
}

TEST(CollisionResponse, RegisteredPairsAreOrdered) {
    int n = 0;
    for (int i = 0; i < kModelTypeCount; ++i)
        for (int j = 0; j < kModelTypeCount; ++j) n += is_penalty_response_pair(ModelType(i), ModelType(j));
    EXPECT_EQ(n, 24);
    EXPECT_TRUE(is_penalty_response_pair(ModelType::Triangle, ModelType::Sphere));
    EXPECT_FALSE(is_penalty_response_pair(ModelType::Sphere, ModelType::Triangle));  // never swapped
    EXPECT_TRUE(is_penalty_response_pair(ModelType::Tetrahedron, ModelType::Tetrahedron));
    EXPECT_TRUE(is_penalty_response_pair(ModelType::Cylinder, ModelType::Triangle));
    EXPECT_FALSE(is_penalty_response_pair(ModelType::Point, ModelType::Line));
    // every pair SOFA's intersectors emit in registered order has its response
    for (int i = 0; i < kModelTypeCount; ++i)
        for (int j = 0; j < kModelTypeCount; ++j) {
            const auto a = ModelType(i), b = ModelType(j);
            if (!is_registered_order(a, b)) continue;
            bool any = false;
            for (auto p : {IntersectionParams::new_proximity(), IntersectionParams::min_proximity(),
                           IntersectionParams::local_min_distance(), IntersectionParams::discrete()})
                any |= pair_support(p, a, b) == PairSupport::Supported;
            if (any) {
                EXPECT_TRUE(is_penalty_response_pair(a, b)) << model_type_name(a) << "-" << model_type_name(b);
            }
        }
}

TEST(CollisionResponse, ResponseParamsParsing) {
    ContactResponseParameters p;
    std::vector<std::string> unknown;
    apply_response_params(
        "damping=0.5&friction=coulomb&tangentialStiffnessRatio=0.8&tangentialDamping=0.1&"
        "timeStep=0.005&stiffnessLaw=physical&rigidSphereRadius=v26.06&mu=0.3",
        p, &unknown);
    EXPECT_EQ(p.penalty.damping, 0.5);
    EXPECT_EQ(p.penalty.friction, FrictionModel::coulomb);
    EXPECT_EQ(p.penalty.tangential_stiffness_ratio, 0.8);
    EXPECT_EQ(p.penalty.tangential_damping, 0.1);
    EXPECT_EQ(p.penalty.time_step, 0.005);
    EXPECT_EQ(p.stiffness_law, StiffnessLaw::physical);
    EXPECT_EQ(p.rigid_sphere_radius, RigidSphereRadius::sofa_v26_06);
    ASSERT_EQ(unknown.size(), 1u);
    EXPECT_EQ(unknown[0], "mu");
    auto throws_naming = [](const char* s, const char* what) {
        ContactResponseParameters q;
        try {
            apply_response_params(s, q);
            ADD_FAILURE() << s;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    throws_naming("damping=abc", "damping");
    throws_naming("damping=-1", "damping");
    throws_naming("damping", "damping");
    throws_naming("stiffnessLaw=si", "stiffnessLaw");
    throws_naming("friction=yes", "friction");
    EXPECT_THROW(CollisionResponse("PenalityContactForceField", "damping=x"), std::invalid_argument);
}

TEST(CollisionResponse, ParamsReachTheForceFieldAndCppBase) {
    FloorAndBall s;
    ContactResponseParameters base;
    base.penalty.damping = 3.0;  // C++ API
    CollisionResponse r("PenalityContactForceField", "stiffnessLaw=physical", base);
    r.set_detections(s.detect(), s.params.contact_distance);
    ASSERT_EQ(r.pairs().size(), 1u);
    auto* c = r.find(s.floor, s.sphere);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->parameters().penalty.damping, 3.0);
    EXPECT_EQ(c->force_field().parameters().damping, 3.0);
    EXPECT_EQ(c->parameters().stiffness_law, StiffnessLaw::physical);
    ASSERT_EQ(c->force_field().size(), 1u);
    EXPECT_DOUBLE_EQ(c->force_field().contacts()[0].ks, 5.0);  // 10·10/(10+10)
    // time scale: mass 1 on the ball, static floor → sqrt(1/5)
    const auto ts = r.time_scales(
        [&](const CollisionModel& m) { return &m == &s.sphere ? 1.0 : std::numeric_limits<double>::infinity(); });
    ASSERT_EQ(ts.size(), 1u);
    EXPECT_EQ(ts[0].type1, ModelType::Triangle);
    EXPECT_EQ(ts[0].type2, ModelType::Sphere);
    EXPECT_DOUBLE_EQ(ts[0].critical_time_step, std::sqrt(0.2));
}

TEST(CollisionResponse, NullptrDisablesAPair) {
    FloorAndBall s;
    s.sphere.params().contact_response = "nullptr";
    CollisionResponse r;
    r.set_detections(s.detect(), s.params.contact_distance);
    ASSERT_EQ(r.pairs().size(), 1u);
    EXPECT_EQ(r.pairs()[0].contact, nullptr);
    EXPECT_EQ(r.find(s.floor, s.sphere), nullptr);
    CollisionResponse off("nullptr");
    off.set_detections(s.detect(), s.params.contact_distance);
    EXPECT_EQ(off.find(s.floor, s.sphere), nullptr);
}

TEST(CollisionResponse, UnregisteredPairWarnsAndCreatesNothing) {
    Vec3State s = make_state({{0, 0, 0}, {1, 0, 0}});
    MeshTopology topo;
    topo.set_edges({{0, 1}});
    PointModel p(s, nullptr, named("pts"));
    LineModel l(s, topo, named("lines"));
    CollisionResponse r;
    EXPECT_EQ(r.create_contact(std::string(kPenaltyResponseName), p, l, 0.5), nullptr);  // Point–Line: swapped
    ASSERT_EQ(r.warnings().size(), 1u);
    EXPECT_NE(r.warnings()[0].find("pts"), std::string::npos);
    EXPECT_NE(r.create_contact(std::string(kPenaltyResponseName), l, p, 0.5), nullptr);
    EXPECT_THROW((void)r.create_contact("Other", l, p, 0.5), std::invalid_argument);
}

TEST(CollisionResponse, PairDestroyedWhenOutputsVanishAndRecreatedFromScratch) {
    FloorAndBall s;
    CollisionResponse r;
    int created = 0, destroyed = 0;
    r.on_create = [&](BarycentricPenaltyContact&) { ++created; };
    r.on_destroy = [&](BarycentricPenaltyContact&) { ++destroyed; };
    const BarycentricPenaltyContact* first = nullptr;
    for (int step = 0; step < 3; ++step) {
        r.set_detections(s.detect(), s.params.contact_distance);
        auto* c = r.find(s.floor, s.sphere);
        ASSERT_NE(c, nullptr);
        if (!first) first = c;
        EXPECT_EQ(c, first);  // one persistent contact per pair
        EXPECT_EQ(c->force_field().contacts()[0].age, step);
    }
    EXPECT_EQ(created, 1);
    s.ball.position[0].y() = 10.0;  // no output for one step
    r.set_detections(s.detect(), s.params.contact_distance);
    EXPECT_EQ(r.pairs().size(), 0u);
    EXPECT_EQ(destroyed, 1);
    s.ball.position[0].y() = 0.9;
    r.set_detections(s.detect(), s.params.contact_distance);
    auto* c = r.find(s.floor, s.sphere);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(created, 2);
    EXPECT_EQ(c->force_field().contacts()[0].age, 0);
    EXPECT_EQ(c->force_field().previous_contacts().size(), 0u);  // fresh force field
    r.clear();
    EXPECT_EQ(destroyed, 2);
}

// Four point clouds of 160 points hovering over a floor triangle: four pairs of 160 outputs, so
// set_detections feeds the contacts in parallel in an arena of two threads.
struct FloorAndClouds {
    std::unique_ptr<test::Mesh> mesh = test::triangle_mesh({{-5, 0, -5}, {5, 0, -5}, {0, 0, 5}}, {{0, 2, 1}});
    TriangleModel floor{mesh->state, mesh->topo, named("floor")};
    std::vector<Vec3State> states;
    std::vector<std::unique_ptr<PointModel>> clouds;
    IntersectionParams params = IntersectionParams::new_proximity();
    FloorAndClouds() {
        states.reserve(4);
        for (int c = 0; c < 4; ++c) {
            std::vector<Vec3> pts;
            for (int i = 0; i < 160; ++i)
                pts.emplace_back(-2.0 + 0.025 * i, 0.01 * (1 + c) + 0.00025 * i, 0.3 * c - 0.5);
            states.push_back(make_state(pts));
        }
        for (int c = 0; c < 4; ++c) {
            const std::string name = "cloud" + std::to_string(c);
            clouds.push_back(std::make_unique<PointModel>(states[std::size_t(c)], nullptr, named(name.c_str())));
        }
    }
    std::vector<ModelPairDetection> detect() {
        std::vector<ModelPairDetection> d;
        for (auto& c : clouds) d.push_back(detect_model_pair(params, floor, *c));
        return d;
    }
};

struct FedContacts {
    bool concurrent = false;
    std::vector<std::vector<PenaltyContact>> contacts;  // per cloud
    std::string error;
};

FedContacts feed(int threads, const std::vector<ModelPairDetection>& detections, FloorAndClouds& s) {
    const tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    tbb::task_arena arena(threads);
    FedContacts r;
    arena.execute([&] {
        CollisionResponse response;
        try {
            for (int step = 0; step < 2; ++step) response.set_detections(detections, s.params.contact_distance);
        } catch (const std::invalid_argument& e) {
            r.error = e.what();
        }
        r.concurrent = response.last_feed_concurrent();
        for (auto& c : s.clouds) {
            const BarycentricPenaltyContact* contact = response.find(s.floor, *c);
            r.contacts.emplace_back();
            if (contact)
                r.contacts.back().assign(contact->force_field().contacts().begin(),
                                         contact->force_field().contacts().end());
        }
    });
    return r;
}

TEST(CollisionResponse, ContactsFedInParallelAreThoseOfOneThreadAndTheFirstErrorInOrderIsRaised) {
    FloorAndClouds s;
    const std::vector<ModelPairDetection> detections = s.detect();
    for (const auto& d : detections) ASSERT_EQ(d.outputs.size(), 160u);
    const FedContacts one = feed(1, detections, s);
    const FedContacts two = feed(2, detections, s);
    EXPECT_FALSE(one.concurrent);
    EXPECT_TRUE(two.concurrent);
    ASSERT_EQ(one.contacts.size(), 4u);
    for (std::size_t c = 0; c < 4; ++c) {
        ASSERT_EQ(one.contacts[c].size(), 160u);
        ASSERT_EQ(two.contacts[c].size(), 160u);
        for (std::size_t i = 0; i < 160; ++i) {
            const PenaltyContact &a = one.contacts[c][i], &b = two.contacts[c][i];
            EXPECT_TRUE(a.m1 == b.m1 && a.m2 == b.m2 && a.index1 == b.index1 && a.index2 == b.index2 && a.age == b.age);
            EXPECT_TRUE(test::same_bits(a.normal, b.normal) && test::same_bits(a.dist, b.dist) &&
                        test::same_bits(a.ks, b.ks));
        }
        EXPECT_EQ(one.contacts[c][5].age, 1);  // tracked over the two steps
    }
    // outputs naming points that do not exist, in the second and fourth pairs: the second
    // pair's error, with one thread or two
    std::vector<ModelPairDetection> bad = detections;
    bad[1].outputs[7].elem2 = ElementIndex(1000);
    bad[3].outputs[2].elem2 = ElementIndex(2000);
    const FedContacts one_bad = feed(1, bad, s);
    EXPECT_NE(one_bad.error.find("'cloud1' (Point): element 1000 out of range"), std::string::npos) << one_bad.error;
    for (int round = 0; round < 20; ++round) {
        const FedContacts two_bad = feed(2, bad, s);
        ASSERT_EQ(two_bad.error, one_bad.error);
    }
}

}  // namespace
}  // namespace penalty
