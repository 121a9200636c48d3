#include "kernels/mechanics/triangle_fem_large.hpp"

#include "kernels/lanes.hpp"
#include "penalty/core/error.hpp"

namespace penalty::detail {

namespace {

using Block = TriangleFemLargeBlock;
constexpr std::size_t kWidth = Block::kWidth;

/// Element e's term k: stored where `deferred` marks it, else added to df.
inline void apply_term(const DeferredTerms& deferred, std::size_t e, std::size_t k, Vec3* df, std::int32_t vertex,
                       const Vec3& term) {
    if (deferred.mask != nullptr && ((deferred.mask[e] >> k) & 1U)) deferred.terms[3 * e + k] = term;
    else df[vertex] += term;
}

/// The scalar reference: triangle (block b, lane l)'s product, its terms applied.
void dforce_scalar(const Block& b, std::size_t l, std::size_t e, Vec3* df, const Vec3* dx, double k_factor,
                   const DeferredTerms& deferred) {
    const auto& r = b.frame;
    const auto& j = b.j;
    const auto& m = b.material;
    // D: x, y of R·dx per vertex (rows of R are columns of Rᵀ)
    std::array<double, 6> d;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3& v = dx[b.vertex[k][l]];
        d[2 * k] = r[0][l] * v[0] + r[3][l] * v[1] + r[6][l] * v[2];
        d[2 * k + 1] = r[1][l] * v[0] + r[4][l] * v[1] + r[7][l] * v[2];
    }
    // ε = Jᵀ·D, σ = Dₐ·ε, F = J·σ: the non-zero terms (computeStrain, computeStress, computeForceLarge)
    const double s0 = j[Block::j00][l] * d[0] + j[Block::j20][l] * d[2];
    const double s1 = j[Block::j11][l] * d[1] + j[Block::j31][l] * d[3] + j[Block::j51][l] * d[5];
    const double s2 = j[Block::j02][l] * d[0] + j[Block::j12][l] * d[1] + j[Block::j22][l] * d[2] +
                      j[Block::j32][l] * d[3] + j[Block::j42][l] * d[4];
    const double t0 = m[Block::d00][l] * s0 + m[Block::d01][l] * s1;
    const double t1 = m[Block::d10][l] * s0 + m[Block::d11][l] * s1;
    const double t2 = m[Block::d22][l] * s2;
    const std::array<double, 6> f = {j[Block::j00][l] * t0 + j[Block::j02][l] * t2,
                                     j[Block::j11][l] * t1 + j[Block::j12][l] * t2,
                                     j[Block::j20][l] * t0 + j[Block::j22][l] * t2,
                                     j[Block::j31][l] * t1 + j[Block::j32][l] * t2,
                                     j[Block::j42][l] * t2,
                                     j[Block::j51][l] * t1};
    // df_k += k·(Rᵀ·(−F_2k, −F_2k+1, 0))
    for (std::size_t k = 0; k < 3; ++k) {
        const double x = -f[2 * k], y = -f[2 * k + 1];
        Vec3 term;
        for (std::size_t i = 0; i < 3; ++i)
            term[static_cast<Eigen::Index>(i)] =
                (r[3 * i][l] * x + r[3 * i + 1][l] * y + r[3 * i + 2][l] * 0.0) * k_factor;
        apply_term(deferred, e, k, df, b.vertex[k][l], term);
    }
}

#ifdef PENALTY_HAS_AVX_LANES
[[gnu::target("avx"), gnu::always_inline]] inline __m256d lanes(const Block::Lanes& v) {
    return _mm256_load_pd(v.data());
}
[[gnu::target("avx"), gnu::always_inline]] inline __m256d mul(__m256d a, __m256d b) { return _mm256_mul_pd(a, b); }
[[gnu::target("avx"), gnu::always_inline]] inline __m256d add(__m256d a, __m256d b) { return _mm256_add_pd(a, b); }

/// The four triangles of block b (triangles 4b … 4b + 3): lane l does dforce_scalar's operations
/// for its triangle, in their order; the terms are applied after, triangle by triangle.
[[gnu::target("avx")]] void dforce_block_avx(const Block& b, std::size_t first_element, Vec3* df, const Vec3* dx,
                                             double k_factor, const DeferredTerms& deferred) {
    __m256d r[9];
    for (std::size_t i = 0; i < 9; ++i) r[i] = lanes(b.frame[i]);
    __m256d d[6];
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& v = b.vertex[k];
        const Lanes3 p = load_lanes(dx[v[0]].data(), dx[v[1]].data(), dx[v[2]].data(), dx[v[3]].data());
        d[2 * k] = add(add(mul(r[0], p.x), mul(r[3], p.y)), mul(r[6], p.z));
        d[2 * k + 1] = add(add(mul(r[1], p.x), mul(r[4], p.y)), mul(r[7], p.z));
    }
    const auto& j = b.j;
    const auto& m = b.material;
    const __m256d s0 = add(mul(lanes(j[Block::j00]), d[0]), mul(lanes(j[Block::j20]), d[2]));
    const __m256d s1 =
        add(add(mul(lanes(j[Block::j11]), d[1]), mul(lanes(j[Block::j31]), d[3])), mul(lanes(j[Block::j51]), d[5]));
    const __m256d s2 = add(
        add(add(add(mul(lanes(j[Block::j02]), d[0]), mul(lanes(j[Block::j12]), d[1])), mul(lanes(j[Block::j22]), d[2])),
            mul(lanes(j[Block::j32]), d[3])),
        mul(lanes(j[Block::j42]), d[4]));
    const __m256d t0 = add(mul(lanes(m[Block::d00]), s0), mul(lanes(m[Block::d01]), s1));
    const __m256d t1 = add(mul(lanes(m[Block::d10]), s0), mul(lanes(m[Block::d11]), s1));
    const __m256d t2 = mul(lanes(m[Block::d22]), s2);
    const __m256d f[6] = {add(mul(lanes(j[Block::j00]), t0), mul(lanes(j[Block::j02]), t2)),
                          add(mul(lanes(j[Block::j11]), t1), mul(lanes(j[Block::j12]), t2)),
                          add(mul(lanes(j[Block::j20]), t0), mul(lanes(j[Block::j22]), t2)),
                          add(mul(lanes(j[Block::j31]), t1), mul(lanes(j[Block::j32]), t2)),
                          mul(lanes(j[Block::j42]), t2),
                          mul(lanes(j[Block::j51]), t1)};
    const __m256d sign = _mm256_set1_pd(-0.0), zero = _mm256_setzero_pd(), k = _mm256_set1_pd(k_factor);
    __m128d xy[3][kWidth];                      // [vertex][lane]: the term's x, y
    alignas(32) std::array<Block::Lanes, 3> z;  // [vertex][lane]: its z
    for (std::size_t v = 0; v < 3; ++v) {
        const __m256d x = _mm256_xor_pd(f[2 * v], sign), y = _mm256_xor_pd(f[2 * v + 1], sign);
        __m256d w[3];
        for (std::size_t i = 0; i < 3; ++i)
            w[i] = mul(add(add(mul(r[3 * i], x), mul(r[3 * i + 1], y)), mul(r[3 * i + 2], zero)), k);
        const __m256d even = _mm256_unpacklo_pd(w[0], w[1]);  // x0 y0 | x2 y2
        const __m256d odd = _mm256_unpackhi_pd(w[0], w[1]);   // x1 y1 | x3 y3
        xy[v][0] = _mm256_castpd256_pd128(even);
        xy[v][1] = _mm256_castpd256_pd128(odd);
        xy[v][2] = _mm256_extractf128_pd(even, 1);
        xy[v][3] = _mm256_extractf128_pd(odd, 1);
        _mm256_store_pd(z[v].data(), w[2]);
    }
    // df += the terms, triangle by triangle, vertex by vertex (x and y in one addition of two
    // lanes, z alone: the same IEEE additions)
    for (std::size_t l = 0; l < kWidth; ++l) {
        const std::size_t e = first_element + l;
        const unsigned mask = deferred.mask != nullptr ? deferred.mask[e] : 0U;
        for (std::size_t v = 0; v < 3; ++v) {
            if ((mask >> v) & 1U) {
                double* term = deferred.terms[3 * e + v].data();
                _mm_storeu_pd(term, xy[v][l]);
                term[2] = z[v][l];
            } else {
                double* out = df[b.vertex[v][l]].data();
                _mm_storeu_pd(out, _mm_add_pd(_mm_loadu_pd(out), xy[v][l]));
                out[2] += z[v][l];
            }
        }
    }
}
#endif

}  // namespace

