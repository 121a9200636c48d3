// Pressure loads (TrianglePressureForceField, QuadPressureForceField, EdgePressureForceField,
// SurfacePressureForceField):
// closed forms on known areas and lengths, SOFA's corner shares, and the derivative checks.
#include "penalty/mechanics/pressure_loads.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/point_state.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

Vec3 total(const std::vector<Vec3>& f) {
    Vec3 s = Vec3::Zero();
    for (const Vec3& v : f) s += v;
    return s;
}

using test::force_of;

/// A constant force field: the FD Jacobian of f is zero, add_dforce and the triplets add nothing
/// (K = 0, so check_force_field_derivatives' relative comparisons do not apply), and
/// f = −∂E/∂x. Returns |f|∞.
double check_constant_force_field(BaseForceField& ff, Vec3Object& s) {
    const auto n = static_cast<Eigen::Index>(3 * s.num_dofs());
    const Eigen::VectorXd x0 = Vec3Object::flat(s.position);
    const auto force = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
        Vec3Object::flat(s.position) = x;
        return Vec3Object::flat(force_of(ff, s));
    };
    const auto energy = [&](const Eigen::VectorXd& x) {
        force(x);
        return ff.potential_energy();
    };
    EXPECT_LT(test::finite_jacobian(x0, force, 1e-6).cwiseAbs().maxCoeff(), 1e-8);
    const Eigen::VectorXd grad = test::finite_gradient(x0, energy, 1e-6);
    const Eigen::VectorXd f = force(x0);
    EXPECT_LT((f + grad).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, f.cwiseAbs().maxCoeff()));
    std::fill(s.dx.begin(), s.dx.end(), Vec3(1, -2, 3));
    std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
    ff.accumulate_dforce(1.0, 1.0);
    for (const Vec3& v : s.df) EXPECT_EQ(v, Vec3::Zero());
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, 1.0);
    EXPECT_TRUE(t.empty());
    EXPECT_EQ(f.size(), n);
    return f.cwiseAbs().maxCoeff();
}

// A 2 m × 1.5 m rectangle in the plane z = 0 split in two triangles (area 1.5 m² each), and a
// fifth point off the surface.
Vec3Object rectangle_state() {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1.5, 0), Vec3(0, 1.5, 0), Vec3(5, 5, 5)};
    s.init();
    return s;
}

MeshTopology rectangle_topology() {
    MeshTopology t;
    t.set_triangles({{0, 1, 2}, {0, 2, 3}});
    return t;
}

TEST(TrianglePressureForceField, PressureTimesRestAreaSplitInThirds) {
    Vec3Object s = rectangle_state();
    const MeshTopology topo = rectangle_topology();
    TrianglePressureForceField ff(s, topo, {0, 1}, Vec3(0, 10, -20));
    ff.init();
    EXPECT_DOUBLE_EQ(ff.total_rest_area(), 3.0);
    const std::vector<Vec3> f = force_of(ff, s);
    // each triangle: P·1.5 m², a third on each corner; corners 0 and 2 are in both triangles
    const Vec3 third = Vec3(0, 10, -20) * 1.5 / 3;
    EXPECT_TRUE(f[0].isApprox(2 * third, 1e-15));
    EXPECT_TRUE(f[1].isApprox(third, 1e-15));
    EXPECT_TRUE(f[2].isApprox(2 * third, 1e-15));
    EXPECT_TRUE(f[3].isApprox(third, 1e-15));
    EXPECT_EQ(f[4], Vec3::Zero());
    EXPECT_TRUE(total(f).isApprox(Vec3(0, 30, -60), 1e-15));
    // the rest area, not the current one: stretching the rectangle changes nothing
    s.position[2] = Vec3(4, 3, 1);
    s.position[3] = Vec3(0, 3, 0);
    EXPECT_TRUE(total(force_of(ff, s)).isApprox(Vec3(0, 30, -60), 1e-15));
}

TEST(TrianglePressureForceField, ConstantForceHasNoStiffnessAndItsPotentialIsMinusFDotX) {
    Vec3Object s = rectangle_state();
    const MeshTopology topo = rectangle_topology();
    TrianglePressureForceField ff(s, topo, {1}, Vec3(3, -1, 2));
    ff.init();
    s.position[2] += Vec3(0.1, -0.2, 0.3);
    EXPECT_GT(check_constant_force_field(ff, s), 1.0);
}

