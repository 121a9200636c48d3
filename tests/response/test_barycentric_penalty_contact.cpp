// BarycentricPenaltyContact end to end: detection (exhaustive narrow phase) -> response ->
// forces on the DOFs. Worked examples A, B, D of spec §11, contact age, stiffness laws.
#include "penalty/response/barycentric_penalty_contact.hpp"

#include "../collision/fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

using test::make_rigid_state;
using test::make_state;
using test::named;

CollisionModelParams with_k(const char* name, double k, double cd = 0.0) {
    CollisionModelParams p = named(name);
    p.contact_stiffness = k;
    p.contact_distance = cd;
    return p;
}

// ---------------------------------------------------------------- worked example A

TEST(BarycentricPenaltyContact, WorkedExampleA_TriangleSphereEndToEnd) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo, with_k("tri", 10));
    Vec3State ball = make_state({{0.25, 0.25, 0.8}});
    SphereModel sph(ball, 0.5, {}, with_k("ball", 10));
    const auto params = IntersectionParams::new_proximity();
    auto det = detect_model_pair(params, tri, sph);
    ASSERT_EQ(det.model1, &tri);
    ASSERT_EQ(det.outputs.size(), 1u);

    BarycentricPenaltyContact c(tri, sph, params.contact_distance);
    c.set_detection_outputs(det.outputs);
    ASSERT_EQ(c.force_field().size(), 1u);
    const PenaltyContact& pc = c.force_field().contacts()[0];
    EXPECT_DOUBLE_EQ(pc.dist, 1.0);
    EXPECT_DOUBLE_EQ(pc.ks, 100.0);
    EXPECT_EQ(pc.m1, 0);
    EXPECT_EQ(pc.m2, 0);  // identity: the sphere DOF itself
    EXPECT_EQ(pc.age, 0);
    EXPECT_EQ(pc.normal, Vec3(0, 0, 1));
    // contact point on the triangle: weights (0.5, 0.25, 0.25)
    const auto& bm = dynamic_cast<const BarycentricContactMapper&>(c.mapper1());
    ASSERT_EQ(bm.rows().size(), 1u);
    EXPECT_DOUBLE_EQ(bm.rows()[0][0].weight, 0.5);
    EXPECT_DOUBLE_EQ(bm.rows()[0][1].weight, 0.25);
    EXPECT_DOUBLE_EQ(bm.rows()[0][2].weight, 0.25);
    EXPECT_TRUE(c.mapper1().positions()[0].isApprox(Vec3(0.25, 0.25, 0)));

    std::vector<Vec3> f_tri(3, Vec3::Zero()), f_ball(1, Vec3::Zero());
    c.add_force(flat_span(f_tri), flat_span(f_ball));
    EXPECT_NEAR(c.force_field().contacts()[0].pen, 0.2, 1e-15);
    EXPECT_NEAR((f_ball[0] - Vec3(0, 0, 20)).norm(), 0.0, 1e-13);
    EXPECT_NEAR((f_tri[0] - Vec3(0, 0, -10)).norm(), 0.0, 1e-13);
    EXPECT_NEAR((f_tri[1] - Vec3(0, 0, -5)).norm(), 0.0, 1e-13);
    EXPECT_NEAR((f_tri[2] - Vec3(0, 0, -5)).norm(), 0.0, 1e-13);
}

// ---------------------------------------------------------------- worked example B

struct ExampleB {
    std::unique_ptr<test::Mesh> mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    Rigid3State body = make_rigid_state({RigidFrame{Vec3(0.25, 0.25, 0.8), Quat::Identity()}});
    TriangleModel tri{mesh->state, mesh->topo, with_k("tri", 10)};
    RigidSphereModel sph{body, 0.5, {}, with_k("rigid ball", 10)};
};

