// TriangularQuadraticSpringsForceField: SOFA's rest coefficients on a right triangle, no force at
// rest, and f = −∂E/∂x, df = K·dx by finite differences, with and without angular springs.
#include "penalty/mechanics/triangular_quadratic_springs.hpp"

#include "penalty_test/cloth.hpp"
#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace penalty {
namespace {

TEST(TriangularQuadraticSprings, RestCoefficientsOfOneRightTriangle) {
    // (0,0,0), (1,0,0), (0,1,0): A = ½, ℓ = (√2, 1, 1), cot = (0, 1, 1);
    // s_j = ℓ_j² (2 cot_j² (λ+μ) + μ) / (8 A)
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}});
    TriangularQuadraticSpringsForceField ff(s, topo, {.young_modulus = 10.0, .poisson_ratio = 0.25});
    ff.init();
    const double lm = ff.lambda() + ff.mu();
    EXPECT_NEAR(ff.edge_stiffness()[static_cast<std::size_t>(topo.edge_index(1, 2))], 2 * ff.mu() / 4, 1e-14);
    EXPECT_NEAR(ff.edge_stiffness()[static_cast<std::size_t>(topo.edge_index(0, 2))], (2 * lm + ff.mu()) / 4, 1e-14);
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    ff.accumulate_force();
    for (const Vec3& f : s.force) EXPECT_EQ(f, Vec3::Zero());
    EXPECT_EQ(ff.potential_energy(), 0.0);
    EXPECT_THROW(TriangularQuadraticSpringsForceField(s, topo, {.poisson_ratio = 1.0}), std::invalid_argument);
}