TEST(TrianglePressureForceField, CauchyStressModeUsesTheCurrentAreaVectorOnEachCornerAndNoStiffness) {
    Vec3Object s = rectangle_state();
    const MeshTopology topo = rectangle_topology();
    TrianglePressureForceField ff(s, topo, {0}, Vec3(1, 1, 1));
    ff.set_use_constant_force(false);
    ff.set_cauchy_stress(Mat3::Identity() * 6.0);
    ff.init();
    // σ = 6·I: σ·(b−a)×(c−a)/6 = (b−a)×(c−a) = (0, 0, 3) on EACH of the three corners
    std::vector<Vec3> f = force_of(ff, s);
    EXPECT_TRUE(f[0].isApprox(Vec3(0, 0, 3), 1e-15));
    EXPECT_TRUE(f[1].isApprox(Vec3(0, 0, 3), 1e-15));
    EXPECT_TRUE(f[2].isApprox(Vec3(0, 0, 3), 1e-15));
    // the current positions: doubling the triangle in x doubles the force
    s.position[1].x() = 4;
    s.position[2].x() = 4;
    f = force_of(ff, s);
    EXPECT_TRUE(f[0].isApprox(Vec3(0, 0, 6), 1e-15));
    // SOFA's addDForce adds nothing although f depends on x (reproduced)
    std::fill(s.dx.begin(), s.dx.end(), Vec3(1, 2, 3));
    std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
    ff.accumulate_dforce(1.0, 0.0);
    EXPECT_EQ(total(s.df), Vec3::Zero());
}

TEST(TrianglePressureForceField, BadTriangleIndexIsRefusedAtInit) {
    Vec3Object s = rectangle_state();
    const MeshTopology topo = rectangle_topology();
    TrianglePressureForceField ff(s, topo, {2}, Vec3(1, 0, 0));
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

// A non-planar quad (0, 1, 2, 3): triangles (0,1,2) of area ½|(2,0,0)×(2,3,0)| = 3 and (0,2,3) of
// area ½|(2,3,0)×(0,3,4)| = ½|(12,−8,6)| = √61; a flat unit square (1, 4, 5, 2) next to it.
Vec3Object quad_state() {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 3, 0), Vec3(0, 3, 4), Vec3(3, 0, 0), Vec3(3, 1, 0)};
    s.init();
    return s;
}

TEST(QuadPressureForceField, PressureTimesTheRestAreaOfItsTwoTrianglesSplitInQuarters) {
    Vec3Object s = quad_state();
    MeshTopology topo;
    topo.set_quads({{0, 1, 2, 3}, {1, 4, 5, 2}});
    QuadPressureForceField ff(s, topo, {0}, Vec3(0, -8, 4));
    ff.init();
    const double area = 3.0 + std::sqrt(61.0);  // geometry::Quad::area: (0,1,2) + (0,2,3)
    EXPECT_DOUBLE_EQ(ff.total_rest_area(), area);
    const std::vector<Vec3> f = force_of(ff, s);
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(f[i].isApprox(Vec3(0, -8, 4) * area / 4, 1e-15)) << i;
    EXPECT_EQ(f[4], Vec3::Zero());
    // the rest area, not the current one
    s.position[3] = Vec3(0, 9, 9);
    EXPECT_TRUE(total(force_of(ff, s)).isApprox(Vec3(0, -8, 4) * area, 1e-15));
    EXPECT_GT(check_constant_force_field(ff, s), 1.0);
}

TEST(QuadPressureForceField, PlaneSelectionAndBadIndices) {
    Vec3Object s = quad_state();
    MeshTopology topo;
    topo.set_quads({{0, 1, 2, 3}, {1, 4, 5, 2}});
    // dmin < z < dmax strictly: point 3 (z = 4) leaves quad 0 out
    EXPECT_EQ(quads_between_planes(topo, s.position, Vec3(0, 0, 1), -0.5, 0.5), (std::vector<Index>{1}));
    EXPECT_EQ(quads_between_planes(topo, s.position, Vec3(0, 0, 1), 0.0, 5.0), (std::vector<Index>{}));
    QuadPressureForceField bad(s, topo, {2}, Vec3(1, 0, 0));
    EXPECT_THROW(bad.init(), std::invalid_argument);
}

