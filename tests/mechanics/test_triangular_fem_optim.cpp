// TriangularFEMForceFieldOptim: a uniform stretch of a right triangle in closed form, derivatives at a
// rigidly placed rest shape and near it, the force and product on threads (the bits of one
// thread).
#include "penalty/mechanics/fast_triangular_bending_springs.hpp"
#include "penalty/mechanics/quad_bending_fem.hpp"
#include "penalty/mechanics/triangular_fem_optim.hpp"

#include "penalty_test/cloth.hpp"
#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

namespace penalty {
namespace {

using test::Cloth;

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

TEST(TriangularFEMForceFieldOptim, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    for (const bool shuffle : {false, true}) {
        const test::TriangleSheet sheet(shuffle);
        ASSERT_GE(sheet.topology.triangles().size(), detail::OrderedScatter::kMinElements);
        Vec3Object state;
        state.position = sheet.points;
        state.init();
        TriangularFEMForceFieldOptim fem(state, sheet.topology,
                                         {.young_modulus = {3e4}, .poisson_ratio = {0.3}, .rest_scale = {}});
        fem.init();
        test::expect_threads_give_one_threads_bits(fem, state, shuffle ? "shuffled" : "in order");
    }
}

}  // namespace
}  // namespace penalty
