// The NewProximity, MinProximity and Discrete element intersectors (kernels_sofa.cpp), each on
// a configuration whose outputs (count, points, normal, value, id) have a closed form.
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

using test::make_state;

/// One segment (0,0,0)–(2,0,0) as a line model.
struct SofaKernelSegment {
    Vec3State state = make_state({{0, 0, 0}, {2, 0, 0}});
    MeshTopology topo;
    SofaKernelSegment() {
        topo.set_num_points(2);
        topo.set_edges({{0, 1}});
    }
};

void expect_vec_near(const Vec3& got, const Vec3& expected, double tol) {
    EXPECT_LE((got - expected).norm(), tol) << "got " << got.transpose() << ", expected " << expected.transpose();
}

TEST(KernelsSofa, NewProximityLinePointClampsToTheEndAndMinProximityToo) {
    // the point (3, 0.4, 0) beyond the end (2,0,0): both methods clamp to that end;
    // d = (1, 0.4, 0), |d| = √1.16, value = |d| − C
    SofaKernelSegment seg;
    LineModel line(seg.state, seg.topo, test::named("line"));
    Vec3State ps = make_state({{3, 0.4, 0}});
    PointModel point(ps, nullptr, test::named("point"));
    for (IntersectionParams p : {IntersectionParams::new_proximity(), IntersectionParams::min_proximity()}) {
        p.alarm_distance = 2.0;
        p.contact_distance = 0.5;
        const auto det = detect_model_pair(p, point, line);
        ASSERT_EQ(det.model1, &line);
        ASSERT_EQ(det.outputs.size(), 1u) << intersection_method_name(p.method);
        const DetectionOutput& o = det.outputs[0];
        EXPECT_EQ(o.point[0], Vec3(2, 0, 0));
        EXPECT_EQ(o.point[1], Vec3(3, 0.4, 0));
        expect_vec_near(o.normal, Vec3(1, 0.4, 0) / std::sqrt(1.16), 1e-15);
        EXPECT_NEAR(o.value, std::sqrt(1.16) - 0.5, 1e-15);
        EXPECT_EQ(o.id, 0);  // the point's index
    }
    // NewProximity's test is strict: |d| = R gives nothing; MinProximity's (with SOFA's guard) is not
    IntersectionParams np = IntersectionParams::new_proximity();
    np.alarm_distance = 1.25;
    ps.position[0] = Vec3(2.75, 1, 0);  // d = (0.75, 1, 0), |d| = 1.25 exactly
    EXPECT_EQ(detect_model_pair(np, line, point).outputs.size(), 0u);
    np.alarm_distance = std::nextafter(1.25, 2.0);
    EXPECT_EQ(detect_model_pair(np, line, point).outputs.size(), 1u);
}

