// TriangularBiquadraticSpringsForceField: SOFA's rest coefficients on a right triangle, no force
// at rest, f = −∂E/∂x everywhere, and the stiffness against finite differences where SOFA's
// matrix is the exact Jacobian (stretched triangles), SOFA's regularised matrix under
// compression checked for what it is (symmetric part of the spring terms, not exact).
#include "penalty/mechanics/triangular_biquadratic_springs.hpp"

#include "penalty_test/cloth.hpp"
#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

/// A 3×3-vertex cloth in the x-z plane (8 triangles, both diagonal directions).
using test::Cloth;

TEST(TriangularBiquadraticSprings, RestCoefficientsOfOneRightTriangle) {
    // (0,0,0), (1,0,0), (0,1,0): A = ½, ℓ² = (2, 1, 1), cot = (0, 1, 1);
    // s_j = (2 cot_j² (λ+μ) + μ) / (16 A), edge stiffness = s_j (one triangle)
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}});
    TriangularBiquadraticSpringsForceField ff(s, topo, {.young_modulus = 10.0, .poisson_ratio = 0.25});
    ff.init();
    const double lm = ff.lambda() + ff.mu();
    EXPECT_DOUBLE_EQ(ff.lambda(), 10.0 * 0.25 / (1 - 0.0625));
    EXPECT_DOUBLE_EQ(ff.mu(), 10.0 * 0.75 / (1 - 0.0625));
    EXPECT_DOUBLE_EQ(ff.edge_stiffness()[static_cast<std::size_t>(topo.edge_index(1, 2))], ff.mu() / 8);
    EXPECT_DOUBLE_EQ(ff.edge_stiffness()[static_cast<std::size_t>(topo.edge_index(0, 2))], (2 * lm + ff.mu()) / 8);
    EXPECT_DOUBLE_EQ(ff.edge_stiffness()[static_cast<std::size_t>(topo.edge_index(0, 1))], (2 * lm + ff.mu()) / 8);
    // at rest: no force, no energy (up to the area term of J = 1 − ε from rounding: (J − 1)³)
    Cloth c;
    TriangularBiquadraticSpringsForceField rest(c.state, c.topology, {.young_modulus = 15.0, .poisson_ratio = 0.9});
    rest.init();
    EXPECT_LT(c.force(rest).cwiseAbs().maxCoeff(), 1e-30);
    EXPECT_LT(rest.potential_energy(), 1e-30);
    EXPECT_THROW(TriangularBiquadraticSpringsForceField(c.state, c.topology, {.poisson_ratio = -1.0}),
                 std::invalid_argument);
}

TEST(TriangularBiquadraticSprings, StretchedDerivativesMatchFiniteDifferences) {
    // stretched by 10 % and perturbed: every triangle has J > 1 (no area term), SOFA's matrix is
    // the exact Hessian of E
    for (const bool angular : {true, false}) {
        Cloth c;
        TriangularBiquadraticSpringsForceField ff(
            c.state, c.topology, {.young_modulus = 15.0, .poisson_ratio = 0.3, .use_angular_springs = angular});
        ff.init();
        for (std::size_t i = 0; i < c.state.position.size(); ++i)
            c.state.position[i] =
                1.1 * c.state.position[i] + Vec3(0.02 * std::sin(1.0 + i), 0.05 * std::cos(2.0 * i), 0.01 * i);
        if (angular) {
            const auto d = test::check_force_field_derivatives(ff, c.state, {1e-6, 1e-12, 1e-6});
            EXPECT_GT(d.force.norm(), 0.1);
        } else {
            // SOFA's quirk: without angular springs the per-triangle edge vectors are never
            // updated, the matrix keeps −s_k Δ I only; the force is still the edge springs'
            const Eigen::VectorXd f = c.force(ff);
            const Eigen::VectorXd x0 = Vec3Object::flat(c.state.position);
            const Eigen::VectorXd grad = test::finite_gradient(
                x0,
                [&](const Eigen::VectorXd& x) {
                    for (std::size_t i = 0; i < c.state.position.size(); ++i)
                        c.state.position[i] = x.segment<3>(3 * static_cast<Eigen::Index>(i));
                    (void)c.force(ff);
                    return ff.potential_energy();
                },
                1e-6);
            EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-grad), f, 1e-6));
        }
    }
}

