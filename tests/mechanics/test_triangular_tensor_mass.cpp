// TriangularTensorMassForceField: SOFA's Lamé coefficients, the edge tensors of one triangle in
// closed form, a force linear in the displacement that vanishes under translation, and its
// derivatives by finite differences.
#include "penalty/mechanics/triangular_tensor_mass.hpp"

#include "penalty_test/cloth.hpp"
#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

/// A 3×3-vertex cloth in the x-z plane (8 triangles, both diagonal directions).
using test::Cloth;

TEST(TriangularTensorMass, LameCoefficientsAsSofa) {
    Cloth c;
    const TriangularTensorMassForceField ff(c.state, c.topology, {.young_modulus = 15.0, .poisson_ratio = 0.9});
    // updateLameCoefficients: λ = E ν / (1 − ν²), μ = E (1 − ν) / (1 − ν²)
    EXPECT_DOUBLE_EQ(ff.lambda(), 15.0 * 0.9 / 0.19);
    EXPECT_DOUBLE_EQ(ff.mu(), 15.0 * 0.1 / 0.19);
    EXPECT_THROW(TriangularTensorMassForceField(c.state, c.topology, {.young_modulus = 1.0, .poisson_ratio = 1.0}),
                 std::invalid_argument);
    EXPECT_THROW(TriangularTensorMassForceField(c.state, c.topology, {.young_modulus = -1.0, .poisson_ratio = 0.3}),
                 std::invalid_argument);
}

TEST(TriangularTensorMass, EdgeTensorsOfOneRightTriangle) {
    // Triangle (0,1,2) = (0,0,0), (1,0,0), (0,1,0): ℓ² opposite each vertex = 2, 1, 1; A = ½;
    // cot = (0, 1, 1). Edge opposite vertex 0 is (1,2): j = 0, k = 1, l = 2, p_l = x0 − x1 = (−1,0,0),
    // p_k = x0 − x2 = (0,−1,0), diagonal −cot_0 (λ+μ)/2 = 0; the edge (1,2) starts at t_1 ≠ t_l,
    // so its tensor is Mᵀ with M = λ/2 · p_l p_kᵀ + μ/4 · p_k p_lᵀ.
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}});
    TriangularTensorMassForceField ff(s, topo, {.young_modulus = 10.0, .poisson_ratio = 0.25});
    ff.init();
    const double lambda = ff.lambda(), mu = ff.mu();
    const auto e12 = static_cast<std::size_t>(topo.edge_index(1, 2));
    ASSERT_EQ(topo.edges()[e12][0], 1);
    Mat3 m =
        lambda / 2 * Vec3(-1, 0, 0) * Vec3(0, -1, 0).transpose() + mu / 4 * Vec3(0, -1, 0) * Vec3(-1, 0, 0).transpose();
    EXPECT_TRUE(ff.edge_tensors()[e12].isApprox(m.transpose(), 1e-15)) << ff.edge_tensors()[e12];
    // the three tensors have the diagonal −cot_j (λ+μ)/2: 0, −(λ+μ)/2, −(λ+μ)/2
    double trace_sum = 0;
    for (const Mat3& t : ff.edge_tensors()) trace_sum += t.trace();
    // traces: p_l·p_k (λ/(4A) + μ/(8A)) + 3·diagonal per edge; Σ p_l·p_k over j = 0 + 1 + 1... (x0−x1)·(x0−x2) = 0,
    // (x1−x2)·(x1−x0) = 1, (x2−x0)·(x2−x1) = 1
    EXPECT_NEAR(trace_sum, 2 * (lambda / 2 + mu / 4) - 3 * (lambda + mu), 1e-12);
}

TEST(TriangularTensorMass, LinearInTheDisplacementAndZeroUnderTranslation) {
    Cloth c;
    TriangularTensorMassForceField ff(c.state, c.topology, {.young_modulus = 15.0, .poisson_ratio = 0.3});
    ff.init();
    const auto rest = c.state.position;
    const auto force_at = [&](double scale, const Vec3& shift) {
        for (std::size_t i = 0; i < rest.size(); ++i) {
            const Vec3 u(0.1 * std::sin(3.0 * i), 0.2 * std::cos(2.0 * i), 0.05 * i);
            c.state.position[i] = rest[i] + scale * u + shift;
        }
        std::fill(c.state.force.begin(), c.state.force.end(), Vec3::Zero());
        ff.accumulate_force();
        return Vec3Object::flat(c.state.force).eval();
    };
    const Eigen::VectorXd f1 = force_at(1.0, Vec3::Zero());
    const Eigen::VectorXd f2 = force_at(2.0, Vec3::Zero());
    EXPECT_GT(f1.norm(), 0.1);
    EXPECT_LT((f2 - 2 * f1).cwiseAbs().maxCoeff(), 1e-12 * f1.cwiseAbs().maxCoeff());
    const Eigen::VectorXd shifted = force_at(1.0, Vec3(3.0, -2.0, 0.5));
    EXPECT_LT((shifted - f1).cwiseAbs().maxCoeff(), 1e-12 * f1.cwiseAbs().maxCoeff());
    // forces sum to zero (internal)
    Vec3 total = Vec3::Zero();
    for (const Vec3& f : c.state.force) total += f;
    EXPECT_LT(total.norm(), 1e-12 * f1.norm());
}

TEST(TriangularTensorMass, ForceDerivativesMatchFiniteDifferences) {
    Cloth c;
    TriangularTensorMassForceField ff(c.state, c.topology, {.young_modulus = 15.0, .poisson_ratio = 0.9});
    ff.init();
    for (std::size_t i = 0; i < c.state.position.size(); ++i)
        c.state.position[i] += Vec3(0.05 * std::sin(1.0 + i), 0.1 * std::cos(2.0 * i), 0.03 * i);
    const auto d = test::check_force_field_derivatives(ff, c.state, {1e-6, 1e-12, 1e-6});
    EXPECT_GT(d.force.norm(), 0.1);
    EXPECT_GT(d.k_dforce.norm(), 1.0);
}

TEST(TriangularTensorMass, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // the edges of a curved sheet of 8 192 triangles (about 12 000, OrderedScatter::kMinElements
    // or more), in the grid's order and shuffled
    for (const bool shuffle : {false, true}) {
        const test::TriangleSheet sheet(shuffle);
        Vec3Object state;
        state.position = sheet.points;
        state.init();
        TriangularTensorMassForceField tensors(state, sheet.topology, {.young_modulus = 500.0, .poisson_ratio = 0.3});
        tensors.init();
        ASSERT_GE(sheet.topology.edges().size(), detail::OrderedScatter::kMinElements);
        test::expect_threads_give_one_threads_bits(tensors, state, shuffle ? "shuffled" : "in order");
    }
}

}  // namespace
}  // namespace penalty
