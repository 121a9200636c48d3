// FastTriangularBendingSprings (flat rest, linear force): one element per interior edge, the element
// weights of two right triangles in closed form, exact derivatives everywhere, the force and
// product on threads (the bits of one thread).
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

TEST(FastTriangularBendingSprings, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // a curved sheet of 8 192 triangles (about 12 000 interior edges, more than
    // OrderedScatter::kMinElements), in the grid's order and shuffled: each vertex's four
    // subtractions an element of the product stored together and replayed in element order
    for (const bool shuffle : {false, true}) {
        const test::TriangleSheet sheet(shuffle);
        Vec3Object state;
        state.position = sheet.points;
        state.init();
        FastTriangularBendingSprings springs(state, sheet.topology, 3.0, 1e-6);
        springs.init();
        ASSERT_GE(springs.elements().size(), detail::OrderedScatter::kMinElements);
        test::expect_threads_give_one_threads_bits(springs, state, shuffle ? "shuffled" : "in order");
    }
}

}  // namespace
}  // namespace penalty
