// The edge-block product of the triangle spring fields (kernels/mechanics/triangle_edge_blocks.cpp):
// the scalar path is SOFA's addDForce of TriangularQuadraticSprings / TriangularBiquadraticSprings
// written out here (per triangle, per edge k: δ = dx_i − dx_j, df_i += (D_k·δ)·k, df_j −= (D_kᵀ·δ)·k,
// each row summed left to right), and the AVX path is the scalar one to the bit (zeros of both
// signs, subnormals, infinities; a NaN is a NaN on both) on random meshes whose triangles share
// vertices, repeat one (degenerate) and come in counts that leave a partial last block.
#include "kernel_cases.hpp"
#include "kernels/mechanics/triangle_edge_blocks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace penalty {
namespace edge_block_cases {  // (named: the suite's files share unity batches)

using namespace test_kernel_cases;

struct EdgeCase {
    std::vector<Triangle> triangles;
    std::vector<std::array<Mat3, 3>> dfdx;
    std::vector<Vec3> dx;
    std::vector<Vec3> df;
    std::vector<detail::TriangleEdgeBlock> blocks;
};

/// A block entry: stiffness-like values of every sign, and with `special` now and then a
/// subnormal, an infinity or a NaN.
double block_entry(std::mt19937& rng, bool special) {
    double value = 0.0;
    if (draw_special(rng, special, 24, value)) return value;
    return rng() % 10 == 0 ? -0.0 : std::uniform_real_distribution<double>(-50, 50)(rng);
}

EdgeCase make_case(std::mt19937& rng, std::size_t triangles, std::size_t points, bool special) {
    EdgeCase c;
    std::uniform_int_distribution<PointId> vertex(0, static_cast<PointId>(points - 1));
    for (std::size_t t = 0; t < triangles; ++t) {
        Triangle tri{vertex(rng), vertex(rng), vertex(rng)};
        if (t % 13 == 5) tri[2] = tri[0];  // degenerate: a repeated vertex
        c.triangles.push_back(tri);
        std::array<Mat3, 3> m;
        for (Mat3& d : m)
            for (int i = 0; i < 9; ++i) d.data()[i] = block_entry(rng, special);
        c.dfdx.push_back(m);
    }
    for (std::size_t p = 0; p < points; ++p) {
        c.dx.emplace_back(product_entry(rng), product_entry(rng), product_entry(rng));
        c.df.emplace_back(product_entry(rng), product_entry(rng), product_entry(rng));
    }
    detail::size_triangle_edge_blocks(c.blocks, triangles);
    for (std::size_t t = 0; t < triangles; ++t) detail::set_triangle_edge_lane(c.blocks, t, c.triangles[t], c.dfdx[t]);
    return c;
}

/// SOFA's addDForce, written from its formulas; `reversed`: each row summed right to left.
std::vector<Vec3> sofa_product(const EdgeCase& c, double k, bool reversed) {
    std::vector<Vec3> df = c.df;
    const auto row = [reversed](double a0, double b0, double a1, double b1, double a2, double b2) {
        return reversed ? a2 * b2 + a1 * b1 + a0 * b0 : a0 * b0 + a1 * b1 + a2 * b2;
    };
    for (std::size_t t = 0; t < c.triangles.size(); ++t)
        for (std::size_t e = 0; e < 3; ++e) {
            const auto i = static_cast<std::size_t>(c.triangles[t][(e + 1) % 3]);
            const auto j = static_cast<std::size_t>(c.triangles[t][(e + 2) % 3]);
            const Vec3 d = c.dx[i] - c.dx[j];
            const Mat3& m = c.dfdx[t][e];
            for (int r = 0; r < 3; ++r) df[i][r] += row(m(r, 0), d[0], m(r, 1), d[1], m(r, 2), d[2]) * k;
            for (int r = 0; r < 3; ++r) df[j][r] -= row(m(0, r), d[0], m(1, r), d[1], m(2, r), d[2]) * k;
        }
    return df;
}

std::vector<Vec3> kernel_product(const EdgeCase& c, KernelPath path, double k) {
    std::vector<Vec3> df = c.df;
    detail::triangle_edge_dforce(path, c.blocks, c.triangles.size(), df.data(), c.dx.data(), k);
    return df;
}

/// Each component the same bits, or NaN in both.
bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
        for (int r = 0; r < 3; ++r)
            if (std::memcmp(&a[i][r], &b[i][r], sizeof(double)) != 0 && !(std::isnan(a[i][r]) && std::isnan(b[i][r])))
                return false;
    return true;
}

}  // namespace edge_block_cases

namespace {

using namespace test_kernel_cases;
using edge_block_cases::EdgeCase;
using edge_block_cases::make_case;

TEST(TriangleEdgeBlocks, ScalarPathIsSofasAddDForce) {
    std::mt19937 rng(71);
    int order_matters = 0;
    for (int n = 0; n < 100; ++n) {
        const EdgeCase c = make_case(rng, 1 + rng() % 40, 2 + rng() % 30, false);
        const double k = std::uniform_real_distribution<double>(-2, 2)(rng);
        const std::vector<Vec3> df = edge_block_cases::kernel_product(c, KernelPath::scalar, k);
        EXPECT_TRUE(edge_block_cases::same_bits(df, edge_block_cases::sofa_product(c, k, false))) << "case " << n;
        EXPECT_GT(changed_dofs(c.df, df), 0) << "case " << n;
        // the comparison can fail: rows summed right to left differ in some last bits
        order_matters += edge_block_cases::same_bits(df, edge_block_cases::sofa_product(c, k, true)) ? 0 : 1;
    }
    EXPECT_GT(order_matters, 50);
}

TEST(TriangleEdgeBlocks, AvxPathIsTheScalarPathToTheBit) {
    if (!avx_available()) GTEST_SKIP() << "this CPU has no AVX";
    std::mt19937 rng(73);
    int non_finite = 0;
    for (int n = 0; n < 600; ++n) {
        const bool special = n % 4 == 3;
        // 1 … 40 triangles: whole blocks of four and a partial last one
        const EdgeCase c = make_case(rng, 1 + rng() % 40, 2 + rng() % 30, special);
        const double k = n % 7 == 0 ? -0.0 : std::uniform_real_distribution<double>(-2, 2)(rng);
        const std::vector<Vec3> scalar = edge_block_cases::kernel_product(c, KernelPath::scalar, k);
        EXPECT_TRUE(edge_block_cases::same_bits(scalar, edge_block_cases::kernel_product(c, KernelPath::avx, k)))
            << "case " << n;
        EXPECT_TRUE(edge_block_cases::same_bits(scalar, edge_block_cases::kernel_product(c, KernelPath::avx512, k)))
            << "case " << n;  // runs avx
        for (const Vec3& v : scalar) non_finite += v.allFinite() ? 0 : 1;
    }
    EXPECT_GT(non_finite, 100);  // the special values reached the results
}

}  // namespace
}  // namespace penalty
