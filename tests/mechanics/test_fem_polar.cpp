// TetrahedronFEMForceField method polar (SOFA's initPolar / accumulateForcePolar): the polar
// rotation, stress-free rigid motions, rotation invariance, the stiffness against finite
// differences at a rotated rest state, and HexahedronFEMForceField's stiffness factors and method
// polar (HexahedronFEMForceField::computeRotationPolar).
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <random>

namespace penalty {
namespace {

TEST(PolarRotation, IsTheOrthogonalFactorOfRotationTimesStretch) {
    const Mat3 r = Eigen::AngleAxisd(0.9, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
    Mat3 s;
    s << 2.0, 0.3, -0.1, 0.3, 1.5, 0.2, -0.1, 0.2, 0.8;  // symmetric positive definite
    EXPECT_TRUE(polar_rotation(r * s).isApprox(r, 1e-12));
    EXPECT_TRUE(polar_rotation(Mat3::Identity()).isApprox(Mat3::Identity(), 1e-15));
    // a reflection stays a reflection (orthogonal, det −1), as SOFA's iteration
    Mat3 mirror = Mat3::Identity();
    mirror(2, 2) = -1;
    const Mat3 q = polar_rotation(mirror * s);
    EXPECT_TRUE((q * q.transpose()).isApprox(Mat3::Identity(), 1e-12));
    EXPECT_NEAR(q.determinant(), -1.0, 1e-12);
    EXPECT_TRUE(q.isApprox(mirror, 1e-12));
}

struct PolarBlock {
    RegularGridTopology grid{{3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1.2)};
    MeshTopology topo = test::kuhn_tetrahedra(grid);
};

TEST(TetrahedronFEMPolar, RigidMotionIsStressFreeAndStiffnessMatchesFiniteDifferences) {
    PolarBlock b;
    Vec3Object s;
    s.position = b.grid.points();
    s.init();
    TetrahedronFEMForceField ff(s, b.topo, 500.0, 0.35, FemMethod::Polar);
    ff.init();
    const Mat3 r = Eigen::AngleAxisd(0.8, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
    for (std::size_t i = 0; i < s.position.size(); ++i) s.position[i] = r * s.rest_position[i] + Vec3(0.3, -1, 2);
    const test::DerivativeTolerances tol{
        .dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt};
    const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, s, tol);
    EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 10.0);
    EXPECT_LT(d.force.cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_TRUE(d.k_dforce.isApprox(d.k_dforce.transpose(), 1e-12));
}

TEST(TetrahedronFEMPolar, ForcesRotateWithTheBodyAndMatchLargeForSmallStrains) {
    PolarBlock b;
    Vec3Object polar_state, large_state;
    for (Vec3Object* st : {&polar_state, &large_state}) {
        st->position = b.grid.points();
        st->init();
    }
    TetrahedronFEMForceField polar(polar_state, b.topo, 100, 0.3, FemMethod::Polar);
    TetrahedronFEMForceField large(large_state, b.topo, 100, 0.3, FemMethod::Large);
    polar.init();
    large.init();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1e-4, 1e-4);
    std::vector<Vec3> deformed = polar_state.rest_position;
    for (auto& p : deformed) p += Vec3(u(rng), u(rng), u(rng));
    polar_state.position = deformed;
    large_state.position = deformed;
    polar.accumulate_force();
    large.accumulate_force();
    const std::vector<Vec3> f1 = polar_state.force;
    // small strains: both corotational variants agree to first order in the strain
    double fmax = 0, diff = 0;
    for (std::size_t i = 0; i < f1.size(); ++i) {
        fmax = std::max(fmax, f1[i].norm());
        diff = std::max(diff, (f1[i] - large_state.force[i]).norm());
    }
    EXPECT_GT(fmax, 1e-4);
    EXPECT_LT(diff, 1e-3 * fmax);
    // rotated body: rotated forces
    const Mat3 r = Eigen::AngleAxisd(1.1, Vec3(0.2, 1, -0.4).normalized()).toRotationMatrix();
    for (std::size_t i = 0; i < deformed.size(); ++i) polar_state.position[i] = r * deformed[i];
    std::fill(polar_state.force.begin(), polar_state.force.end(), Vec3::Zero());
    polar.accumulate_force();
    for (std::size_t i = 0; i < f1.size(); ++i) EXPECT_LT((polar_state.force[i] - r * f1[i]).norm(), 1e-9 * fmax) << i;
}

TEST(HexahedronFEM, StiffnessFactorsScaleEachElement) {
    RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
    Vec3Object s;
    s.position = g.points();
    s.init();
    HexahedronFEMForceField full(s, g.mesh(), 1000, 0.3), weighted(s, g.mesh(), 1000, 0.3);
    weighted.set_stiffness_factors({0.5, 1.0});
    full.init();
    weighted.init();
    EXPECT_TRUE(weighted.element_stiffness()[0].isApprox(0.5 * full.element_stiffness()[0], 1e-15));
    EXPECT_EQ(weighted.element_stiffness()[1], full.element_stiffness()[1]);
}

/// A unit cube's corners in SOFA's hexahedron order.
std::array<Vec3, 8> unit_cube_corners() {
    return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
            Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
}

TEST(HexahedronFEMPolar, FrameOfARotatedShearedCubeIsTheTransposedRotation) {
    // p = Q·S·x⁰ on the unit cube: the mean edges are the columns of Q·S, so the edge matrix (rows
    // = edges) is S·Qᵀ = Qᵀ·(Q S Qᵀ), whose orthogonal polar factor is Qᵀ (rows = local axes).
    const Mat3 q = Eigen::AngleAxisd(0.7, Vec3(0.3, -1, 0.4).normalized()).toRotationMatrix();
    Mat3 stretch;
    stretch << 1.4, 0.25, -0.1, 0.25, 0.8, 0.15, -0.1, 0.15, 1.1;  // symmetric positive definite, sheared
    std::array<Vec3, 8> p = unit_cube_corners();
    for (Vec3& v : p) v = q * stretch * v + Vec3(2, -1, 0.5);
    EXPECT_TRUE(hexahedron_polar_frame(p).isApprox(q.transpose(), 1e-12));
    // the large frame follows the x edges, so a shear tilts it away from Qᵀ
    EXPECT_GT((hexahedron_edge_frame(p) - q.transpose()).norm(), 1e-2);
}

TEST(HexahedronFEMPolar, RigidMotionIsStressFreeAndStiffnessMatchesFiniteDifferences) {
    RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1.2));
    Vec3Object s;
    s.position = g.points();
    s.init();
    HexahedronFEMForceField ff(s, g.mesh(), 800.0, 0.3, FemMethod::Polar);
    ff.init();
    const Mat3 r = Eigen::AngleAxisd(0.9, Vec3(-1, 2, 0.5).normalized()).toRotationMatrix();
    for (std::size_t i = 0; i < s.position.size(); ++i) s.position[i] = r * s.rest_position[i] + Vec3(1, 0.5, -2);
    const test::DerivativeTolerances tol{
        .dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt};
    const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, s, tol);
    EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 10.0);
    EXPECT_LT(d.force.cwiseAbs().maxCoeff(), 1e-10);
}