TEST(KernelsSofa, MinProximityLineSphereMirrorsTheProjectionAboutTheMidpoint) {
    // sphere (r 0.3) centred (0.5, 0.8, 0) over the segment (0,0,0)–(2,0,0): its projection is
    // (0.5,0,0), t = 0.75 from p2 toward p1; SOFA applies t from p1 toward p2 (§14.1): (1.5,0,0)
    SofaKernelSegment seg;
    LineModel line(seg.state, seg.topo, test::named("line"));
    Vec3State ss = make_state({{0.5, 0.8, 0}});
    SphereModel sphere(ss, 0.3, {}, test::named("sphere"));
    IntersectionParams p = IntersectionParams::min_proximity();
    p.alarm_distance = 2.0;
    p.contact_distance = 0.25;
    {
        const auto det = detect_model_pair(p, line, sphere);
        ASSERT_EQ(det.outputs.size(), 1u);
        const DetectionOutput& o = det.outputs[0];
        EXPECT_EQ(o.point[0], Vec3(1.5, 0, 0));
        EXPECT_EQ(o.point[1], Vec3(0.5, 0.8, 0));  // a Vec3 sphere's contact point is its centre
        expect_vec_near(o.normal, Vec3(-1, 0.8, 0) / std::sqrt(1.64), 1e-15);
        EXPECT_NEAR(o.value, std::sqrt(1.64) - 0.25 - 0.3, 1e-15);
    }
    p.quirks.fix_minproximity_line_sphere_mirror = true;
    {
        const auto det = detect_model_pair(p, line, sphere);
        ASSERT_EQ(det.outputs.size(), 1u);
        const DetectionOutput& o = det.outputs[0];
        EXPECT_EQ(o.point[0], Vec3(0.5, 0, 0));
        EXPECT_EQ(o.normal, Vec3(0, 1, 0));
        EXPECT_NEAR(o.value, 0.8 - 0.25 - 0.3, 1e-15);
    }
    // a centre beyond the segment's end: MinProximity wants a strict interior parameter, none
    ss.position[0] = Vec3(2.5, 0.5, 0);
    EXPECT_EQ(detect_model_pair(p, line, sphere).outputs.size(), 0u);
    // NewProximity clamps to the end (2,0,0): d = (0.5, 0.5, 0)
    IntersectionParams np = IntersectionParams::new_proximity();
    const auto det = detect_model_pair(np, line, sphere);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].point[0], Vec3(2, 0, 0));
    EXPECT_NEAR(det.outputs[0].value, std::sqrt(0.5) - (0.5 + 0.3), 1e-15);
}

TEST(KernelsSofa, TrianglePointOverAVertexIsNewProximitysAndNotMinProximitys) {
    // the unit right triangle; a point (−0.3, −0.4, 0.5) beyond its vertex (0,0,0): NewProximity
    // takes the vertex (owned: one triangle owns all its features), |d| = √0.5; MinProximity
    // wants the projection strictly inside the triangle: none
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo, test::named("tri"));
    Vec3State ps = make_state({{-0.3, -0.4, 0.5}});
    PointModel point(ps, nullptr, test::named("point"));
    const auto np = detect_model_pair(IntersectionParams::new_proximity(), tri, point);
    ASSERT_EQ(np.outputs.size(), 1u);
    EXPECT_EQ(np.outputs[0].point[0], Vec3(0, 0, 0));
    expect_vec_near(np.outputs[0].normal, Vec3(-0.3, -0.4, 0.5) / std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(np.outputs[0].value, std::sqrt(0.5) - 0.5, 1e-15);
    EXPECT_TRUE(detect_model_pair(IntersectionParams::min_proximity(), tri, point).outputs.empty());
    // above the interior both agree: Q = (0.25, 0.25, 0), value 0.5 − C
    ps.position[0] = Vec3(0.25, 0.25, 0.5);
    for (const IntersectionParams& p : {IntersectionParams::new_proximity(), IntersectionParams::min_proximity()}) {
        const auto det = detect_model_pair(p, tri, point);
        ASSERT_EQ(det.outputs.size(), 1u);
        EXPECT_EQ(det.outputs[0].point[0], Vec3(0.25, 0.25, 0));
        EXPECT_EQ(det.outputs[0].normal, Vec3(0, 0, 1));
        EXPECT_NEAR(det.outputs[0].value, 0.5 - p.contact_distance, 1e-15);
    }
}

TEST(KernelsSofa, TheModelsContactDistancesAreASkinOnBothThresholds) {
    // point–point at distance 1.2: NewProximity's alarm 1 misses it; skins 0.15 + 0.1 reach it,
    // and the value is 1.2 − (C + 0.25)
    Vec3State a = make_state({{0, 0, 0}});
    Vec3State b = make_state({{0, 1.2, 0}});
    PointModel pa(a, nullptr, test::named("a"));
    PointModel pb(b, nullptr, test::named("b"));
    EXPECT_TRUE(detect_model_pair(IntersectionParams::new_proximity(), pa, pb).outputs.empty());
    CollisionModelParams skin_a = test::named("a");
    skin_a.contact_distance = 0.15;
    CollisionModelParams skin_b = test::named("b");
    skin_b.contact_distance = 0.1;
    PointModel sa(a, nullptr, skin_a);
    PointModel sb(b, nullptr, skin_b);
    const auto det = detect_model_pair(IntersectionParams::new_proximity(), sa, sb);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_NEAR(det.outputs[0].value, 1.2 - (0.5 + 0.25), 1e-15);
    EXPECT_EQ(det.outputs[0].normal, Vec3(0, 1, 0));
}