TEST(BarycentricPenaltyContact, WorkedExampleB_RigidSphereHeadAndV2606) {
    for (RigidSphereRadius rule : {RigidSphereRadius::sofa_head, RigidSphereRadius::sofa_v26_06}) {
        ExampleB s;
        const auto params = IntersectionParams::new_proximity();
        auto det = detect_model_pair(params, s.tri, s.sph);
        ASSERT_EQ(det.outputs.size(), 1u);
        ContactResponseParameters rp;
        rp.rigid_sphere_radius = rule;
        BarycentricPenaltyContact c(s.tri, s.sph, params.contact_distance, rp);
        c.set_detection_outputs(det.outputs);
        const auto& rm = dynamic_cast<const RigidContactMapper&>(c.mapper2());
        ASSERT_EQ(rm.points().size(), 1u);
        EXPECT_NEAR((rm.points()[0].local - Vec3(0, 0, -0.5)).norm(), 0.0, 1e-15);
        std::vector<Vec3> f_tri(3, Vec3::Zero());
        std::vector<RigidDeriv> f_body(1);
        c.add_force(flat_span(f_tri), flat_span(f_body));
        const PenaltyContact& pc = c.force_field().contacts()[0];
        const bool head = rule == RigidSphereRadius::sofa_head;
        EXPECT_DOUBLE_EQ(pc.dist, head ? 1.0 : 0.5);
        EXPECT_DOUBLE_EQ(pc.ks, head ? 100.0 : 200.0);
        EXPECT_NEAR(pc.pen, head ? 0.7 : 0.2, 1e-15);
        const double mag = head ? 70.0 : 40.0;
        EXPECT_NEAR((f_body[0].linear - Vec3(0, 0, mag)).norm(), 0.0, 1e-12);
        EXPECT_NEAR(f_body[0].angular.norm(), 0.0, 1e-12);  // (R·L) ∥ F
        EXPECT_NEAR((f_tri[0] - Vec3(0, 0, -mag / 2)).norm(), 0.0, 1e-12);
        EXPECT_NEAR((f_tri[1] - Vec3(0, 0, -mag / 4)).norm(), 0.0, 1e-12);
        EXPECT_NEAR((f_tri[2] - Vec3(0, 0, -mag / 4)).norm(), 0.0, 1e-12);
    }
}

// ---------------------------------------------------------------- worked example D

TEST(BarycentricPenaltyContact, WorkedExampleD_DeduplicationEndToEnd) {
    // Two point clouds; output k uses element k on both sides so the winners are identifiable.
    Vec3State s1 = make_state({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
    Vec3State s2 = make_state({{0, 0, 0.5}, {1, 0, 0.5}, {2, 0, 0.5}, {3, 0, 0.5}});
    PointModel a(s1, nullptr, with_k("a", 10, 0.25));
    PointModel b(s2, nullptr, with_k("b", 10, 0.25));
    const std::int64_t ids[4] = {7, 3, 7, 7};
    const double values[4] = {-0.10, -0.05, -0.30, -0.30};
    DetectionOutputList out;
    for (int k = 0; k < 4; ++k) {
        DetectionOutput o;
        o.elem1 = o.elem2 = ElementIndex(k);
        o.id = ids[k];
        o.value = values[k];
        o.point = {s1.position[std::size_t(k)], s2.position[std::size_t(k)]};
        o.normal = Vec3(0, 0, 1);
        out.push_back(o);
    }
    BarycentricPenaltyContact c(a, b, 0.5);
    c.set_detection_outputs(out);
    ASSERT_EQ(c.force_field().size(), 2u);
    EXPECT_EQ(c.force_field().contacts()[0].m1, 1);  // #1 (id 3)
    EXPECT_EQ(c.force_field().contacts()[1].m1, 2);  // #2 (id 7) replaced #0, #3 ignored
    EXPECT_EQ(c.tracker().position_of(3), 1);
    EXPECT_EQ(c.tracker().position_of(7), 2);
    // dist = 0.5 + 0.25 + 0.25 = 1, ks = 100, pen = 1 − 0.5 = 0.5 → 50 N on DOFs 1 and 2 only
    std::vector<Vec3> f1(4, Vec3::Zero()), f2(4, Vec3::Zero());
    c.add_force(flat_span(f1), flat_span(f2));
    for (int k = 0; k < 4; ++k) {
        const double expect = (k == 1 || k == 2) ? 50.0 : 0.0;
        EXPECT_NEAR((f2[std::size_t(k)] - Vec3(0, 0, expect)).norm(), 0.0, 1e-12) << k;
        EXPECT_NEAR((f1[std::size_t(k)] + Vec3(0, 0, expect)).norm(), 0.0, 1e-12) << k;
    }
    // next step, same outputs: both contacts carried over (age 1), old indices 1 and 2
    c.set_detection_outputs(out);
    EXPECT_EQ(c.force_field().contacts()[0].age, 1);
    EXPECT_EQ(c.force_field().contacts()[1].age, 1);
}

// ---------------------------------------------------------------- age

TEST(BarycentricPenaltyContact, AgeGrowsAndRestartsAfterDisappearance) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo, with_k("tri", 10));
    Vec3State ball = make_state({{0.25, 0.25, 0.8}});
    SphereModel sph(ball, 0.5, {}, with_k("ball", 10));
    const auto params = IntersectionParams::new_proximity();
    BarycentricPenaltyContact c(tri, sph, params.contact_distance);
    for (int step = 0; step < 5; ++step) {
        ball.position[0].z() = 0.8 + 0.01 * step;  // still within the alarm distance
        auto det = detect_model_pair(params, tri, sph);
        ASSERT_EQ(det.outputs.size(), 1u);
        c.set_detection_outputs(det.outputs);
        ASSERT_EQ(c.force_field().size(), 1u);
        EXPECT_EQ(c.force_field().contacts()[0].age, step);
    }
    ball.position[0].z() = 5.0;  // gone for one step
    auto det = detect_model_pair(params, tri, sph);
    ASSERT_TRUE(det.outputs.empty());
    c.set_detection_outputs(det.outputs);
    EXPECT_EQ(c.force_field().size(), 0u);
    EXPECT_EQ(c.tracker().tracked_ids(), 0u);
    ball.position[0].z() = 0.8;
    det = detect_model_pair(params, tri, sph);
    c.set_detection_outputs(det.outputs);
    ASSERT_EQ(c.force_field().size(), 1u);
    EXPECT_EQ(c.force_field().contacts()[0].age, 0);
}