void fill_triangle_fem_large_blocks(std::vector<TriangleFemLargeBlock>& blocks, std::span<const Triangle> triangles,
                                    std::span<const Mat3> frames, std::span<const Eigen::Matrix<double, 6, 3>> j,
                                    std::span<const Mat3> material) {
    PENALTY_DEMAND(frames.size() >= triangles.size() && j.size() >= triangles.size() &&
                   material.size() >= triangles.size());
    blocks.assign((triangles.size() + kWidth - 1) / kWidth, Block{});
    for (std::size_t e = 0; e < triangles.size(); ++e) {
        Block& b = blocks[e / kWidth];
        const std::size_t l = e % kWidth;
        for (Eigen::Index r = 0; r < 3; ++r)
            for (Eigen::Index c = 0; c < 3; ++c) b.frame[static_cast<std::size_t>(3 * r + c)][l] = frames[e](r, c);
        const auto& je = j[e];
        const std::array<double, Block::kJEntries> entries = {je(0, 0), je(2, 0), je(1, 1), je(3, 1), je(5, 1),
                                                              je(0, 2), je(1, 2), je(2, 2), je(3, 2), je(4, 2)};
        for (std::size_t i = 0; i < entries.size(); ++i) b.j[i][l] = entries[i];
        const Mat3& d = material[e];
        const std::array<double, Block::kMaterialEntries> da = {d(0, 0), d(0, 1), d(1, 0), d(1, 1), d(2, 2)};
        for (std::size_t i = 0; i < da.size(); ++i) b.material[i][l] = da[i];
        for (std::size_t k = 0; k < 3; ++k) b.vertex[k][l] = triangles[e][k];
    }
}

void triangle_fem_large_dforce(KernelPath path, std::span<const TriangleFemLargeBlock> blocks, std::size_t first,
                               std::size_t end, Vec3* df, const Vec3* dx, double k_factor,
                               const DeferredTerms& deferred) {
    PENALTY_DEMAND(first <= end && end <= blocks.size() * kWidth);
    std::size_t e = first;
#ifdef PENALTY_HAS_AVX_LANES
    if (path != KernelPath::scalar) {
        // the triangles before the first whole block, then whole blocks, then the rest
        for (; e < end && e % kWidth != 0; ++e)
            dforce_scalar(blocks[e / kWidth], e % kWidth, e, df, dx, k_factor, deferred);
        for (; e + kWidth <= end; e += kWidth) dforce_block_avx(blocks[e / kWidth], e, df, dx, k_factor, deferred);
    }
#else
    (void)path;
#endif
    for (; e < end; ++e) dforce_scalar(blocks[e / kWidth], e % kWidth, e, df, dx, k_factor, deferred);
}

}  // namespace penalty::detail