TEST(KernelsSofa, SphereIdsAreTheIndexInTheModelWithMoreElements) {
    // SOFA's id_big: three spheres against one point: the sphere's index; one sphere against
    // three points: the point's index (ties: element 2's)
    Vec3State three = make_state({{0, 0, 0}, {5, 0, 0}, {10, 0, 0}});
    Vec3State one = make_state({{10.5, 0, 0}});
    SphereModel spheres(three, 0.25, {}, test::named("spheres"));
    PointModel point(one, nullptr, test::named("point"));
    auto det = detect_model_pair(IntersectionParams::new_proximity(), spheres, point);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].elem1, ElementIndex(2));
    EXPECT_EQ(det.outputs[0].id, 2);
    EXPECT_NEAR(det.outputs[0].value, 0.5 - (0.5 + 0.25), 1e-15);
    SphereModel sphere(one, 0.25, {}, test::named("sphere"));
    PointModel points(three, nullptr, test::named("points"));
    det = detect_model_pair(IntersectionParams::new_proximity(), sphere, points);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].elem2, ElementIndex(2));
    EXPECT_EQ(det.outputs[0].id, 2);
    // two against two (a tie): element 2's index; sphere 0 meets point 1, sphere 1 point 0
    Vec3State sphere_centres = make_state({{0, 0, 0}, {10, 0, 0}});
    Vec3State point_positions = make_state({{10.5, 0, 0}, {0, 0.5, 0}});
    SphereModel two_spheres(sphere_centres, 0.25, {}, test::named("two spheres"));
    PointModel two_points(point_positions, nullptr, test::named("two points"));
    det = detect_model_pair(IntersectionParams::new_proximity(), two_spheres, two_points);
    ASSERT_EQ(det.outputs.size(), 2u);
    EXPECT_EQ(det.outputs[0].elem1, ElementIndex(0));
    EXPECT_EQ(det.outputs[0].id, 1);
    EXPECT_EQ(det.outputs[1].elem1, ElementIndex(1));
    EXPECT_EQ(det.outputs[1].id, 0);
}

TEST(KernelsSofa, NewProximityTriangleLineTestsVerticesAgainstTheLineAndEndsAgainstTheTriangle) {
    // the unit right triangle and the segment (0.1,0.1,0.3)–(0.2,0.1,0.3) above it: its two ends
    // project inside at distance 0.3; the vertices' nearest points on the segment are (0.1,0.1,0.3)
    // for (0,0,0) and (0,1,0) and (0.2,0.1,0.3) for (1,0,0): distances √0.11, √0.74, √0.91
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo, test::named("tri"));
    Vec3State ls = make_state({{0.1, 0.1, 0.3}, {0.2, 0.1, 0.3}});
    MeshTopology lt;
    lt.set_num_points(2);
    lt.set_edges({{0, 1}});
    LineModel line(ls, lt, test::named("line"));
    IntersectionParams p = IntersectionParams::new_proximity();
    auto det = detect_model_pair(p, tri, line);
    ASSERT_EQ(det.outputs.size(), 5u);
    std::vector<double> values;
    for (const DetectionOutput& o : det.outputs) {
        EXPECT_EQ(o.id, 0);  // the line's index
        values.push_back(o.value + 0.5);
    }
    // vertex outputs first (vertex as point[0], normal toward the line), then the two ends
    EXPECT_NEAR(values[0], std::sqrt(0.11), 1e-15);
    EXPECT_NEAR(values[1], std::sqrt(0.74), 1e-15);
    EXPECT_NEAR(values[2], std::sqrt(0.91), 1e-15);
    EXPECT_NEAR(values[3], 0.3, 1e-15);
    EXPECT_NEAR(values[4], 0.3, 1e-15);
    EXPECT_EQ(det.outputs[0].point[0], Vec3(0, 0, 0));
    EXPECT_EQ(det.outputs[0].point[1], Vec3(0.1, 0.1, 0.3));
    EXPECT_EQ(det.outputs[3].point[0], Vec3(0.1, 0.1, 0));
    EXPECT_EQ(det.outputs[4].point[0], Vec3(0.2, 0.1, 0));
    // alarm 0.5: the ends and the vertex (0,0,0) (√0.11 ≈ 0.33) only
    p.alarm_distance = 0.5;
    det = detect_model_pair(p, tri, line);
    EXPECT_EQ(det.outputs.size(), 3u);
}

