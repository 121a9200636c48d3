// CollisionResponse: response names, responseParams, per-model override, "nullptr", registered
// pairs, lifecycle (a pair without outputs for one step is destroyed and recreated from scratch),
// time scales.
#include "penalty/response/collision_response.hpp"

#include "../collision/fixtures.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

using test::make_state;
using test::named;

struct FloorAndBall {
    std::unique_ptr<test::Mesh> mesh =
        test::triangle_mesh({{-5, 0, -5}, {5, 0, -5}, {0, 0, 5}}, {{0, 2, 1}});
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
    EXPECT_THROW(CollisionResponse("default"), std::invalid_argument);  // removed in SOFA (§1)
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
    apply_response_params("damping=0.5&friction=coulomb&tangentialStiffnessRatio=0.8&tangentialDamping=0.1&"
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
    const auto ts = r.time_scales([&](const CollisionModel& m) {
        return &m == &s.sphere ? 1.0 : std::numeric_limits<double>::infinity();
    });
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

}  // namespace
}  // namespace penalty
