// The triangle and quad surface force fields of SOFA's FEM and spring modules:
// FastTriangularBendingSprings (flat rest, linear force: exact derivatives everywhere),
// TriangularFEMForceFieldOptim (a uniform stretch in closed form, derivatives at any rigidly
// placed rest shape) and QuadBendingFEMForceField (the Q4 membrane's uniform stretch in closed
// form, out-of-plane derivatives), each with its assembled matrix against add_dforce.
#include "penalty/mechanics/fast_triangular_bending_springs.hpp"
#include "penalty/mechanics/quad_bending_fem.hpp"
#include "penalty/mechanics/triangular_fem_optim.hpp"

#include "penalty_test/cloth.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

using test::Cloth;

// ---- FastTriangularBendingSprings -------------------------------------------------------------
TEST(FastTriangularBendingSprings, OneElementPerInteriorEdgeAndNoForceFlat) {
    Cloth c;
    FastTriangularBendingSprings ff(c.state, c.topology, 2.0, 1e-6);
    ff.init();
    // the 3×3 cloth has 16 edges, 8 of them shared by two triangles
    EXPECT_EQ(ff.elements().size(), 8u);
    const Eigen::VectorXd f = c.force(ff);
    EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(ff.potential_energy(), 1e-25);
    for (const auto& e : ff.elements()) {
        EXPECT_NEAR(e.alpha[0] + e.alpha[1] + e.alpha[2] + e.alpha[3], 0.0, 1e-15) << "R is blind to translations";
        EXPECT_GT(e.lambda, 0.0);
    }
}

TEST(FastTriangularBendingSprings, ElementWeightsOfTwoRightTrianglesInClosedForm) {
    // square (0,0,0) (1,0,0) (1,1,0) (0,1,0) cut along (0,2): A = 1 (in triangle 0), B = 3, C, D = 0, 2
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology t;
    t.set_triangles({{0, 1, 2}, {0, 2, 3}});
    FastTriangularBendingSprings ff(s, t, 3.0, 1e-6);
    ff.init();
    ASSERT_EQ(ff.elements().size(), 1u);
    const auto& e = ff.elements()[0];
    EXPECT_EQ(e.vid[0], 1);
    EXPECT_EQ(e.vid[1], 3);
    // equal triangles: α = (½, ½, −½, −½); h_A = h_B = 1/√2, |CD| = √2: λ = (2/3)(√2)/(¼)·√2·3 = 16
    EXPECT_NEAR(e.alpha[0], 0.5, 1e-15);
    EXPECT_NEAR(e.alpha[2], -0.5, 1e-15);
    EXPECT_NEAR(e.lambda, 16.0, 1e-12);
    // lift A by w: R = (0, 0, w/2), f_A = −λ α_A R, E = ½ λ w²/4
    s.position[1].z() = 0.1;
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    ff.accumulate_force();
    EXPECT_NEAR(s.force[1].z(), -16.0 * 0.5 * 0.05, 1e-14);
    EXPECT_NEAR(ff.potential_energy(), 0.5 * 16.0 * 0.0025, 1e-14);
}

TEST(FastTriangularBendingSprings, DerivativesAreExactAnywhere) {
    Cloth c;
    FastTriangularBendingSprings ff(c.state, c.topology, 2.0, 1e-6);
    ff.init();
    c.deform();
    const auto d = test::check_force_field_derivatives(
        ff, c.state, {.dforce_vs_fd = 1e-7, .assembled_vs_dforce = 1e-13, .force_vs_energy = 1e-7});
    EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 0.1);
}

// ---- TriangularFEMForceFieldOptim -------------------------------------------------------------
TEST(TriangularFEMForceFieldOptim, UniformStretchOfARightTriangle) {
    // a = (0,0,0), b = (1,0,0), c = (0,1,0); b moved to (1+ε, 0, 0): frame unchanged, d_bx = −ε
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology t;
    t.set_triangles({{0, 1, 2}});
    TriangularFemOptimParameters p;
    p.young_modulus = {100};
    p.poisson_ratio = {0.25};
    TriangularFEMForceFieldOptim ff(s, t, p);
    ff.init();
    const double eps = 1e-3;
    s.position[1].x() += eps;
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    ff.accumulate_force();
    // strain (−ε, 0, 0); μ = E/(1+ν) = 80, γ = Eν/(1−ν²) = 80/3; σ₀ = (μ+γ)(−ε)/(2·1·1);
    // f_b = X cy σ₀ (cx = 0)
    const double mu = 80, gamma = 100 * 0.25 / (1 - 0.0625);
    EXPECT_NEAR(s.force[1].x(), (mu + gamma) * -eps / 2, 1e-12);
    EXPECT_NEAR(s.force[2].y(), gamma * -eps / 2, 1e-12);
    EXPECT_NEAR((s.force[0] + s.force[1] + s.force[2]).norm(), 0.0, 1e-15);
}