TEST(TriangularBiquadraticSprings, CompressedForceIsMinusTheEnergyGradient) {
    // shrunk to 80 %: J = 0.64 < 1 for every triangle, the area term acts; f = −∂E/∂x still
    // holds; SOFA's matrix is a regularised stand-in (not the Hessian).
    Cloth c;
    TriangularBiquadraticSpringsForceField ff(c.state, c.topology, {.young_modulus = 15.0, .poisson_ratio = 0.3});
    ff.init();
    for (std::size_t i = 0; i < c.state.position.size(); ++i)
        c.state.position[i] = 0.8 * c.state.position[i] + Vec3(0.01 * std::sin(1.0 + i), 0.0, 0.01 * std::cos(1.0 * i));
    const Eigen::VectorXd x0 = Vec3Object::flat(c.state.position);
    const auto set = [&](const Eigen::VectorXd& x) {
        for (std::size_t i = 0; i < c.state.position.size(); ++i)
            c.state.position[i] = x.segment<3>(3 * static_cast<Eigen::Index>(i));
    };
    const Eigen::VectorXd grad = test::finite_gradient(
        x0,
        [&](const Eigen::VectorXd& x) {
            set(x);
            (void)c.force(ff);
            return ff.potential_energy();
        },
        1e-6);
    set(x0);
    const Eigen::VectorXd f = c.force(ff);
    EXPECT_GT(f.norm(), 0.1);
    EXPECT_TRUE(test::near_relative(Eigen::VectorXd(-grad), f, 1e-6));
    // the assembled matrix is add_dforce's
    const auto n = static_cast<Eigen::Index>(f.size());
    Eigen::MatrixXd k_dforce(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {
        std::fill(c.state.dx.begin(), c.state.dx.end(), Vec3::Zero());
        std::fill(c.state.df.begin(), c.state.df.end(), Vec3::Zero());
        Vec3Object::flat(c.state.dx)[j] = 1.0;
        ff.accumulate_dforce(1.0, 0.0);
        k_dforce.col(j) = Vec3Object::flat(c.state.df);
    }
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, 1.0);
    SparseMatrix k(n, n);
    k.setFromTriplets(t.begin(), t.end());
    EXPECT_TRUE(test::near_relative(Eigen::MatrixXd(k), k_dforce, 1e-12));
}

TEST(TriangularBiquadraticSprings, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // a curved sheet of 8 192 triangles and about 12 000 edges (OrderedScatter::kMinElements or
    // more), in the grid's order and shuffled, perturbed so that some triangles are compressed
    // (the area term): each vertex's terms of the edge loop, the triangle loop and the product
    // in the loops' order, the energy summed edge by edge then term by term
    for (const bool shuffle : {false, true}) {
        const test::TriangleSheet sheet(shuffle);
        Vec3Object state;
        state.position = sheet.points;
        state.init();
        TriangularBiquadraticSpringsForceField springs(state, sheet.topology, {.young_modulus = 500.0});
        springs.init();
        ASSERT_GE(sheet.topology.triangles().size(), detail::OrderedScatter::kMinElements);
        test::expect_threads_give_one_threads_bits(springs, state, shuffle ? "shuffled" : "in order");
    }
}

TEST(TriangularBiquadraticSprings, KernelPathsGiveTheSameBits) {
    // the one-thread product (detail::triangle_edge_dforce) on the curved sheet: scalar and AVX
    // paths the same bits, the packed blocks following each force evaluation
    test::expect_sheet_kernel_paths<TriangularBiquadraticSpringsForceField>(
        BiquadraticSpringParameters{.young_modulus = 500.0}, "TriangularBiquadraticSprings");
}

}  // namespace
}  // namespace penalty
