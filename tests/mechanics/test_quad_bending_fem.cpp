// QuadBendingFEMForceField: a uniform stretch is the plane-stress membrane in closed form, derivatives
// of the flat plate, degenerate quads refused.
#include "penalty/mechanics/fast_triangular_bending_springs.hpp"
#include "penalty/mechanics/quad_bending_fem.hpp"
#include "penalty/mechanics/triangular_fem_optim.hpp"

#include "penalty_test/cloth.hpp"
#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

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

TEST(QuadBendingFEMForceField, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // a 91 × 91-quad plate (8 281 quads, OrderedScatter::kMinElements or more), slightly curved,
    // its quads in the grid's order and shuffled: each vertex's four-slot additions and the
    // energy's twelve terms a quad in the loop's order
    constexpr int n = 91;
    for (const bool shuffle : {false, true}) {
        Vec3Object state;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) state.position.emplace_back(0.02 * i, 0.01 * j, 1e-4 * (i - j) * (i + j) / n);
        state.init();
        std::vector<Quad> quads;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int a = j * (n + 1) + i;
                quads.push_back({a, a + 1, a + n + 2, a + n + 1});
            }
        if (shuffle) std::shuffle(quads.begin(), quads.end(), std::mt19937(13));
        MeshTopology topology;
        topology.set_quads(std::move(quads));
        QuadBendingParameters p;
        p.thickness = 0.01;
        QuadBendingFEMForceField plate(state, topology, p);
        plate.init();
        test::expect_threads_give_one_threads_bits(plate, state, shuffle ? "shuffled" : "in order");
    }
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
