// SOFA quirks (spec §14 items 1–4, 8) reproduced by default with a switch that fixes each;
// degenerate input never produces NaN; model skins; LocalMinDistance filters.
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

using test::make_state;

bool all_finite(const DetectionOutputList& out) {
    for (const auto& o : out)
        if (!o.normal.allFinite() || !o.point[0].allFinite() || !o.point[1].allFinite() || !std::isfinite(o.value))
            return false;
    return true;
}

std::unique_ptr<test::Mesh> segment(const Vec3& a, const Vec3& b) {
    auto m = std::make_unique<test::Mesh>();
    m->state = make_state({a, b});
    m->topo.set_num_points(2);
    m->topo.set_edges({{0, 1}});
    return m;
}

TEST(Quirk1, MinProximityLineSphereMirroredClosestPoint) {
    auto seg = segment({0, 0, 0}, {1, 0, 0});
    LineModel line(seg->state, seg->topo);
    Vec3State s = make_state({{0.2, 0.5, 0}});
    SphereModel sph(s, 0.1);
    auto p = IntersectionParams::min_proximity();
    auto det = detect_model_pair(p, line, sph);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_NEAR((det.outputs[0].point[0] - Vec3(0.8, 0, 0)).norm(), 0.0, 1e-15);  // mirrored
    EXPECT_NEAR(det.outputs[0].value, std::sqrt(0.36 + 0.25) - 0.6, 1e-15);
    EXPECT_EQ(det.outputs[0].id, 0);
    p.quirks.fix_minproximity_line_sphere_mirror = true;
    det = detect_model_pair(p, line, sph);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_NEAR((det.outputs[0].point[0] - Vec3(0.2, 0, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR(det.outputs[0].value, -0.1, 1e-15);
    EXPECT_NEAR((det.outputs[0].normal - Vec3(0, 1, 0)).norm(), 0.0, 1e-15);
}

TEST(Quirk2, NewProximityTriangleSphereWrongEdgeFlags) {
    // T0 = (0,2,4) owns edge 0-2; T1 = (0,1,2) owns edge 1-2 (its BC edge, E23) but not its
    // E31 edge (2-0); T2 = (2,1,3) shares edge 1-2 as its AB edge (E12, not owned).
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {-1, 0.5, 0}},
                                    {{0, 2, 4}, {0, 1, 2}, {2, 1, 3}});
    TriangleModel tri(mesh->state, mesh->topo);
    ASSERT_TRUE(tri.flags(1) & TriangleModel::kE23);
    ASSERT_FALSE(tri.flags(1) & TriangleModel::kE31);
    ASSERT_FALSE(tri.flags(2) & TriangleModel::kE12);
    Vec3State s = make_state({{0.5, 0.5, 0.2}});  // above the midpoint of edge 1-2
    SphereModel sph(s, 0.0);
    auto p = IntersectionParams::new_proximity();
    p.alarm_distance = 0.3;
    // SOFA: T1 checks E31 for its BC edge (not owned) and T2 checks E12: nobody reports
    EXPECT_TRUE(detect_model_pair(p, tri, sph).outputs.empty());
    p.quirks.fix_newproximity_triangle_sphere_edge_flags = true;
    const auto det = detect_model_pair(p, tri, sph);
    ASSERT_EQ(det.outputs.size(), 1u);  // fixed: the owner reports the shared edge once
    EXPECT_EQ(det.outputs[0].elem1, ElementIndex(1));
    EXPECT_NEAR(det.outputs[0].value, 0.2 - 0.5, 1e-15);
}

TEST(Quirk3, TriangleTriangleVertex1WithoutOwnership) {
    // model 1: two triangles sharing vertex 0 (owned by triangle 0); model 2: a large triangle
    // just below vertex 0
    auto m1 = test::triangle_mesh({{0, 0, 0.1}, {-1, 0, 0.5}, {-1, -1, 0.5}, {0, 1, 0.5}, {-1, 1, 0.5}},
                                  {{0, 1, 2}, {0, 3, 4}});
    auto m2 = test::triangle_mesh({{-5, -5, 0}, {5, -5, 0}, {0, 5, 0}}, {{0, 1, 2}});
    TriangleModel a(m1->state, m1->topo), b(m2->state, m2->topo);
    ASSERT_FALSE(a.flags(1) & TriangleModel::kP1);
    auto p = IntersectionParams::new_proximity();
    p.alarm_distance = 0.2;
    auto count_vertex0 = [&](const IntersectionParams& ip) {
        int n = 0;
        for (const auto& o : detect_model_pair(ip, a, b).outputs) n += (o.point[0] - Vec3(0, 0, 0.1)).norm() < 1e-15;
        return n;
    };
    EXPECT_EQ(count_vertex0(p), 2);  // from triangle 0 (id 0) and triangle 1 (id 3)
    p.quirks.fix_newproximity_triangle_triangle_vertex1_flag = true;
    EXPECT_EQ(count_vertex0(p), 1);
}

TEST(Quirk4, TriangleTriangleOverwritesStoredNormals) {
    auto m1 = test::triangle_mesh({{0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}}, {{0, 1, 2}});
    auto m2 = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 2, 1}});  // normal -z
    TriangleModel a(m1->state, m1->topo), b(m2->state, m2->topo);
    auto p = IntersectionParams::new_proximity();
    (void)detect_model_pair(p, a, b);
    EXPECT_EQ(b.normal(0), Vec3(0, 0, -1));  // −n(e1) = −(+z)
    b.params().moving = true;
    auto m3 = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});  // normal +z
    TriangleModel c(m3->state, m3->topo);
    (void)detect_model_pair(p, a, c);
    EXPECT_EQ(c.normal(0), Vec3(0, 0, -1));  // overwritten although the geometry says +z
    p.quirks.fix_newproximity_triangle_triangle_normal_overwrite = true;
    (void)detect_model_pair(p, a, c);
    EXPECT_EQ(c.normal(0), Vec3(0, 0, 1));
}

