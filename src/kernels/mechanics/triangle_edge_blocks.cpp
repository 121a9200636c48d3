#include "kernels/mechanics/triangle_edge_blocks.hpp"

#include "kernels/lanes.hpp"
#include "penalty/core/error.hpp"

namespace penalty::detail {

// (a named namespace: the other kernels of a unity batch have their own Block, lanes, mul, add)
namespace triangle_edge_kernel {

using Block = TriangleEdgeBlock;
constexpr std::size_t kWidth = Block::kWidth;

/// The scalar reference: triangle (block b, lane l)'s six terms added to df.
void dforce_scalar(const Block& b, std::size_t l, Vec3* df, const Vec3* dx, double k_factor) {
    for (std::size_t k = 0; k < 3; ++k) {
        const auto i = static_cast<std::size_t>(b.vertex[(k + 1) % 3][l]);
        const auto j = static_cast<std::size_t>(b.vertex[(k + 2) % 3][l]);
        const Vec3 delta = dx[i] - dx[j];
        const Block::Lanes* m = &b.dfdx[9 * k];
        Vec3 to_i;
        Vec3 from_j;
        for (std::size_t r = 0; r < 3; ++r) {
            const auto ri = static_cast<Eigen::Index>(r);
            to_i[ri] = (m[3 * r][l] * delta[0] + m[3 * r + 1][l] * delta[1] + m[3 * r + 2][l] * delta[2]) * k_factor;
            from_j[ri] = (m[r][l] * delta[0] + m[3 + r][l] * delta[1] + m[6 + r][l] * delta[2]) * k_factor;
        }
        df[i] += to_i;
        df[j] -= from_j;
    }
}

#ifdef PENALTY_HAS_AVX_LANES
[[gnu::target("avx"), gnu::always_inline]] inline __m256d lanes(const Block::Lanes& v) {
    return _mm256_load_pd(v.data());
}
[[gnu::target("avx"), gnu::always_inline]] inline __m256d mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
[[gnu::target("avx"), gnu::always_inline]] inline __m256d add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }

/// The four triangles of block b: lane l does dforce_scalar's operations for its triangle, in
/// their order; the terms are added after, triangle by triangle, edge by edge, i before j.
[[gnu::target("avx")]] void dforce_block_avx(const Block& b, Vec3* df, const Vec3* dx, double k_factor) {
    Lanes3 p[3];
    for (std::size_t v = 0; v < 3; ++v) {
        const auto& w = b.vertex[v];
        p[v] = load_lanes(dx[w[0]].data(), dx[w[1]].data(), dx[w[2]].data(), dx[w[3]].data());
    }
    const __m256d k = _mm256_set1_pd(k_factor);
    alignas(32) double to_i[3][3][kWidth];    // [edge][row][lane]
    alignas(32) double from_j[3][3][kWidth];  // [edge][row][lane]
    for (std::size_t e = 0; e < 3; ++e) {
        const Lanes3& a = p[(e + 1) % 3];
        const Lanes3& c = p[(e + 2) % 3];
        const __m256d d0 = _mm256_sub_pd(a.x, c.x), d1 = _mm256_sub_pd(a.y, c.y), d2 = _mm256_sub_pd(a.z, c.z);
        const Block::Lanes* m = &b.dfdx[9 * e];
        for (std::size_t r = 0; r < 3; ++r) {
            _mm256_store_pd(
                to_i[e][r],
                mul(add(add(mul(lanes(m[3 * r]), d0), mul(lanes(m[3 * r + 1]), d1)), mul(lanes(m[3 * r + 2]), d2)), k));
            _mm256_store_pd(from_j[e][r],
                            mul(add(add(mul(lanes(m[r]), d0), mul(lanes(m[3 + r]), d1)), mul(lanes(m[6 + r]), d2)), k));
        }
    }
    for (std::size_t l = 0; l < kWidth; ++l)
        for (std::size_t e = 0; e < 3; ++e) {
            double* i = df[b.vertex[(e + 1) % 3][l]].data();
            i[0] += to_i[e][0][l];
            i[1] += to_i[e][1][l];
            i[2] += to_i[e][2][l];
            double* j = df[b.vertex[(e + 2) % 3][l]].data();
            j[0] -= from_j[e][0][l];
            j[1] -= from_j[e][1][l];
            j[2] -= from_j[e][2][l];
        }
}
#endif

}  // namespace triangle_edge_kernel

void size_triangle_edge_blocks(std::vector<TriangleEdgeBlock>& blocks, std::size_t count) {
    // every lane is set after, but the last block's unused ones: only that block is cleared
    blocks.resize((count + TriangleEdgeBlock::kWidth - 1) / TriangleEdgeBlock::kWidth);
    if (!blocks.empty()) blocks.back() = TriangleEdgeBlock{};
}

void set_triangle_edge_lane(std::vector<TriangleEdgeBlock>& blocks, std::size_t e, const Triangle& t,
                            const std::array<Mat3, 3>& dfdx) {
    constexpr std::size_t width = TriangleEdgeBlock::kWidth;
    PENALTY_DEMAND(e / width < blocks.size());
    TriangleEdgeBlock& b = blocks[e / width];
    const std::size_t l = e % width;
    for (std::size_t k = 0; k < 3; ++k) {
        b.vertex[k][l] = t[k];
        for (Eigen::Index r = 0; r < 3; ++r)
            for (Eigen::Index c = 0; c < 3; ++c) b.dfdx[9 * k + static_cast<std::size_t>(3 * r + c)][l] = dfdx[k](r, c);
    }
}

void triangle_edge_dforce(KernelPath path, std::span<const TriangleEdgeBlock> blocks, std::size_t count, Vec3* df,
                          const Vec3* dx, double k_factor) {
    constexpr std::size_t width = TriangleEdgeBlock::kWidth;
    PENALTY_DEMAND(count <= blocks.size() * width);
    std::size_t e = 0;
#ifdef PENALTY_HAS_AVX_LANES
    if (path != KernelPath::scalar)
        for (; e + width <= count; e += width)
            triangle_edge_kernel::dforce_block_avx(blocks[e / width], df, dx, k_factor);
#else
    (void)path;
#endif
    for (; e < count; ++e) triangle_edge_kernel::dforce_scalar(blocks[e / width], e % width, df, dx, k_factor);
}

}  // namespace penalty::detail
