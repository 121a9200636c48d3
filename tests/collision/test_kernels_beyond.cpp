// The pairs beyond SOFA (kernels_beyond.cpp): Cylinder against Sphere, Cylinder and Triangle,
// and Tetrahedron–Point, on configurations whose distance, normal, points, value and id have a
// closed form.
#include "fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penalty {
namespace {

using test::make_rigid_state;
using test::make_state;

IntersectionParams beyond(IntersectionParams p) {
    p.enable_beyond_sofa_pairs = true;
    return p;
}

void expect_close(const Vec3& got, const Vec3& expected, double tol) {
    EXPECT_LE((got - expected).norm(), tol) << "got " << got.transpose() << ", expected " << expected.transpose();
}

TEST(KernelsBeyond, CylinderSphereFromTheSideTheCapAndInside) {
    // default cylinders at the origin and at x = 10: radius 0.5, height 2, axis y; spheres of
    // radius 0.2, three near the first cylinder, one near the second
    Rigid3State frames =
        make_rigid_state({RigidFrame{Vec3::Zero(), Quat::Identity()}, RigidFrame{Vec3(10, 0, 0), Quat::Identity()}});
    CylinderModel cylinder(frames);
    Vec3State centres = make_state({{1, 0, 0}, {0, 1.5, 0}, {0.3, 0, 0}, {10.8, 0, 0}});
    SphereModel spheres(centres, 0.2, {}, test::named("spheres"));
    const IntersectionParams p = beyond(IntersectionParams::new_proximity());
    const auto det = detect_model_pair(p, spheres, cylinder);
    ASSERT_EQ(det.model1, &cylinder);
    ASSERT_EQ(det.outputs.size(), 4u);
    // the side: closest (0.5,0,0), signed distance 0.5, value 0.5 − (C + r)
    EXPECT_EQ(det.outputs[0].point[0], Vec3(0.5, 0, 0));
    EXPECT_EQ(det.outputs[0].point[1], Vec3(1, 0, 0));
    EXPECT_EQ(det.outputs[0].normal, Vec3(1, 0, 0));
    EXPECT_NEAR(det.outputs[0].value, 0.5 - 0.7, 1e-15);
    // the top cap: closest (0,1,0), distance 0.5
    EXPECT_EQ(det.outputs[1].point[0], Vec3(0, 1, 0));
    EXPECT_EQ(det.outputs[1].normal, Vec3(0, 1, 0));
    EXPECT_NEAR(det.outputs[1].value, 0.5 - 0.7, 1e-15);
    // a centre inside, 0.2 from the side: signed distance −0.2, the outward normal
    EXPECT_NEAR(det.outputs[2].value, -0.2 - 0.7, 1e-15);
    EXPECT_EQ(det.outputs[2].normal, Vec3(1, 0, 0));
    // one contact per (cylinder, sphere): id = e1·|spheres| + e2
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(det.outputs[i].id, std::int64_t(i));
    EXPECT_EQ(det.outputs[3].elem1, ElementIndex(1));
    EXPECT_EQ(det.outputs[3].id, 1 * 4 + 3);
    EXPECT_NEAR(det.outputs[3].value, 0.3 - 0.7, 1e-15);
    // the test is strict: signed distance = A + r is no contact
    centres.position = {Vec3(0.5 + 1.2, 0, 0)};
    EXPECT_TRUE(detect_model_pair(p, cylinder, spheres).outputs.empty());
    centres.position = {Vec3(std::nextafter(1.7, 0.0), 0, 0)};
    EXPECT_EQ(detect_model_pair(p, cylinder, spheres).outputs.size(), 1u);
}

TEST(KernelsBeyond, CylinderRigidSpherePointIsTheCentreOrTheSurfaceByMethod) {
    // a cylinder turned by 90° about z (axis −x): the rigid sphere at (1.5, 0, 0) faces its cap
    // at x = −1·(−1) = 1: distance 0.5; NewProximity reports the centre, MinProximity the
    // surface point c − n·r
    Rigid3State frames =
        make_rigid_state({RigidFrame{Vec3::Zero(), Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()))}});
    CylinderModel cylinder(frames);
    Rigid3State ball = make_rigid_state({RigidFrame{Vec3(1.5, 0, 0), Quat::Identity()}});
    RigidSphereModel sphere(ball, 0.2);
    const auto np = detect_model_pair(beyond(IntersectionParams::new_proximity()), cylinder, sphere);
    ASSERT_EQ(np.outputs.size(), 1u);
    expect_close(np.outputs[0].point[0], Vec3(1, 0, 0), 1e-15);
    expect_close(np.outputs[0].normal, Vec3(1, 0, 0), 1e-15);
    EXPECT_EQ(np.outputs[0].point[1], Vec3(1.5, 0, 0));
    EXPECT_NEAR(np.outputs[0].value, 0.5 - 0.7, 1e-15);
    const auto min = detect_model_pair(beyond(IntersectionParams::min_proximity()), cylinder, sphere);
    ASSERT_EQ(min.outputs.size(), 1u);
    expect_close(min.outputs[0].point[1], Vec3(1.3, 0, 0), 1e-15);
    EXPECT_NEAR(min.outputs[0].value, 0.5 - 0.7, 1e-15);
}