TEST(EdgePressureForceField, PressureTimesRestLengthSplitInHalves) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(3, 4, 0), Vec3(3, 4, 2)};
    s.init();
    MeshTopology topo;
    topo.set_edges({{0, 1}, {1, 2}});
    EdgePressureForceField ff(s, topo, {0, 1}, Vec3(0, 0, -0.1));
    ff.init();
    EXPECT_DOUBLE_EQ(ff.total_rest_length(), 7.0);
    std::vector<Vec3> f = force_of(ff, s);
    EXPECT_TRUE(f[0].isApprox(Vec3(0, 0, -0.25), 1e-15));  // half of 0.1·5
    EXPECT_TRUE(f[1].isApprox(Vec3(0, 0, -0.35), 1e-15));  // 0.25 + half of 0.1·2
    EXPECT_TRUE(f[2].isApprox(Vec3(0, 0, -0.1), 1e-15));
    s.position[2] = Vec3(10, 10, 10);  // rest lengths: unchanged
    EXPECT_TRUE(total(force_of(ff, s)).isApprox(Vec3(0, 0, -0.7), 1e-15));
    EXPECT_GT(check_constant_force_field(ff, s), 0.05);
}

TEST(EdgePressureForceField, SelectionsAlongPlanesAndByEdgeEnds) {
    MeshTopology topo;
    topo.set_edges({{0, 1}, {1, 2}, {2, 3}, {3, 0}});
    const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    // dmin < x·n < dmax strictly: y ∈ (−0.5, 0.5) holds points 0 and 1 only
    EXPECT_EQ(edges_between_planes(topo, x, Vec3(0, 1, 0), -0.5, 0.5), (std::vector<Index>{0}));
    EXPECT_EQ(edges_between_planes(topo, x, Vec3(0, 1, 0), 0.0, 1.0), (std::vector<Index>{}));
    // same ends in the same order; a reversed or unknown edge gives 0, as SOFA
    const std::vector<Edge> given = {{2, 3}, {0, 3}, {3, 0}};
    EXPECT_EQ(edge_indices_of(topo, given), (std::vector<Index>{2, 0, 3}));
}

// The closed surface of the tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1), faces wound outward
// ((b−a)×(c−a) points out).
Vec3Object tetrahedron_state() {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    s.init();
    return s;
}