// ---------------------------------------------------------------- dist, ks, mu rules

TEST(BarycentricPenaltyContact, DistStiffnessAndFrictionRules) {
    Vec3State s1 = make_state({{0, 0, 0}});
    Vec3State s2 = make_state({{0, 0, 0.1}});
    PointModel a(s1, nullptr, with_k("a", 3, 0.0));
    PointModel b(s2, nullptr, with_k("b", 5, 0.0));
    a.params().contact_friction = 0.2;
    b.params().contact_friction = 0.3;
    DetectionOutput o;
    o.point = {s1.position[0], s2.position[0]};
    o.normal = Vec3(0, 0, 1);
    {
        // Discrete-like: dist = 0 exactly → ks = k1·k2 (no division), spec §14.9
        BarycentricPenaltyContact c(a, b, 0.0);
        c.set_detection_outputs(std::span(&o, 1));
        EXPECT_EQ(c.force_field().contacts()[0].dist, 0.0);
        EXPECT_EQ(c.force_field().contacts()[0].ks, 15.0);
        EXPECT_DOUBLE_EQ(c.force_field().contacts()[0].mu_s, 0.5);
        EXPECT_DOUBLE_EQ(c.force_field().contacts()[0].mu_v, 0.5);
    }
    {
        a.params().contact_distance = 0.1;
        BarycentricPenaltyContact c(a, b, 0.3);
        c.set_detection_outputs(std::span(&o, 1));
        EXPECT_DOUBLE_EQ(c.force_field().contacts()[0].dist, 0.4);
        EXPECT_DOUBLE_EQ(c.force_field().contacts()[0].ks, 15.0 / 0.4);
    }
    {
        ContactResponseParameters rp;
        rp.stiffness_law = StiffnessLaw::physical;
        BarycentricPenaltyContact c(a, b, 0.3, rp);
        c.set_detection_outputs(std::span(&o, 1));
        EXPECT_DOUBLE_EQ(c.force_field().contacts()[0].dist, 0.4);
        EXPECT_DOUBLE_EQ(c.force_field().contacts()[0].ks, 15.0 / 8.0);  // series, no dist
    }
    EXPECT_EQ(combined_contact_stiffness(StiffnessLaw::physical, 0, 0, 1.0), 0.0);
    EXPECT_DOUBLE_EQ(combined_contact_stiffness(StiffnessLaw::physical, 1e4, 1e4, 0.3), 5e3);
    EXPECT_THROW((void)combined_contact_stiffness(StiffnessLaw::sofa, -1, 1, 1), std::invalid_argument);
    EXPECT_THROW(BarycentricPenaltyContact(a, b, -0.1), std::invalid_argument);
}

TEST(BarycentricPenaltyContact, CriticalTimeStep) {
    EXPECT_DOUBLE_EQ(contact_critical_time_step(100.0, 1.0, std::numeric_limits<double>::infinity()), 0.1);
    EXPECT_DOUBLE_EQ(contact_critical_time_step(100.0, 2.0, 2.0), 0.1);  // reduced mass 1
    EXPECT_TRUE(std::isinf(contact_critical_time_step(0.0, 1.0, 1.0)));
    EXPECT_THROW((void)contact_critical_time_step(1.0, 0.0, 1.0), std::invalid_argument);
}

TEST(BarycentricPenaltyContact, BadInputNamesModelAndElement) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo, with_k("floor", 10));
    Vec3State ball = make_state({{0.25, 0.25, 0.8}});
    SphereModel sph(ball, 0.5, {}, with_k("ball", 10));
    BarycentricPenaltyContact c(tri, sph, 0.5);
    DetectionOutput o;
    o.elem1 = ElementIndex(4);  // no such triangle
    o.normal = Vec3(0, 0, 1);
    try {
        c.set_detection_outputs(std::span(&o, 1));
        FAIL() << "expected std::invalid_argument";
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("floor"), std::string::npos) << msg;
        EXPECT_NE(msg.find("element 4"), std::string::npos) << msg;
    }
    EXPECT_THROW(IdentityContactMapper{tri}, std::invalid_argument);
    EXPECT_THROW(RigidContactMapper{sph}, std::invalid_argument);
    EXPECT_THROW(BarycentricContactMapper{sph}, std::invalid_argument);
}

}  // namespace
}  // namespace penalty