TEST(Quirk8, ZeroDistancePolicyNeverNaNByDefault) {
    Vec3State s1 = make_state({{1, 2, 3}});
    Vec3State s2 = make_state({{1, 2, 3}});
    PointModel a(s1), b(s2);
    auto p = IntersectionParams::new_proximity();
    auto det = detect_model_pair(p, a, b);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].normal, Vec3(1, 0, 0));
    EXPECT_EQ(det.outputs[0].value, -0.5);
    p.quirks.zero_distance_normal = ZeroDistanceNormal::Drop;
    EXPECT_TRUE(detect_model_pair(p, a, b).outputs.empty());
    p.quirks.zero_distance_normal = ZeroDistanceNormal::SofaNaN;
    det = detect_model_pair(p, a, b);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_TRUE(std::isnan(det.outputs[0].normal.x()));
    // MinProximity has SOFA's own guard: (1,0,0) whatever the policy
    auto m = IntersectionParams::min_proximity();
    m.quirks.zero_distance_normal = ZeroDistanceNormal::SofaNaN;
    det = detect_model_pair(m, a, b);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].normal, Vec3(1, 0, 0));
    // LocalMinDistance and Discrete: default fallback too
    EXPECT_EQ(detect_model_pair(IntersectionParams::local_min_distance(), a, b).outputs.at(0).normal, Vec3(1, 0, 0));
    SphereModel sa(s1, 0.5), sb(s2, 0.5);
    det = detect_model_pair(IntersectionParams::discrete(), sa, sb);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_EQ(det.outputs[0].normal, Vec3(1, 0, 0));
    EXPECT_EQ(det.outputs[0].value, -1.0);
    // a point exactly on a triangle (NewProximity Triangle-Point)
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo);
    Vec3State on = make_state({{0.25, 0.25, 0}});
    PointModel pt(on);
    det = detect_model_pair(IntersectionParams::new_proximity(), tri, pt);
    ASSERT_EQ(det.outputs.size(), 1u);
    EXPECT_TRUE(all_finite(det.outputs));
}

TEST(Degenerate, ZeroLengthSegmentsGiveNoContactOrFiniteOutput) {
    auto seg = segment({0, 0, 0}, {0, 0, 0});
    LineModel line(seg->state, seg->topo);
    Vec3State s = make_state({{0.1, 0, 0}});
    PointModel pt(s);
    SphereModel sph(s, 0.1);
    for (auto p : {IntersectionParams::new_proximity(), IntersectionParams::min_proximity(),
                   IntersectionParams::local_min_distance()}) {
        EXPECT_TRUE(detect_model_pair(p, line, pt).outputs.empty()) << intersection_method_name(p.method);
        const auto d = detect_model_pair(p, line, sph);
        EXPECT_TRUE(d.outputs.empty()) << intersection_method_name(p.method);
    }
    // line-line with a zero-length segment: det = 0 → midpoints, finite
    auto seg2 = segment({0, 0.2, 0}, {1, 0.2, 0});
    LineModel line2(seg2->state, seg2->topo);
    for (auto p : {IntersectionParams::new_proximity(), IntersectionParams::min_proximity(),
                   IntersectionParams::local_min_distance()}) {
        const auto d = detect_model_pair(p, line2, line);
        EXPECT_TRUE(all_finite(d.outputs)) << intersection_method_name(p.method);
    }
}