MeshTopology tetrahedron_surface() {
    MeshTopology t;
    t.set_triangles({{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
    return t;
}

TEST(SurfacePressureForceField, EachTriangleGetsPressureTimesAreaAlongItsNormalAndTheSurfaceItsVolume) {
    Vec3Object s = tetrahedron_state();
    const MeshTopology topo = tetrahedron_surface();
    SurfacePressureParameters p;
    p.pressure = 60.0;
    p.triangle_indices = {3};  // the slanted face: area √3/2, normal (1,1,1)/√3
    SurfacePressureForceField one(s, topo, p, 0.01);
    one.init();
    const std::vector<Vec3> f = force_of(one, s);
    // p/6·(b−a)×(c−a) on each corner: 10·(1,1,1); Σ = p·area·n = 60·(√3/2)·(1,1,1)/√3 = 30·(1,1,1)
    EXPECT_TRUE(f[1].isApprox(Vec3(10, 10, 10), 1e-15));
    EXPECT_TRUE(total(f).isApprox(Vec3(30, 30, 30), 1e-15));
    EXPECT_EQ(f[0], Vec3::Zero());
    p.triangle_indices.clear();
    SurfacePressureForceField all(s, topo, p, 0.01);
    all.init();
    EXPECT_NEAR(all.mesh_volume(s.position), 1.0 / 6.0, 1e-15);
    EXPECT_LT(total(force_of(all, s)).norm(), 1e-13);  // a closed surface: no net force
    EXPECT_DOUBLE_EQ(all.last_pressure(), 60.0);
}

TEST(SurfacePressureForceField, QuadsShareTheirTwoTrianglesAsSofa) {
    // a unit square face z = 0, normal +z: Σ = p·1 m² along z; corners 0 and 2 get both halves
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology topo;
    topo.set_quads({{0, 1, 2, 3}});
    SurfacePressureParameters p;
    p.pressure = 12.0;
    SurfacePressureForceField ff(s, topo, p, 0.01);
    ff.init();
    const std::vector<Vec3> f = force_of(ff, s);
    EXPECT_TRUE(f[0].isApprox(Vec3(0, 0, 4), 1e-15));
    EXPECT_TRUE(f[1].isApprox(Vec3(0, 0, 2), 1e-15));
    EXPECT_TRUE(f[2].isApprox(Vec3(0, 0, 4), 1e-15));
    EXPECT_TRUE(f[3].isApprox(Vec3(0, 0, 2), 1e-15));
    EXPECT_TRUE(total(f).isApprox(Vec3(0, 0, 12), 1e-15));
}

TEST(SurfacePressureForceField, TangentStiffnessMatchesFiniteDifferencesAndForceIsMinusGradientOfMinusPV) {
    Vec3Object s = tetrahedron_state();
    const MeshTopology topo = tetrahedron_surface();
    SurfacePressureParameters p;
    p.pressure = 7.0;
    SurfacePressureForceField ff(s, topo, p, 0.01);
    ff.init();
    s.position[1] += Vec3(0.2, -0.1, 0.05);
    s.position[3] += Vec3(-0.1, 0.3, 0.2);
    const auto d = test::check_force_field_derivatives(ff, s, {1e-7, 1e-12, 1e-7});
    EXPECT_GT(d.k_dforce.cwiseAbs().maxCoeff(), 0.5);
    // on a closed surface K = −∂²(−pV)/∂x² is symmetric, although each triangle's block is not
    EXPECT_LT((d.k_dforce - d.k_dforce.transpose()).cwiseAbs().maxCoeff(), 1e-12);
}

// SOFA's addTriangleSurfacePressure stores, for each corner, the blocks (p/6)·[bc]ₓ, (p/6)·[ca]ₓ,
// (p/6)·[ab]ₓ (each entry times p/6) and addDForce adds (block·dx)·k three times; this scalar
// transcription is what SurfacePressureForceField.scn's bits (SOFA HEAD's, every step) rest on.
// The cross-product form ([bc]ₓdx_a + [ca]ₓdx_b + [ab]ₓdx_c)·(p/6·k) rounds otherwise here.
TEST(SurfacePressureForceField, DForceInSofasOperationsToTheBit) {
    Vec3Object s;
    s.position = {Vec3(0.1, 0.7, 0.3), Vec3(1.3, 0.2, -0.4), Vec3(0.3, 1.1, 0.9)};
    s.init();
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}});
    SurfacePressureParameters params;
    params.pressure = 5e4 / 3;
    SurfacePressureForceField ff(s, topo, params, 0.01);
    ff.init();
    (void)force_of(ff, s);
    const std::vector<Vec3> dx = {Vec3(0.3, -0.7, 0.11), Vec3(-0.13, 0.17, 0.19), Vec3(0.23, 0.29, -0.31)};
    const double k = -1.0 / 300;
    std::vector<Vec3> df(3, Vec3::Zero());
    ff.add_dforce(df, dx, k, 0.0);

    const std::vector<Vec3>& x = s.position;
    const double q = params.pressure / 6.0;
    const Vec3 edges[3] = {x[2] - x[1], x[0] - x[2], x[1] - x[0]};  // bc, ca, ab
    std::vector<Vec3> expected(3, Vec3::Zero());
    for (int corner = 0; corner < 3; ++corner)
        for (int v = 0; v < 3; ++v) {
            const Vec3& e = edges[v];
            const double m[3][3] = {
                {0.0 * q, -e[2] * q, e[1] * q}, {e[2] * q, 0.0 * q, -e[0] * q}, {-e[1] * q, e[0] * q, 0.0 * q}};
            Vec3 product;
            for (int r = 0; r < 3; ++r) product[r] = m[r][0] * dx[v][0] + m[r][1] * dx[v][1] + m[r][2] * dx[v][2];
            expected[corner] += Vec3(product[0] * k, product[1] * k, product[2] * k);
        }
    const Vec3 cross_form = (edges[0].cross(dx[0]) + edges[1].cross(dx[1]) + edges[2].cross(dx[2])) * (q * k);
    bool cross_form_differs = false;
    for (int corner = 0; corner < 3; ++corner) {
        EXPECT_EQ(df[corner], expected[corner]) << "corner " << corner;
        cross_form_differs = cross_form_differs || cross_form != expected[corner];
    }
    EXPECT_TRUE(cross_form_differs);  // these numbers tell the two orders apart
}