TEST(KernelsSofa, DiscreteTriangleLineReportsTheCrossingPointWithTheTrianglesNormal) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo, test::named("tri"));
    Vec3State ls = make_state({{0.2, 0.3, -1}, {0.2, 0.3, 3}});
    MeshTopology lt;
    lt.set_num_points(2);
    lt.set_edges({{0, 1}});
    LineModel line(ls, lt, test::named("line"));
    auto det = detect_model_pair(IntersectionParams::discrete(), tri, line);
    ASSERT_EQ(det.outputs.size(), 1u);
    const DetectionOutput& o = det.outputs[0];
    expect_vec_near(o.point[0], Vec3(0.2, 0.3, 0), 1e-15);
    EXPECT_EQ(o.point[0], o.point[1]);
    EXPECT_EQ(o.normal, Vec3(0, 0, 1));
    EXPECT_EQ(o.value, 0.0);
    EXPECT_EQ(o.id, 0);
    // the same segment moved beside the triangle (x + y > 1) crosses its plane only
    ls.position = {Vec3(0.7, 0.6, -1), Vec3(0.7, 0.6, 3)};
    EXPECT_TRUE(detect_model_pair(IntersectionParams::discrete(), tri, line).outputs.empty());
}

TEST(KernelsSofa, NewProximityTriangleTriangleStoresTheOtherTrianglesNormalNegated) {
    // §14.4: two one-sided triangle models, parallel planes 0.3 apart facing the same way (+z):
    // the detection stores −n1 = (0,0,−1) as model 2's normal; with the fix it is left alone
    auto lower = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    auto upper = test::triangle_mesh({{0, 0, 0.3}, {1, 0, 0.3}, {0, 1, 0.3}}, {{0, 1, 2}});
    for (const bool fix : {false, true}) {
        TriangleModel t1(lower->state, lower->topo, test::named("lower"));
        TriangleModel t2(upper->state, upper->topo, test::named("upper"));
        IntersectionParams p = IntersectionParams::new_proximity();
        p.quirks.fix_newproximity_triangle_triangle_normal_overwrite = fix;
        const auto det = detect_model_pair(p, t1, t2);
        // every vertex of each against the other: 3 + 3 outputs at 0.3 (vertex 1 without flag
        // check, the others owned)
        ASSERT_EQ(det.outputs.size(), 6u) << fix;
        for (const DetectionOutput& o : det.outputs) EXPECT_NEAR(o.value, 0.3 - 0.5, 1e-15);
        EXPECT_EQ(t1.normal(0), Vec3(0, 0, 1)) << fix;
        EXPECT_EQ(t2.normal(0), fix ? Vec3(0, 0, 1) : Vec3(0, 0, -1)) << fix;
    }
}

}  // namespace
}  // namespace penalty
