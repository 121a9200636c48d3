// TriangularFEMForceField's method-large product kernel (kernels/mechanics/triangle_fem_large.cpp):
// the scalar path against SOFA's operations as TriangleFEMUtils writes them (computeStrain,
// computeStress, computeForceLarge through triangle_fem_sofa::stiffness_forces, the frame products
// of sofa_vec), and the AVX path against the scalar one, to the bit (the sign of zeros included),
// on random frames, J and Dₐ, ranges that start and end inside blocks, and deferred terms.
#include "kernel_cases.hpp"
#include "kernels/mechanics/triangle_fem_large.hpp"
#include "mechanics/sofa_vector_ops.hpp"
#include "mechanics/triangle_fem_sofa_order.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace penalty {
namespace {

using namespace test_kernel_cases;
using detail::TriangleFemLargeBlock;

struct TriangleCase {
    std::vector<Triangle> triangles;
    std::vector<Mat3> frames;
    std::vector<Eigen::Matrix<double, 6, 3>> j;
    std::vector<Mat3> material;
    std::vector<Vec3> dx;
    std::vector<TriangleFemLargeBlock> blocks;
};

/// `count` triangles over `points` points: random rotations, a local J
/// (computeStrainDisplacementLocal of random edges), a plane-stress Dₐ, dx of every sign.
TriangleCase make_case(std::mt19937& rng, std::size_t count, std::size_t points) {
    TriangleCase c;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<PointId> vertex(0, static_cast<PointId>(points - 1));
    for (std::size_t e = 0; e < count; ++e) {
        c.triangles.push_back({vertex(rng), vertex(rng), vertex(rng)});
        const Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
        c.frames.push_back(q.normalized().toRotationMatrix());
        Eigen::Matrix<double, 6, 3> j;
        const Vec3 b(1.0 + u(rng), 0.0, 0.0), cc(u(rng), 0.5 + std::abs(u(rng)), 0.0);
        EXPECT_TRUE(triangle_fem_sofa::strain_displacement_local(j, b, cc)) << "triangle " << e;
        c.j.push_back(j);
        const double nu = 0.3 + 0.1 * u(rng), scale = 100.0 * (1.5 + u(rng));
        Mat3 d;
        d << 1.0, nu, 0.0, nu, 1.0, 0.0, 0.0, 0.0, 0.5 * (1.0 - nu);
        c.material.push_back(scale * d);
    }
    for (std::size_t i = 0; i < points; ++i)
        c.dx.emplace_back(product_entry(rng), product_entry(rng), product_entry(rng));
    detail::fill_triangle_fem_large_blocks(c.blocks, c.triangles, c.frames, c.j, c.material);
    return c;
}

/// SOFA's applyStiffnessLarge terms of triangle e (TriangleFEMUtils' operations, as
/// TriangularFEMForceField made them before its kernel).
std::array<Vec3, 3> reference_terms(const TriangleCase& c, std::size_t e, double k_factor) {
    const Mat3& to_world = c.frames[e];
    const Mat3 to_local = to_world.transpose();
    triangle_fem_sofa::Displacement local_dx;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3 l = sofa_vec::times(to_local, c.dx[static_cast<std::size_t>(c.triangles[e][k])]);
        local_dx[static_cast<Eigen::Index>(2 * k)] = l[0];
        local_dx[static_cast<Eigen::Index>(2 * k + 1)] = l[1];
    }
    const triangle_fem_sofa::Displacement nodal =
        triangle_fem_sofa::stiffness_forces(true, c.j[e], c.material[e], local_dx);
    std::array<Vec3, 3> terms;
    for (std::size_t k = 0; k < 3; ++k) {
        const auto i = static_cast<Eigen::Index>(2 * k);
        terms[k] = sofa_vec::scaled(sofa_vec::times(to_world, Vec3(-nodal[i], -nodal[i + 1], 0.0)), k_factor);
    }
    return terms;
}

/// df += the terms of triangles [first, end), triangle by triangle, vertex by vertex.
void reference_dforce(const TriangleCase& c, std::size_t first, std::size_t end, std::vector<Vec3>& df,
                      double k_factor) {
    for (std::size_t e = first; e < end; ++e) {
        const std::array<Vec3, 3> terms = reference_terms(c, e, k_factor);
        for (std::size_t k = 0; k < 3; ++k) df[static_cast<std::size_t>(c.triangles[e][k])] += terms[k];
    }
}

