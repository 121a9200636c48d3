// Worked examples A–C of the spec (§11), detection part, asserted exactly.
#include "fixtures.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

using test::make_state;

TEST(WorkedExample, A_NewProximityTriangleSphere) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo, test::named("tri"));
    EXPECT_EQ(tri.flags(0), 0x1FFu);  // all vertices and edges owned, all edges boundary
    Vec3State s = make_state({{0.25, 0.25, 0.8}});
    SphereModel sph(s, 0.5, {}, test::named("sphere"));
    const auto det = detect_model_pair(IntersectionParams::new_proximity(), sph, tri);
    ASSERT_EQ(det.model1, &tri);  // registered order Triangle–Sphere
    ASSERT_EQ(det.outputs.size(), 1u);
    const DetectionOutput& o = det.outputs[0];
    EXPECT_EQ(o.elem1, ElementIndex(0));
    EXPECT_EQ(o.elem2, ElementIndex(0));
    EXPECT_EQ(o.id, 0);
    EXPECT_NEAR((o.point[0] - Vec3(0.25, 0.25, 0)).norm(), 0.0, 1e-15);
    EXPECT_EQ(o.point[1], Vec3(0.25, 0.25, 0.8));
    EXPECT_NEAR((o.normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-15);
    EXPECT_NEAR(o.value, -0.2, 1e-15);
}

TEST(WorkedExample, B_NewProximityTriangleRigidSphere) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo);
    Rigid3State rs = test::make_rigid_state({RigidFrame{Vec3(0.25, 0.25, 0.8), Quat::Identity()}});
    RigidSphereModel sph(rs, 0.5);
    const auto det = detect_model_pair(IntersectionParams::new_proximity(), tri, sph);
    ASSERT_EQ(det.outputs.size(), 1u);
    const DetectionOutput& o = det.outputs[0];
    // surface point opposite to the normal: centre − n r
    EXPECT_NEAR((o.point[1] - Vec3(0.25, 0.25, 0.3)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((o.point[0] - Vec3(0.25, 0.25, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR(o.value, -0.2, 1e-15);
    EXPECT_EQ(o.id, 0);
}

TEST(WorkedExample, C_MinProximitySphereSphere) {
    Vec3State s1 = make_state({{0, 0, 0}});
    Vec3State s2 = make_state({{2.2, 0, 0}});
    SphereModel a(s1, 1.0), b(s2, 1.0);
    const auto det = detect_model_pair(IntersectionParams::min_proximity(), a, b);
    ASSERT_EQ(det.outputs.size(), 1u);
    const DetectionOutput& o = det.outputs[0];
    EXPECT_NEAR(o.value, -0.3, 1e-15);
    EXPECT_EQ(o.normal, Vec3(1, 0, 0));
    EXPECT_EQ(o.point[0], Vec3(0, 0, 0));
    EXPECT_EQ(o.point[1], Vec3(2.2, 0, 0));
    EXPECT_EQ(o.id, 0);
    // at |d| = 3 = A + r1 + r2 the (non-strict) test still reports; beyond it does not
    s2.position[0] = Vec3(3.0, 0, 0);
    EXPECT_EQ(detect_model_pair(IntersectionParams::min_proximity(), a, b).outputs.size(), 1u);
    s2.position[0] = Vec3(3.0 + 1e-12, 0, 0);
    EXPECT_EQ(detect_model_pair(IntersectionParams::min_proximity(), a, b).outputs.size(), 0u);
}

TEST(WorkedExample, NewProximityStrictThreshold) {
    // NewProximity uses |d|² < R²: exactly at R there is no contact
    Vec3State s1 = make_state({{0, 0, 0}});
    Vec3State s2 = make_state({{3.0, 0, 0}});
    SphereModel a(s1, 1.0), b(s2, 1.0);
    EXPECT_EQ(detect_model_pair(IntersectionParams::new_proximity(), a, b).outputs.size(), 0u);
    s2.position[0] = Vec3(2.999999, 0, 0);
    const auto det = detect_model_pair(IntersectionParams::new_proximity(), a, b);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_NEAR(det.outputs[0].value, 2.999999 - 2.5, 1e-15);
}

TEST(WorkedExample, DiscreteSphereSphereOnlyOnOverlap) {
    Vec3State s1 = make_state({{0, 0, 0}});
    Vec3State s2 = make_state({{1.9, 0, 0}});
    SphereModel a(s1, 1.0), b(s2, 1.0);
    auto det = detect_model_pair(IntersectionParams::discrete(), a, b);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_NEAR(det.outputs[0].value, -0.1, 1e-15);
    s2.position[0] = Vec3(2.0, 0, 0);  // touching: accepted (non-strict), value 0
    det = detect_model_pair(IntersectionParams::discrete(), a, b);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].value, 0.0);
    s2.position[0] = Vec3(2.01, 0, 0);
    EXPECT_EQ(detect_model_pair(IntersectionParams::discrete(), a, b).outputs.size(), 0u);
}

}  // namespace
}  // namespace penalty