TEST(TriangularFEMForceFieldOptim, DerivativesAtARigidlyPlacedRestAndNearIt) {
    Cloth c;
    TriangularFemOptimParameters p;
    p.young_modulus = {60};
    p.poisson_ratio = {0.3};
    TriangularFEMForceFieldOptim ff(c.state, c.topology, p);
    ff.init();
    const Quat q(Eigen::AngleAxisd(0.9, Vec3(1, 2, -1).normalized()));
    for (Vec3& x : c.state.position) x = q * x + Vec3(0.5, -1, 2);
    const auto d = test::check_force_field_derivatives(
        ff, c.state, {.dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt});
    EXPECT_LT(d.force.cwiseAbs().maxCoeff(), 1e-12) << "stress-free";
    // near rest the frame's rotation is a small correction: df = K dx to the strain's order
    c.state.position[4] += Vec3(0.001, 0.0005, -0.0007);
    static_cast<void>(test::check_force_field_derivatives(
        ff, c.state, {.dforce_vs_fd = 5e-3, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt}));
}

// ---- QuadBendingFEMForceField -----------------------------------------------------------------
struct QuadPlate {
    Vec3Object state;
    MeshTopology topology;
    QuadPlate() {
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) state.position.emplace_back(2.0 * i, 1.0 * j, 0.0);
        state.init();
        topology.set_quads({{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}});
    }
};

TEST(QuadBendingFEMForceField, UniformStretchIsThePlaneStressMembrane) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology t;
    t.set_quads({{0, 1, 2, 3}});
    QuadBendingParameters p;
    p.young_modulus = {1000};
    p.poisson_ratio = {0.3};
    p.thickness = 0.1;
    QuadBendingFEMForceField ff(s, t, p);
    ff.init();
    // u = ε x, v = 0 (ε_yy = 0): σ_xx t = E t ε/(1 − ν²) on the right edge of height 1, half on each node
    const double eps = 1e-4;
    for (Vec3& x : s.position) x.x() *= 1 + eps;
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    ff.accumulate_force();
    const double edge_force = 1000 * 0.1 * eps / (1 - 0.09) * 1.0;
    // the stiffness uses the current (stretched) size: relative error of order ε
    EXPECT_NEAR(s.force[1].x(), -edge_force / 2, 1e-3 * edge_force);
    EXPECT_NEAR(s.force[2].x(), -edge_force / 2, 1e-3 * edge_force);
    EXPECT_NEAR(s.force[0].x(), edge_force / 2, 1e-3 * edge_force);
    EXPECT_NEAR((s.force[0] + s.force[1] + s.force[2] + s.force[3]).norm(), 0.0, 1e-15);
}

TEST(QuadBendingFEMForceField, DerivativesOfTheFlatPlate) {
    QuadPlate plate;
    QuadBendingParameters p;
    p.young_modulus = {2000};
    p.poisson_ratio = {0.49};
    p.thickness = 0.5;
    QuadBendingFEMForceField ff(plate.state, plate.topology, p);
    ff.init();
    // at rest D = 0, so the stiffness's dependence on the positions does not show: K is exact
    const auto rest = test::check_force_field_derivatives(
        ff, plate.state, {.dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-13, .force_vs_energy = std::nullopt});
    EXPECT_GT(rest.k_dforce.cwiseAbs().maxCoeff(), 1.0);
    // stretched in its plane, the plate's side lengths do not change to first order with the
    // out-of-plane coordinates: the z columns of K and the z gradient of the energy are exact
    for (Vec3& x : plate.state.position) x = Vec3(1.01 * x.x() + 0.02 * x.y(), 0.99 * x.y(), 0.0);
    const auto d = test::check_force_field_derivatives(
        ff, plate.state, {.dforce_vs_fd = 1e9, .assembled_vs_dforce = 1e-13, .force_vs_energy = std::nullopt});
    for (Eigen::Index i = 0; i < 9; ++i)
        EXPECT_TRUE(test::near_relative(Eigen::VectorXd(d.k_dforce.col(3 * i + 2)),
                                        Eigen::VectorXd(d.k_fd.col(3 * i + 2)), 1e-6))
            << "column z of point " << i;
    // with the out-of-plane moves alone, the energy ½ Dᵀ F of a bent plate has the gradient −f_z
    // up to the lengths' second-order change (K is evaluated at the current positions)
    for (std::size_t i = 0; i < 9; ++i) plate.state.position[i].z() = 1e-4 * std::sin(double(i));
    const auto energy = [&](const Eigen::VectorXd& z) {
        for (Eigen::Index i = 0; i < 9; ++i) plate.state.position[static_cast<std::size_t>(i)].z() = z[i];
        std::fill(plate.state.force.begin(), plate.state.force.end(), Vec3::Zero());
        ff.accumulate_force();
        return ff.potential_energy();
    };
    Eigen::VectorXd z0(9);
    for (Eigen::Index i = 0; i < 9; ++i) z0[i] = plate.state.position[static_cast<std::size_t>(i)].z();
    const Eigen::VectorXd g = test::finite_gradient(z0, energy, 1e-8);
    energy(z0);
    Eigen::VectorXd fz(9);
    for (Eigen::Index i = 0; i < 9; ++i) fz[i] = plate.state.force[static_cast<std::size_t>(i)].z();
    EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-g), fz, 1e-3));
}

TEST(QuadBendingFEMForceField, RefusesDegenerateQuads) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology t;
    t.set_quads({{0, 1, 2, 3}});
    QuadBendingFEMForceField ff(s, t, {});
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