TEST(HexahedronFEMPolar, ShearedElementRotatesByThePolarFactorNotTheEdgeFrame) {
    // One cube sheared in x by y (x += γ·y) and rotated by Q: the polar method measures the strain
    // in the frame Qᵀ·polar(shear), the large method in the frame of the x edges; both are
    // corotational, so their forces differ at finite shear but rotate with the body.
    RegularGridTopology g({2, 2, 2}, Vec3(0, 0, 0), Vec3(1, 1, 1));
    Vec3Object polar_state, large_state;
    for (Vec3Object* st : {&polar_state, &large_state}) {
        st->position = g.points();
        st->init();
    }
    HexahedronFEMForceField polar(polar_state, g.mesh(), 1000, 0.3, FemMethod::Polar);
    HexahedronFEMForceField large(large_state, g.mesh(), 1000, 0.3, FemMethod::Large);
    polar.init();
    large.init();
    const Mat3 q = Eigen::AngleAxisd(0.5, Vec3(0, 0, 1)).toRotationMatrix();
    for (std::size_t i = 0; i < polar_state.position.size(); ++i) {
        const Vec3 x0 = polar_state.rest_position[i];
        const Vec3 sheared(x0.x() + 0.2 * x0.y(), x0.y(), x0.z());
        polar_state.position[i] = q * sheared;
        large_state.position[i] = q * sheared;
    }
    polar.accumulate_force();
    large.accumulate_force();
    double fmax = 0, diff = 0;
    for (std::size_t i = 0; i < polar_state.force.size(); ++i) {
        fmax = std::max(fmax, polar_state.force[i].norm());
        diff = std::max(diff, (polar_state.force[i] - large_state.force[i]).norm());
    }
    EXPECT_GT(fmax, 1.0);
    EXPECT_GT(diff, 1e-3 * fmax);  // the frames differ: not the large method under another name
    std::array<Vec3, 8> p;
    for (std::size_t k = 0; k < 8; ++k)
        p[k] = polar_state.position[static_cast<std::size_t>(g.mesh().hexahedra()[0][k])];
    Mat3 edges;
    edges.row(0) = ((p[1] - p[0] + p[2] - p[3] + p[5] - p[4] + p[6] - p[7]) * 0.25).transpose();
    edges.row(1) = ((p[3] - p[0] + p[2] - p[1] + p[7] - p[4] + p[6] - p[5]) * 0.25).transpose();
    edges.row(2) = ((p[4] - p[0] + p[5] - p[1] + p[7] - p[3] + p[6] - p[2]) * 0.25).transpose();
    const Eigen::JacobiSVD<Mat3> svd(edges, Eigen::ComputeFullU | Eigen::ComputeFullV);
    EXPECT_TRUE(hexahedron_polar_frame(p).isApprox(svd.matrixU() * svd.matrixV().transpose(), 1e-10));
}

}  // namespace
}  // namespace penalty
