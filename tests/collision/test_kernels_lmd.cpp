// The LocalMinDistance element intersectors and their validity filters (kernels_lmd.cpp), on
// configurations whose outputs have a closed form: strict interior projections, the one-sided
// triangle, the cones of an edge between two triangles, strict and non-strict sphere pairs.
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

using test::make_state;

IntersectionParams lmd_params() {
    IntersectionParams p = IntersectionParams::local_min_distance();
    p.alarm_distance = 1.0;
    p.contact_distance = 0.25;
    return p;
}

TEST(KernelsLmd, TrianglePointOnlyInFrontOfAOneSidedTriangle) {
    // the unit right triangle (normal +z): a point 0.5 above its interior gives Q below it and
    // value 0.5 − C; 0.5 below, nothing (valid_triangle) unless the model is two-sided or the
    // filters are off
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel one_sided(mesh->state, mesh->topo, test::named("tri"));
    Vec3State ps = make_state({{0.25, 0.5, 0.5}});
    PointModel point(ps, nullptr, test::named("point"));
    auto det = detect_model_pair(lmd_params(), point, one_sided);
    ASSERT_EQ(det.model1, &one_sided);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].point[0], Vec3(0.25, 0.5, 0));
    EXPECT_EQ(det.outputs[0].point[1], Vec3(0.25, 0.5, 0.5));
    EXPECT_EQ(det.outputs[0].normal, Vec3(0, 0, 1));
    EXPECT_EQ(det.outputs[0].value, 0.5 - 0.25);
    ps.position[0] = Vec3(0.25, 0.5, -0.5);
    EXPECT_TRUE(detect_model_pair(lmd_params(), one_sided, point).outputs.empty());
    CollisionModelParams two = test::named("two-sided");
    two.both_side = true;
    TriangleModel two_sided(mesh->state, mesh->topo, two);
    det = detect_model_pair(lmd_params(), two_sided, point);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].normal, Vec3(0, 0, -1));
    IntersectionParams unfiltered = lmd_params();
    unfiltered.filter_intersection = false;
    EXPECT_EQ(detect_model_pair(unfiltered, one_sided, point).outputs.size(), 1u);
    // a projection outside the triangle (x + y > 1): LocalMinDistance wants the interior, none
    ps.position[0] = Vec3(0.6, 0.6, 0.1);
    EXPECT_TRUE(detect_model_pair(unfiltered, one_sided, point).outputs.empty());
}

TEST(KernelsLmd, LinePointIsAStrictInteriorProjection) {
    // a free segment (0,0,0)–(2,0,0): the point (0.5, 0.6, 0) projects on (0.5,0,0); a point
    // beyond an end has no interior projection: no output (NewProximity would clamp)
    Vec3State ls = make_state({{0, 0, 0}, {2, 0, 0}});
    MeshTopology lt;
    lt.set_num_points(2);
    lt.set_edges({{0, 1}});
    LineModel line(ls, lt, test::named("line"));
    Vec3State ps = make_state({{0.5, 0.6, 0}});
    PointModel point(ps, nullptr, test::named("point"));
    auto det = detect_model_pair(lmd_params(), line, point);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].point[0], Vec3(0.5, 0, 0));
    EXPECT_EQ(det.outputs[0].normal, Vec3(0, 1, 0));
    EXPECT_NEAR(det.outputs[0].value, 0.6 - 0.25, 1e-15);
    EXPECT_EQ(det.outputs[0].id, 0);
    ps.position[0] = Vec3(2.1, 0.2, 0);
    EXPECT_TRUE(detect_model_pair(lmd_params(), line, point).outputs.empty());
    // the alarm test is strict: |QP| = A + skins gives nothing
    ps.position[0] = Vec3(1, 1, 0);
    EXPECT_TRUE(detect_model_pair(lmd_params(), line, point).outputs.empty());
    ps.position[0] = Vec3(1, std::nextafter(1.0, 0.0), 0);
    EXPECT_EQ(detect_model_pair(lmd_params(), line, point).outputs.size(), 1u);
}