TEST(TriangularQuadraticSprings, RefusalsNameTheComponentAndTheValue) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology topo;
    topo.set_triangles({{0, 1, 3}});
    const auto message = [&](const QuadraticSpringParameters& p, bool init) {
        try {
            TriangularQuadraticSpringsForceField ff(s, topo, p);
            if (init) ff.init();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(message({.young_modulus = -1.0}, false),
              "TriangularQuadraticSpringsForceField: youngModulus must be finite and >= 0, got -1");
    EXPECT_EQ(message({.poisson_ratio = -1.0}, false),
              "TriangularQuadraticSpringsForceField: poissonRatio must be finite and not +-1, got -1");
    EXPECT_EQ(message({.damping_ratio = std::numeric_limits<double>::quiet_NaN()}, false),
              "TriangularQuadraticSpringsForceField: dampingRatio must be finite, got nan");
    EXPECT_EQ(message({}, true), "TriangularQuadraticSpringsForceField: point 3 out of range for a state of 3 points");
    // the Lamé coefficients of E = 10, ν = 0.25: λ = 2.5/0.9375, μ = 7.5/0.9375
    TriangularQuadraticSpringsForceField ff(s, topo, {.young_modulus = 10.0, .poisson_ratio = 0.25});
    EXPECT_DOUBLE_EQ(ff.lambda(), 2.5 / 0.9375);
    EXPECT_DOUBLE_EQ(ff.mu(), 7.5 / 0.9375);
}

/// The cloth of the derivative tests, stretched in x, squeezed in z and lifted: edges both longer
/// and shorter than at rest.
using test::Cloth;

TEST(TriangularQuadraticSprings, SofasAngularStiffnessIsOffByOneTerm) {
    // SOFA's matrix with angular springs is not the Hessian (see exact_angular_stiffness): the
    // exact variant matches finite differences, SOFA's differs from it by Σ s_k δ_k/L U Uᵀ
    Cloth exact_cloth;
    TriangularQuadraticSpringsForceField exact(
        exact_cloth.state, exact_cloth.topology,
        {.young_modulus = 15.0, .poisson_ratio = 0.3, .exact_angular_stiffness = true});
    exact.init();
    exact_cloth.deform();
    const auto e = test::check_force_field_derivatives(exact, exact_cloth.state, {1e-6, 1e-12, 1e-6});
    Cloth sofa_cloth;
    TriangularQuadraticSpringsForceField sofa(sofa_cloth.state, sofa_cloth.topology,
                                              {.young_modulus = 15.0, .poisson_ratio = 0.3});
    sofa.init();
    sofa_cloth.deform();
    const auto n = static_cast<Eigen::Index>(3 * sofa_cloth.state.num_dofs());
    std::fill(sofa_cloth.state.force.begin(), sofa_cloth.state.force.end(), Vec3::Zero());
    sofa.accumulate_force();
    EXPECT_TRUE(test::near_relative(Vec3Object::flat(sofa_cloth.state.force).eval(), e.force, 1e-15));  // same force
    Eigen::MatrixXd k_sofa(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {
        std::fill(sofa_cloth.state.dx.begin(), sofa_cloth.state.dx.end(), Vec3::Zero());
        std::fill(sofa_cloth.state.df.begin(), sofa_cloth.state.df.end(), Vec3::Zero());
        Vec3Object::flat(sofa_cloth.state.dx)[j] = 1.0;
        sofa.accumulate_dforce(1.0, 0.0);
        k_sofa.col(j) = Vec3Object::flat(sofa_cloth.state.df);
    }
    // the two differ only by −s_k δ_k/L_k · U Uᵀ per pair (symmetric, non-zero when stretched)
    const Eigen::MatrixXd difference = e.k_dforce - k_sofa;
    EXPECT_GT(difference.cwiseAbs().maxCoeff(), 1e-3);
    EXPECT_LT((difference - difference.transpose()).cwiseAbs().maxCoeff(), 1e-12 * difference.cwiseAbs().maxCoeff());
    // translation invariance holds for both: each row sums to zero over the three axes' columns
    for (Eigen::Index r = 0; r < n; ++r)
        for (Eigen::Index axis = 0; axis < 3; ++axis) {
            double row_sum = 0;
            for (Eigen::Index c = axis; c < n; c += 3) row_sum += k_sofa(r, c);
            EXPECT_NEAR(row_sum, 0.0, 1e-12 * k_sofa.cwiseAbs().maxCoeff());
        }
}

TEST(TriangularQuadraticSprings, ForceDerivativesMatchFiniteDifferences) {
    for (const bool angular : {false}) {
        Vec3Object s;
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) s.position.emplace_back(i, 0.0, 1.2 * j);
        s.init();
        MeshTopology topo;
        topo.set_triangles({{0, 1, 4}, {0, 4, 3}, {1, 2, 4}, {2, 5, 4}, {3, 4, 6}, {4, 7, 6}, {4, 5, 8}, {4, 8, 7}});
        TriangularQuadraticSpringsForceField ff(
            s, topo, {.young_modulus = 15.0, .poisson_ratio = 0.3, .use_angular_springs = angular});
        ff.init();
        // stretched in x, squeezed in z, lifted: edges both longer and shorter than at rest
        for (std::size_t i = 0; i < s.position.size(); ++i)
            s.position[i] = Vec3(1.1 * s.position[i].x(), 0.2 * std::sin(1.0 + i), 0.9 * s.position[i].z() + 0.02 * i);
        const auto d = test::check_force_field_derivatives(ff, s, {1e-6, 1e-12, 1e-6});
        EXPECT_GT(d.force.norm(), 0.1) << (angular ? "angular" : "edges only");
    }
}

TEST(TriangularQuadraticSprings, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // a curved sheet of 8 192 triangles (OrderedScatter::kMinElements), in the grid's order and
    // shuffled, with and without angular springs
    for (const bool angular : {true, false})
        for (const bool shuffle : {false, true}) {
            const test::TriangleSheet sheet(shuffle);
            Vec3Object state;
            state.position = sheet.points;
            state.init();
            TriangularQuadraticSpringsForceField springs(state, sheet.topology,
                                                         {.young_modulus = 500.0, .use_angular_springs = angular});
            springs.init();
            test::expect_threads_give_one_threads_bits(
                springs, state, std::string(shuffle ? "shuffled" : "in order") + (angular ? ", angular" : ""));
        }
}

TEST(TriangularQuadraticSprings, KernelPathsGiveTheSameBits) {
    // the one-thread product (detail::triangle_edge_dforce) on the curved sheet: scalar and AVX
    // paths the same bits, the packed blocks following each force evaluation
    test::expect_sheet_kernel_paths<TriangularQuadraticSpringsForceField>(
        QuadraticSpringParameters{.young_modulus = 500.0, .use_angular_springs = true}, "TriangularQuadraticSprings");
}

}  // namespace
}  // namespace penalty