TEST(KernelsBeyond, ParallelCylindersApartAndOverlapping) {
    // two default cylinders (radius 0.5, axis y), centres 1.5 apart in x: distance 0.5 along x;
    // 0.8 apart: a penetration 0.2 (the centre offset is a candidate direction)
    Rigid3State a = make_rigid_state({RigidFrame{Vec3::Zero(), Quat::Identity()}});
    Rigid3State b = make_rigid_state({RigidFrame{Vec3(1.5, 0.25, 0), Quat::Identity()}});
    CylinderModel ca(a, 0.5, 2.0, Vec3::UnitY(), test::named("a"));
    CylinderModel cb(b, 0.5, 2.0, Vec3::UnitY(), test::named("b"));
    const IntersectionParams p = beyond(IntersectionParams::new_proximity());
    auto det = detect_model_pair(p, ca, cb);
    ASSERT_EQ(det.outputs.size(), 1u);
    expect_close(det.outputs[0].normal, Vec3(1, 0, 0), 1e-12);
    EXPECT_NEAR(det.outputs[0].value, 0.5 - 0.5, 1e-12);
    EXPECT_NEAR(det.outputs[0].point[0].x(), 0.5, 1e-12);
    EXPECT_NEAR(det.outputs[0].point[1].x(), 1.0, 1e-12);
    EXPECT_EQ(det.outputs[0].id, 0);
    b.position[0].center = Vec3(0.8, 0.25, 0);
    det = detect_model_pair(p, ca, cb);
    ASSERT_EQ(det.outputs.size(), 1u);
    expect_close(det.outputs[0].normal, Vec3(1, 0, 0), 1e-12);
    EXPECT_NEAR(det.outputs[0].value, -0.2 - 0.5, 1e-12);
    // beyond the alarm distance 1 (distance 1.0 + 1e-9): nothing
    b.position[0].center = Vec3(2.0 + 1e-9, 0.25, 0);
    EXPECT_TRUE(detect_model_pair(p, ca, cb).outputs.empty());
}

TEST(KernelsBeyond, CylinderAboveATriangleMeetsItAtItsBottomCap) {
    // the default cylinder (bottom cap y = −1, radius 0.5) over a large triangle in y = −1.3:
    // distance 0.3, normal from the cylinder toward the triangle (0,−1,0)
    Rigid3State frames = make_rigid_state({RigidFrame{Vec3::Zero(), Quat::Identity()}});
    CylinderModel cylinder(frames);
    auto mesh = test::triangle_mesh({{-5, -1.3, -5}, {5, -1.3, -5}, {0, -1.3, 5}}, {{0, 1, 2}});
    TriangleModel triangle(mesh->state, mesh->topo, test::named("floor"));
    const auto det = detect_model_pair(beyond(IntersectionParams::min_proximity()), triangle, cylinder);
    ASSERT_EQ(det.model1, &cylinder);
    ASSERT_EQ(det.outputs.size(), 1u);
    expect_close(det.outputs[0].normal, Vec3(0, -1, 0), 1e-12);
    EXPECT_NEAR(det.outputs[0].value, 0.3 - 0.5, 1e-12);
    EXPECT_NEAR(det.outputs[0].point[0].y(), -1.0, 1e-12);
    EXPECT_NEAR(det.outputs[0].point[1].y(), -1.3, 1e-12);
}

TEST(KernelsBeyond, TetrahedronPointOutsideAndInsideInEveryMethod) {
    // the unit corner tetrahedron; (0.2, 0.2, −0.3) is 0.3 below its face z = 0; (0.1, 0.2, 0.3)
    // is inside, nearest the face x = 0 (0.1; the slanted face is 0.4/√3 ≈ 0.23 away)
    Vec3State corners = make_state({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    MeshTopology topo;
    topo.set_num_points(4);
    topo.set_tetrahedra({{0, 1, 2, 3}});
    TetrahedronModel tetra(corners, topo, test::named("tetra"));
    Vec3State ps = make_state({{5, 5, 5}, {0.2, 0.2, -0.3}, {0.1, 0.2, 0.3}});
    PointModel points(ps, nullptr, test::named("points"));
    for (const IntersectionParams& base : {IntersectionParams::new_proximity(), IntersectionParams::min_proximity(),
                                           IntersectionParams::local_min_distance(), IntersectionParams::discrete()}) {
        const IntersectionParams p = beyond(base);
        const auto det = detect_model_pair(p, points, tetra);
        const bool discrete = p.method == IntersectionMethod::Discrete;  // A = C = 0: inside only
        ASSERT_EQ(det.outputs.size(), discrete ? 1u : 2u) << intersection_method_name(p.method);
        const DetectionOutput& inside = det.outputs.back();
        EXPECT_EQ(inside.id, 2);  // the point's index
        EXPECT_NEAR(inside.value, -0.1 - p.contact_distance, 1e-15);
        EXPECT_EQ(inside.normal, Vec3(-1, 0, 0));
        expect_close(inside.point[0], Vec3(0, 0.2, 0.3), 1e-15);
        EXPECT_EQ(inside.point[1], Vec3(0.1, 0.2, 0.3));
        if (discrete) continue;
        const DetectionOutput& below = det.outputs.front();
        EXPECT_EQ(below.id, 1);
        EXPECT_NEAR(below.value, 0.3 - p.contact_distance, 1e-15);
        expect_close(below.normal, Vec3(0, 0, -1), 1e-15);
        expect_close(below.point[0], Vec3(0.2, 0.2, 0), 1e-15);
    }
    // opt-in: without the switch the pair is reported as beyond SOFA, without outputs
    const auto off = detect_model_pair(IntersectionParams::new_proximity(), tetra, points);
    EXPECT_EQ(off.support, PairSupport::BeyondSofa);
    EXPECT_TRUE(off.outputs.empty());
}

}  // namespace
}  // namespace penalty