TEST(KernelsLmd, AnEdgeBetweenTwoTrianglesTakesOnlyPointsOnItsFrontSide) {
    // two flat triangles (normal +z) sharing the edge (0,0,0)–(1,0,0): a point 0.4 above the
    // edge's middle passes the edge's filter; 0.4 below (against the mean normal) does not
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}}, {{0, 1, 2}, {1, 0, 3}});
    LineModel lines(mesh->state, mesh->topo, test::named("edges"));
    Index shared = -1;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const Edge& e = lines.edge(Index(i));
        if ((e[0] == 0 && e[1] == 1) || (e[0] == 1 && e[1] == 0)) shared = Index(i);
    }
    ASSERT_GE(shared, 0);
    ASSERT_EQ(mesh->topo.triangles_around_edge()[std::size_t(shared)].size(), 2u);
    Vec3State ps = make_state({{0.5, 0, 0.4}});
    PointModel point(ps, nullptr, test::named("point"));
    // the outputs of the shared edge, each from (0.5,0,0) with the value 0.4 − C
    const auto outputs_of_shared = [&](const IntersectionParams& p) {
        int count = 0;
        for (const DetectionOutput& o : detect_model_pair(p, lines, point).outputs)
            if (o.elem1 == ElementIndex(shared)) {
                ++count;
                EXPECT_EQ(o.point[0], Vec3(0.5, 0, 0));
                EXPECT_NEAR(o.value, (o.point[1] - o.point[0]).norm() - 0.25, 1e-15);
                EXPECT_NEAR((o.point[1] - o.point[0]).norm(), 0.4, 1e-15);
            }
        return count;
    };
    EXPECT_EQ(outputs_of_shared(lmd_params()), 1);
    ps.position[0] = Vec3(0.5, 0, -0.4);
    EXPECT_EQ(outputs_of_shared(lmd_params()), 0);
    IntersectionParams unfiltered = lmd_params();
    unfiltered.filter_intersection = false;
    EXPECT_EQ(outputs_of_shared(unfiltered), 1);
    // over one triangle or the other (±y), |PQ| = 0.4: each against one side tangent t
    // (t·PQ = −0.4·cos θ for PQ at θ above the plane): rejected with angle_cone 0 (the cone's
    // mean-normal share n̄·t·coneFactor is 0); with angle_cone 0.7 when −0.4·cos θ < −0.7·0.4
    IntersectionParams cone = lmd_params();
    cone.angle_cone = 0.7;
    for (const double y : {0.4, -0.4}) {
        // θ = 0 (in the plane) and θ with cos θ = 0.6
        ps.position[0] = Vec3(0.5, y, 0);
        EXPECT_EQ(outputs_of_shared(lmd_params()), 0) << y;
        EXPECT_EQ(outputs_of_shared(cone), 0) << y;
        ps.position[0] = Vec3(0.5, 0.6 * y, 0.32);
        EXPECT_EQ(outputs_of_shared(lmd_params()), 0) << y;
        EXPECT_EQ(outputs_of_shared(cone), 1) << y;
    }
}

TEST(KernelsLmd, VecSpheresAreStrictAndRigidSpheresAreNot) {
    // centres 2 apart, radii 0.5 each, alarm 1: |d| = A + r1 + r2 exactly. LocalMinDistance's
    // Sphere–Sphere tests |d|² < R² (none); its RigidSphere pairs SOFA's |d|² ≤ R² (one)
    Vec3State a = make_state({{0, 0, 0}});
    Vec3State b = make_state({{0, 2, 0}});
    SphereModel sa(a, 0.5, {}, test::named("a"));
    SphereModel sb(b, 0.5, {}, test::named("b"));
    EXPECT_TRUE(detect_model_pair(lmd_params(), sa, sb).outputs.empty());
    Rigid3State ra = test::make_rigid_state({RigidFrame{Vec3(0, 0, 0), Quat::Identity()}});
    Rigid3State rb = test::make_rigid_state({RigidFrame{Vec3(0, 2, 0), Quat::Identity()}});
    RigidSphereModel rsa(ra, 0.5);
    RigidSphereModel rsb(rb, 0.5);
    auto det = detect_model_pair(lmd_params(), rsa, rsb);
    ASSERT_EQ(det.outputs.size(), 1u);
    // rigid: the surface points, value |d| − r1 − r2 − C
    EXPECT_EQ(det.outputs[0].point[0], Vec3(0, 0.5, 0));
    EXPECT_EQ(det.outputs[0].point[1], Vec3(0, 1.5, 0));
    EXPECT_EQ(det.outputs[0].value, 2 - 1 - 0.25);
    // closer, the Vec3 spheres report their centres, value |d| − (C + r1 + r2)
    b.position[0] = Vec3(0, 1.5, 0);
    det = detect_model_pair(lmd_params(), sa, sb);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].point[0], Vec3(0, 0, 0));
    EXPECT_EQ(det.outputs[0].point[1], Vec3(0, 1.5, 0));
    EXPECT_EQ(det.outputs[0].normal, Vec3(0, 1, 0));
    EXPECT_EQ(det.outputs[0].value, 1.5 - (0.25 + 0.5 + 0.5));
}

TEST(KernelsLmd, CrossingFreeSegmentsMeetAtTheirCommonPerpendicular) {
    // (−1,0,0)–(1,0,0) and (0,−1,0.3)–(0,1,0.3): P = (0,0,0), Q = (0,0,0.3); free segments
    // (no triangles) pass the line filter when PQ is perpendicular to them
    Vec3State s1 = make_state({{-1, 0, 0}, {1, 0, 0}});
    Vec3State s2 = make_state({{0, -1, 0.3}, {0, 1, 0.3}});
    MeshTopology lt;
    lt.set_num_points(2);
    lt.set_edges({{0, 1}});
    LineModel l1(s1, lt, test::named("l1"));
    LineModel l2(s2, lt, test::named("l2"));
    const auto det = detect_model_pair(lmd_params(), l1, l2);
    ASSERT_EQ(det.outputs.size(), 1u);
    const DetectionOutput& o = det.outputs[0];
    EXPECT_NEAR((o.point[0] - Vec3(0, 0, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((o.point[1] - Vec3(0, 0, 0.3)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((o.normal - Vec3(0, 0, 1)).norm(), 0.0, 1e-15);
    EXPECT_NEAR(o.value, 0.3 - 0.25, 1e-15);
}

}  // namespace
}  // namespace penalty