TEST(Degenerate, ParallelSegmentsUseMidpoints) {
    auto s1 = segment({0, 0, 0}, {1, 0, 0});
    auto s2 = segment({0.5, 0.3, 0}, {1.5, 0.3, 0});
    LineModel a(s1->state, s1->topo), b(s2->state, s2->topo);
    const auto d = detect_model_pair(IntersectionParams::new_proximity(), a, b);
    ASSERT_EQ(d.outputs.size(), 1u);
    EXPECT_NEAR((d.outputs[0].point[0] - Vec3(0.5, 0, 0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((d.outputs[0].point[1] - Vec3(1.0, 0.3, 0)).norm(), 0.0, 1e-15);
    EXPECT_TRUE(all_finite(d.outputs));
}

TEST(Degenerate, ZeroAreaTrianglesGiveNoContact) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo);
    Vec3State s = make_state({{0.5, 0.1, 0}});
    PointModel pt(s);
    SphereModel sph(s, 0.05);
    auto seg = segment({0.5, -1, 0.0}, {0.5, 1, 0.0});
    LineModel line(seg->state, seg->topo);
    for (auto p : {IntersectionParams::new_proximity(), IntersectionParams::min_proximity(),
                   IntersectionParams::local_min_distance()}) {
        EXPECT_TRUE(detect_model_pair(p, tri, pt).outputs.empty()) << intersection_method_name(p.method);
        EXPECT_TRUE(detect_model_pair(p, tri, sph).outputs.empty()) << intersection_method_name(p.method);
    }
    // Triangle-Line (NewProximity): vertex-vs-line sub-tests still work and stay finite
    const auto d = detect_model_pair(IntersectionParams::new_proximity(), tri, line);
    EXPECT_TRUE(all_finite(d.outputs));
    EXPECT_TRUE(detect_model_pair(IntersectionParams::discrete(), tri, line).outputs.empty());
}

TEST(Degenerate, CylindersAndTetrahedraNeverNaN) {
    auto p = IntersectionParams::new_proximity();
    p.enable_beyond_sofa_pairs = true;
    Rigid3State rs = test::make_rigid_state({RigidFrame{}});
    CylinderModel cyl(rs);
    Vec3State centre = make_state({{0, 0.3, 0}});  // on the axis, inside
    SphereModel sph(centre, 0.0);
    auto d = detect_model_pair(p, cyl, sph);
    ASSERT_EQ(d.outputs.size(), 1u);
    EXPECT_TRUE(all_finite(d.outputs));
    EXPECT_NEAR(d.outputs[0].value, -0.5 - 0.5, 1e-15);  // depth 0.5 below the side, minus C
    // zero-radius, zero-height cylinders
    CylinderModel thin(rs, 0.0, 0.0);
    d = detect_model_pair(p, thin, sph);
    EXPECT_TRUE(all_finite(d.outputs));
    // two coincident cylinders: overlapping, penetration fallback
    Rigid3State rs2 = test::make_rigid_state({RigidFrame{}});
    CylinderModel other(rs2);
    d = detect_model_pair(p, cyl, other);
    ASSERT_EQ(d.outputs.size(), 1u);
    EXPECT_TRUE(all_finite(d.outputs));
    EXPECT_NEAR(d.outputs[0].value, -1.0 - 0.5, 1e-12);  // min overlap: the diameter 1.0
    // flat tetrahedron with a point on it
    auto m = std::make_unique<test::Mesh>();
    m->state = make_state({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
    m->topo.set_num_points(4);
    m->topo.set_tetrahedra({{0, 1, 2, 3}});
    TetrahedronModel tet(m->state, m->topo);
    Vec3State on = make_state({{0.2, 0.2, 0}});
    PointModel pt(on);
    d = detect_model_pair(p, tet, pt);
    ASSERT_EQ(d.outputs.size(), 1u);
    EXPECT_TRUE(all_finite(d.outputs));
}

TEST(Skins, ModelContactDistancesAddToAlarmAndContactDistance) {
    Vec3State s1 = make_state({{0, 0, 0}});
    Vec3State s2 = make_state({{1.25, 0, 0}});
    CollisionModelParams p1, p2;
    p1.contact_distance = 0.1;
    p2.contact_distance = 0.2;
    PointModel a(s1, nullptr, p1), b(s2, nullptr, p2);
    auto d = detect_model_pair(IntersectionParams::new_proximity(), a, b);  // R = 1.3
    ASSERT_EQ(d.outputs.size(), 1u);
    EXPECT_NEAR(d.outputs[0].value, 1.25 - 0.8, 1e-15);
    s2.position[0].x() = 1.3;
    EXPECT_TRUE(detect_model_pair(IntersectionParams::new_proximity(), a, b).outputs.empty());
    // Discrete sphere pairs ignore model skins (spec §5.4)
    SphereModel sa(s1, 0.5, {}, p1), sb(s2, 0.5, {}, p2);
    s2.position[0].x() = 1.05;
    EXPECT_TRUE(detect_model_pair(IntersectionParams::discrete(), sa, sb).outputs.empty());
}

TEST(IdRules, SphereIndexPointIndexAndIdBig) {
    // MinProximity Sphere–Point: id = sphere index; NewProximity: id of the bigger model
    Vec3State s = make_state({{0, 0, 0}});
    Vec3State pts = make_state({{0.5, 0, 0}, {0, 0.6, 0}, {0, 0, 0.7}});
    SphereModel sph(s, 0.2);
    PointModel pm(pts);
    for (const auto& o : detect_model_pair(IntersectionParams::min_proximity(), sph, pm).outputs) EXPECT_EQ(o.id, 0);
    const auto d = detect_model_pair(IntersectionParams::new_proximity(), sph, pm);
    ASSERT_EQ(d.outputs.size(), 3u);
    for (const auto& o : d.outputs) EXPECT_EQ(o.id, o.elem2.value());
    // Triangle–Triangle ids: 3·e1 + k and 3·size1 + 12·e2 + m
    auto m1 = test::triangle_mesh({{0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}}, {{0, 1, 2}});
    auto m2 = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel a(m1->state, m1->topo), b(m2->state, m2->topo);
    auto p = IntersectionParams::new_proximity();
    p.alarm_distance = 0.2;
    std::vector<std::int64_t> ids;
    for (const auto& o : detect_model_pair(p, a, b).outputs) ids.push_back(o.id);
    EXPECT_EQ(ids, (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5}));
}

TEST(LocalMinDistanceFilters, TriangleIsOneSidedUnlessBothSide) {
    auto mesh = test::triangle_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
    TriangleModel tri(mesh->state, mesh->topo);
    Vec3State s = make_state({{0.25, 0.25, 0.3}, {0.25, 0.25, -0.3}});
    PointModel pt(s);
    auto p = IntersectionParams::local_min_distance();
    auto d = detect_model_pair(p, tri, pt);
    ASSERT_EQ(d.outputs.size(), 1u);
    EXPECT_EQ(d.outputs[0].elem2, ElementIndex(0));
    tri.params().both_side = true;
    EXPECT_EQ(detect_model_pair(p, tri, pt).outputs.size(), 2u);
    tri.params().both_side = false;
    p.filter_intersection = false;
    EXPECT_EQ(detect_model_pair(p, tri, pt).outputs.size(), 2u);
}

TEST(LocalMinDistanceFilters, LineBetweenTwoTrianglesAcceptsOnlyTheOutsideCone) {
    // a roof: two triangles sharing edge (0,1) along x, normals tilted up on each side
    auto mesh = std::make_unique<test::Mesh>();
    mesh->state = make_state({{0, 0, 0}, {1, 0, 0}, {0.5, 1, -0.5}, {0.5, -1, -0.5}});
    mesh->topo.set_num_points(4);
    mesh->topo.set_triangles({{0, 1, 2}, {1, 0, 3}});
    LineModel line(mesh->state, mesh->topo);
    Index ridge = -1;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const Edge& e = line.edge(Index(i));
        if (std::min(e[0], e[1]) == 0 && std::max(e[0], e[1]) == 1) ridge = Index(i);
    }
    ASSERT_GE(ridge, 0);
    Vec3State s = make_state({{0.5, 0, 0.5}, {0.5, 0, -0.5}});
    PointModel pt(s);
    auto p = IntersectionParams::local_min_distance();
    int above = 0, below = 0;
    for (const auto& o : detect_model_pair(p, line, pt).outputs) {
        if (o.elem1 != ElementIndex(ridge)) continue;
        (o.elem2 == ElementIndex(0) ? above : below)++;
    }
    EXPECT_EQ(above, 1);
    EXPECT_EQ(below, 0);
}

TEST(LocalMinDistanceFilters, PointFilterNeedsALineModelInItsNode) {
    // a point at the apex of a pyramid surface: only directions inside its outward cone pass
    auto mesh = test::octahedron();
    PointModel apex(mesh->state, &mesh->topo);
    Vec3State s = make_state({{0, 0, 1.5}, {0.0, 0.3, 0.5}});
    PointModel probe(s);
    auto p = IntersectionParams::local_min_distance();
    p.alarm_distance = 0.6;
    auto count_apex = [&]() {
        int n = 0;
        for (const auto& o : detect_model_pair(p, apex, probe).outputs)
            n += (o.elem1 == ElementIndex(4) || o.elem2 == ElementIndex(4));
        return n;
    };
    EXPECT_EQ(count_apex(), 2);  // no line model in the node: filter skipped
    apex.node_has_line_model = true;
    EXPECT_EQ(count_apex(), 1);  // the point below the apex (inside) is rejected
}

}  // namespace
}  // namespace penalty