std::vector<Vec3> start_df(std::mt19937& rng, std::size_t points) {
    std::vector<Vec3> df;
    for (std::size_t i = 0; i < points; ++i)
        df.emplace_back(product_entry(rng), product_entry(rng), product_entry(rng));
    return df;
}

TEST(VectorKernels, TriangleFemLargeProductIsSofasOperationsOnEveryPath) {
    std::mt19937 rng(29);
    std::vector<KernelPath> paths = {KernelPath::scalar};
    if (avx_available()) paths.push_back(KernelPath::avx);
    int compared = 0, changed = 0;
    for (const std::size_t count : {std::size_t{1}, std::size_t{3}, std::size_t{4}, std::size_t{6}, std::size_t{13},
                                    std::size_t{64}, std::size_t{203}}) {
        // few points: triangles share vertices, so the order of the additions is tested
        const TriangleCase c = make_case(rng, count, count / 2 + 3);
        for (const auto& [first, end] : std::vector<std::pair<std::size_t, std::size_t>>{
                 {0, count}, {count / 3, count}, {count / 5, count - count / 4}}) {
            for (const double k : {-0.0123, 1.0, -0.0}) {
                const std::vector<Vec3> df0 = start_df(rng, c.dx.size());
                std::vector<Vec3> expected = df0;
                reference_dforce(c, first, end, expected, k);
                changed += changed_dofs(df0, expected);
                for (const KernelPath path : paths) {
                    std::vector<Vec3> df = df0;
                    detail::triangle_fem_large_dforce(path, c.blocks, first, end, df.data(), c.dx.data(), k, {});
                    expect_same_bits(expected, df,
                                     std::string(to_string(path)) + ", " + std::to_string(count) + " triangles [" +
                                         std::to_string(first) + ", " + std::to_string(end) + ")");
                    ++compared;
                }
            }
        }
    }
    EXPECT_GE(compared, 7 * 3 * 3);
    EXPECT_GT(changed, 300);  // the products changed df: the comparisons are not of untouched vectors
}

TEST(VectorKernels, TriangleFemLargeProductStoresTheDeferredTerms) {
    // the product on threads (OrderedScatter): a term the mask marks (bit k of mask[e]) is stored
    // at terms[3e + k] instead of added; the others are added in order
    std::mt19937 rng(31);
    const std::size_t count = 37;
    const TriangleCase c = make_case(rng, count, 20);
    std::vector<std::uint8_t> mask(count);
    for (auto& m : mask) m = static_cast<std::uint8_t>(rng() % 8);
    const std::vector<Vec3> df0 = start_df(rng, c.dx.size());
    const Vec3 untouched = Vec3::Constant(7.0);
    std::vector<Vec3> expected_df = df0, expected_terms(3 * count, untouched);
    int stored = 0;
    for (std::size_t e = 0; e < count; ++e) {
        const std::array<Vec3, 3> terms = reference_terms(c, e, 0.5);
        for (std::size_t k = 0; k < 3; ++k) {
            if ((mask[e] >> k) & 1U) {
                expected_terms[3 * e + k] = terms[k];
                ++stored;
            } else {
                expected_df[static_cast<std::size_t>(c.triangles[e][k])] += terms[k];
            }
        }
    }
    EXPECT_GT(stored, 30);
    EXPECT_LT(stored, 3 * int(count) - 30);
    std::vector<KernelPath> paths = {KernelPath::scalar};
    if (avx_available()) paths.push_back(KernelPath::avx);
    for (const KernelPath path : paths) {
        std::vector<Vec3> terms(3 * count, untouched), df = df0;
        detail::triangle_fem_large_dforce(path, c.blocks, 0, count, df.data(), c.dx.data(), 0.5,
                                          {mask.data(), terms.data()});
        expect_same_bits(expected_df, df, std::string(to_string(path)) + ": df");
        expect_same_bits(expected_terms, terms, std::string(to_string(path)) + ": stored terms");
    }
}

}  // namespace
}  // namespace penalty