TEST(SurfacePressureForceField, TangentStiffnessOfAnOpenSurfaceIsNotSymmetric) {
    Vec3Object s = tetrahedron_state();
    const MeshTopology topo = tetrahedron_surface();
    SurfacePressureParameters p;
    p.pressure = 7.0;
    p.triangle_indices = {3, 1};
    SurfacePressureForceField ff(s, topo, p, 0.01);
    ff.init();
    s.position[2] += Vec3(0.1, 0.2, -0.1);
    // no energy (an open surface): f is not a gradient
    const auto d = test::check_force_field_derivatives(ff, s, {1e-7, 1e-12, std::nullopt});
    EXPECT_GT((d.k_dforce - d.k_dforce.transpose()).cwiseAbs().maxCoeff(), 0.1);
}

TEST(SurfacePressureForceField, WithoutTangentStiffnessAddsNothing) {
    Vec3Object s = tetrahedron_state();
    const MeshTopology topo = tetrahedron_surface();
    SurfacePressureParameters p;
    p.pressure = 7.0;
    p.use_tangent_stiffness = false;
    SurfacePressureForceField ff(s, topo, p, 0.01);
    ff.init();
    (void)force_of(ff, s);
    std::fill(s.dx.begin(), s.dx.end(), Vec3(1, 2, 3));
    std::fill(s.df.begin(), s.df.end(), Vec3::Zero());
    ff.accumulate_dforce(1.0, 0.0);
    EXPECT_EQ(total(s.df), Vec3::Zero());
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, 1.0);
    EXPECT_TRUE(t.empty());
}

TEST(SurfacePressureForceField, PulseModeRampsBetweenTheBoundsOncePerForceEvaluation) {
    Vec3Object s = tetrahedron_state();
    const MeshTopology topo = tetrahedron_surface();
    SurfacePressureParameters p;
    p.pressure = 5.0;
    p.pulse_mode = true;
    p.pressure_speed = 2.0;  // Pa/s; dt = 1 s → 2 Pa per evaluation
    p.pressure_lower_bound = 0.5;
    SurfacePressureForceField ff(s, topo, p, 1.0);
    ff.init();
    std::vector<double> seen;
    for (int i = 0; i < 8; ++i) {
        (void)force_of(ff, s);
        seen.push_back(ff.last_pressure());
    }
    // from 0 up by 2 to the bound 5 (clamped), down by 2 to the lower bound 0.5, up again
    EXPECT_EQ(seen, (std::vector<double>{2, 4, 5, 3, 1, 0.5, 2.5, 4.5}));
    // no speed: |pressure| per second (SOFA's init)
    p.pressure_speed = 0.0;
    SurfacePressureForceField slow(s, topo, p, 0.5);
    slow.init();
    EXPECT_DOUBLE_EQ(slow.parameters().pressure_speed, 5.0);
    (void)force_of(slow, s);
    EXPECT_DOUBLE_EQ(slow.last_pressure(), 2.5);
}

TEST(SurfacePressureForceField, VolumeConservationScalesByTheFirstVolumeOverTheCurrentOne) {
    Vec3Object s = tetrahedron_state();
    const MeshTopology topo = tetrahedron_surface();
    SurfacePressureParameters p;
    p.pressure = 10.0;
    p.volume_conservation = true;
    SurfacePressureForceField ff(s, topo, p, 0.01);
    ff.init();
    (void)force_of(ff, s);
    EXPECT_DOUBLE_EQ(ff.last_pressure(), 10.0);  // the first call records V₀ = 1/6
    for (Vec3& x : s.position) x *= 2.0;         // V = 8 V₀
    (void)force_of(ff, s);
    EXPECT_NEAR(ff.last_pressure(), 10.0 / 8.0, 1e-14);
}

TEST(SurfacePressureForceField, TheBoxSelectsTheTrianglesWithAllCornersInside) {
    Vec3Object s = tetrahedron_state();
    const MeshTopology topo = tetrahedron_surface();
    SurfacePressureParameters p;
    p.pressure = 6.0;
    p.box_min = Vec3(-0.1, -0.1, -0.1);
    p.box_max = Vec3(1.1, 1.1, 0.1);  // points 0, 1, 2: only the bottom face (0, 2, 1)
    SurfacePressureForceField ff(s, topo, p, 0.01);
    ff.init();
    const std::vector<Vec3> f = force_of(ff, s);
    // bottom face: area ½, outward normal −z: Σ = 6·½·(0,0,−1)
    EXPECT_TRUE(total(f).isApprox(Vec3(0, 0, -3), 1e-15));
    EXPECT_EQ(f[3], Vec3::Zero());
}

}  // namespace
}  // namespace penalty
