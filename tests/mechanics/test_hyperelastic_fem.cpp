// TetrahedronHyperelasticityFEMForceField and its five materials: S = 2∂W/∂C and dS[H] against
// finite differences, f = −∂E/∂x and df = K·dx (and the assembled matrix) on a deformed block,
// closed forms (stress-free rest, St Venant-Kirchhoff under a stretch, linear elasticity at rest),
// and the force and product on threads (the bits of one thread).
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/hyperelastic_fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "hyperelastic_laws.hpp"
#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/sanitizer.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>

namespace penalty {
namespace {

using namespace test_samples;

struct HyperBlock {
    RegularGridTopology grid{{3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1)};
    MeshTopology topo = test::kuhn_tetrahedra(grid);
    Vec3Object state;
    HyperBlock() {
        state.position = grid.points();
        state.init();
    }
    void deform(std::uint32_t seed, double amplitude) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(-1, 1);
        const Mat3 r = Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()).toRotationMatrix();
        for (std::size_t i = 0; i < state.position.size(); ++i)
            state.position[i] = r * (state.rest_position[i] + amplitude * Vec3(u(rng), u(rng), u(rng)));
    }
};

TEST(TetrahedronHyperelasticity, ForceIsMinusEnergyGradientAndStiffnessMatchesFiniteDifferences) {
    for (const HyperelasticLaw& law : every_law()) {
        SCOPED_TRACE(std::string(material_name(law.material)));
        HyperBlock b;
        TetrahedronHyperelasticityFEMForceField ff(b.state, b.topo.tetrahedra(), law);
        ff.init();
        b.deform(11, 0.08);
        const test::DerivativeTolerances tol{
            .dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = 1e-6};
        const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, b.state, tol);
        EXPECT_GT(d.force.cwiseAbs().maxCoeff(), 1.0);
        EXPECT_TRUE(d.k_dforce.isApprox(d.k_dforce.transpose(), 1e-9));  // a Hessian: symmetric
    }
}

TEST(TetrahedronHyperelasticity, RigidMotionIsStressFree) {
    for (const HyperelasticLaw& law : every_law()) {
        HyperBlock b;
        TetrahedronHyperelasticityFEMForceField ff(b.state, b.topo.tetrahedra(), law);
        ff.init();
        b.deform(3, 0.0);  // rotation only
        ff.accumulate_force();
        double fmax = 0;
        for (const Vec3& f : b.state.force) fmax = std::max(fmax, f.norm());
        EXPECT_LT(fmax, 1e-9 * law.parameters[0]) << material_name(law.material);
        EXPECT_NEAR(ff.potential_energy(), 0.0, 1e-9 * law.parameters[0]);
    }
}

TEST(TetrahedronHyperelasticity, StiffnessAtRestIsLinearElasticity) {
    // NeoHookean and St Venant-Kirchhoff (μ, λ) linearise to Hooke's law with E = μ(3λ + 2μ)/(λ + μ),
    // ν = λ/(2(λ + μ)): the stiffness at rest equals TetrahedronFEMForceField small's.
    const double mu = 400, lambda = 900;
    for (const HyperelasticMaterial m : {HyperelasticMaterial::NeoHookean, HyperelasticMaterial::StVenantKirchhoff}) {
        HyperBlock b;
        TetrahedronHyperelasticityFEMForceField ff(b.state, b.topo.tetrahedra(), {m, {mu, lambda}});
        TetrahedronFEMForceField linear(b.state, b.topo, mu * (3 * lambda + 2 * mu) / (lambda + mu),
                                        lambda / (2 * (lambda + mu)), FemMethod::Small);
        ff.init();
        linear.init();
        ff.accumulate_force();
        const auto n = static_cast<Index>(3 * b.state.num_dofs());
        TripletList t1, t2;
        ff.add_stiffness_triplets(t1, 0, 1.0);
        linear.add_stiffness_triplets(t2, 0, 1.0);
        SparseMatrix k1(n, n), k2(n, n);
        k1.setFromTriplets(t1.begin(), t1.end());
        k2.setFromTriplets(t2.begin(), t2.end());
        const Eigen::MatrixXd a(k1), bb(k2);
        EXPECT_LT((a - bb).cwiseAbs().maxCoeff(), 1e-9 * bb.cwiseAbs().maxCoeff()) << material_name(m);
    }
}

TEST(TetrahedronHyperelasticity, BadParametersAreRejected) {
    HyperBlock b;
    EXPECT_THROW(
        TetrahedronHyperelasticityFEMForceField(b.state, b.topo.tetrahedra(), {HyperelasticMaterial::Ogden, {1, 2}}),
        std::invalid_argument);
    EXPECT_THROW(
        TetrahedronHyperelasticityFEMForceField(b.state, b.topo.tetrahedra(), {HyperelasticMaterial::Ogden, {1, 0, 3}}),
        std::invalid_argument);
    std::vector<Tetrahedron> flat{{0, 1, 2, 1}};
    TetrahedronHyperelasticityFEMForceField degenerate(b.state, flat, {HyperelasticMaterial::NeoHookean, {1, 1}});
    EXPECT_THROW(degenerate.init(), std::invalid_argument);
}

TEST(TetrahedronHyperelasticity, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // 13 × 12 × 9 cells, 8 424 tetrahedra (above OrderedScatter::kMinElements), in the grid's
    // order and shuffled, every material
    const RegularGridTopology grid({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    const MeshTopology spatial = test::kuhn_tetrahedra(grid);
    ASSERT_GE(spatial.tetrahedra().size(), detail::OrderedScatter::kMinElements);
    std::vector<Tetrahedron> shuffled = spatial.tetrahedra();
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(6));
    for (const bool shuffle : {false, true})
        for (const HyperelasticLaw& law : every_law()) {
            Vec3Object state;
            state.position = grid.points();
            state.init();
            TetrahedronHyperelasticityFEMForceField fem(state, shuffle ? shuffled : spatial.tetrahedra(), law);
            fem.init();
            const test::ElementProducts one = test::element_products_on_threads(fem, state, 1, 0.02, -0.37);
            EXPECT_EQ(one.chunks, 0U);
            EXPECT_NE(one.energy, 0.0);
            for (const int threads : test::thread_counts_to_compare({2, 3, 8})) {
                const test::ElementProducts many = test::element_products_on_threads(fem, state, threads, 0.02, -0.37);
                const std::string where = std::string(material_name(law.material)) + ", " + std::to_string(threads) +
                                          " threads" + (shuffle ? ", shuffled" : "");
                EXPECT_GT(many.chunks, 1U) << where;
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_TRUE(test::same_vectors_bits(many.force, one.force)) << where;
                EXPECT_TRUE(test::same_vectors_bits(many.product, one.product)) << where;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
            }
        }
}

}  // namespace
}  // namespace penalty
