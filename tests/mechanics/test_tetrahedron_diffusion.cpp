// TetrahedronDiffusionFEMForceField<Vec1d>: the edge coefficients in closed form (the P1
// Laplacian's off-diagonal entries D·V·∇Nᵢ·∇Nⱼ), f = −∂E/∂x and df = K·dx by central differences,
// the assembled K against the product, conservation of the diffused quantity.
#include "penalty/mechanics/tetrahedron_diffusion.hpp"

#include "penalty_test/finite_difference.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

namespace penalty {
namespace {

/// Two tetrahedra sharing face 1-2-3 (the first the unit corner tetrahedron), slightly skewed.
std::vector<Vec3> diffusion_points() {
    return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0.9, 0.8, 1.1)};
}
MeshTopology diffusion_mesh() {
    MeshTopology t;
    t.set_tetrahedra({{0, 1, 2, 3}, {1, 2, 3, 4}});
    return t;
}

struct DiffusionSetup {
    MeshTopology mesh = diffusion_mesh();
    Vec1Object state;
    std::unique_ptr<TetrahedronDiffusionFEMForceField> ff;
    explicit DiffusionSetup(double d = 0.05) {
        state.resize(5);
        ff = std::make_unique<TetrahedronDiffusionFEMForceField>(state, mesh);
        ff->set_constant_coefficient(d);
        ff->set_geometry(diffusion_points());
    }
    Eigen::VectorXd force(const Eigen::VectorXd& x) {
        std::vector<double> f(5, 0.0);
        std::vector<double> xs(x.data(), x.data() + x.size());
        ff->add_force(f, xs, {});
        return Eigen::Map<Eigen::VectorXd>(f.data(), 5);
    }
};

Eigen::VectorXd random_temperatures(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd x(5);
    for (Eigen::Index i = 0; i < 5; ++i) x[i] = u(rng);
    return x;
}

TEST(TetrahedronDiffusion, EdgeCoefficientsAreTheLaplaciansOffDiagonalEntries) {
    // the corner tetrahedron alone: ∇N0 = (−1, −1, −1), ∇Nk = e_k, V = 1/6: the edges from 0
    // get D·V·(−1), the others D·V·0
    MeshTopology one;
    one.set_tetrahedra({{0, 1, 2, 3}});
    Vec1Object s;
    s.resize(4);
    TetrahedronDiffusionFEMForceField ff(s, one);
    ff.set_constant_coefficient(0.3);
    ff.set_geometry({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
    ff.init();
    for (std::size_t e = 0; e < one.edges().size(); ++e) {
        const Edge& edge = one.edges()[e];
        const bool from_origin = edge[0] == 0 || edge[1] == 0;
        EXPECT_NEAR(ff.edge_coefficients()[e], from_origin ? -0.3 / 6 : 0.0, 1e-15) << e;
    }
}

TEST(TetrahedronDiffusion, TransverseAnisotropyScalesTheGradientsAlongItsDirection) {
    // c = D·V·∇Nk·(I + (r − 1) a aᵀ)∇Nl with a = e_x, r = 4: edge 0-1 gets D·V·(−1)·4
    MeshTopology one;
    one.set_tetrahedra({{0, 1, 2, 3}});
    Vec1Object s;
    s.resize(4);
    TetrahedronDiffusionFEMForceField ff(s, one);
    ff.set_anisotropy(4.0, {Vec3(1, 0, 0)});
    ff.set_geometry({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
    ff.init();
    EXPECT_NEAR(ff.edge_coefficients()[std::size_t(one.edge_index(0, 1))], -4.0 / 6, 1e-15);
    EXPECT_NEAR(ff.edge_coefficients()[std::size_t(one.edge_index(0, 2))], -1.0 / 6, 1e-15);
    EXPECT_NEAR(ff.edge_coefficients()[std::size_t(one.edge_index(1, 2))], 0.0, 1e-15);
}

TEST(TetrahedronDiffusion, ForceIsMinusTheEnergyGradientAndConservesTheTotal) {
    DiffusionSetup d;
    d.ff->init();
    const Eigen::VectorXd x = random_temperatures(7);
    const Eigen::VectorXd f = d.force(x);
    const Eigen::VectorXd grad = test::finite_gradient(x, [&](const Eigen::VectorXd& y) {
        (void)d.force(y);
        return d.ff->potential_energy();
    });
    EXPECT_TRUE(test::near_relative(f, Eigen::VectorXd(-grad), 1e-8));
    EXPECT_NEAR(f.sum(), 0.0, 1e-15);          // what leaves a point enters its neighbours
    EXPECT_GT(d.ff->potential_energy(), 0.0);  // heat flows down the gradient: E ≥ 0
    EXPECT_EQ(d.force(Eigen::VectorXd::Constant(5, 0.7)).cwiseAbs().maxCoeff(), 0.0);  // uniform: no flux
}

TEST(TetrahedronDiffusion, DforceAndAssembledStiffnessAreTheForceJacobian) {
    DiffusionSetup d;
    d.ff->init();
    const Eigen::VectorXd x = random_temperatures(11);
    const Eigen::MatrixXd k_fd = test::finite_jacobian(x, [&](const Eigen::VectorXd& y) { return d.force(y); });
    TripletList triplets;
    d.ff->add_stiffness_triplets(triplets, 0, 1.0);
    SparseMatrix k(5, 5);
    k.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::MatrixXd k_dense(k);
    EXPECT_TRUE(test::near_relative(k_dense, k_fd, 1e-8));
    EXPECT_LE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k_dense).eigenvalues().maxCoeff(), 1e-14);  // K ≤ 0
    const Eigen::VectorXd dx = random_temperatures(13);
    std::vector<double> df(5, 0.0);
    std::vector<double> dxs(dx.data(), dx.data() + 5);
    d.ff->add_dforce(df, dxs, 0.25, 3.0);  // b_factor: no damping
    EXPECT_TRUE(
        test::near_relative(Eigen::Map<Eigen::VectorXd>(df.data(), 5), Eigen::VectorXd(0.25 * (k_dense * dx)), 1e-14));
}

TEST(TetrahedronDiffusion, RefusesBadInputWithAClearMessage) {
    DiffusionSetup d;
    d.ff->set_tetrahedron_coefficients({1.0});
    EXPECT_THROW(d.ff->init(), std::invalid_argument);  // one value for two tetrahedra
    DiffusionSetup flat;
    flat.ff->set_geometry({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(0.9, 0.8, 1.1)});
    EXPECT_THROW(flat.ff->init(), std::invalid_argument);  // tetrahedron 0 is flat
    DiffusionSetup aniso;
    aniso.ff->set_anisotropy(2.0, {});
    EXPECT_THROW(aniso.ff->init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
