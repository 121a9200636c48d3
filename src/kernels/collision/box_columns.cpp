#include "kernels/collision/box_columns.hpp"

#include "kernels/lanes.hpp"

namespace penalty::detail {

namespace {

std::uint64_t overlap_mask_scalar(const Aabb& a, double margin, const BoxColumns& c) {
    const double ax = a.max[0] + margin, ay = a.max[1] + margin, az = a.max[2] + margin;
    std::uint64_t mask = 0;
    for (std::uint32_t k = 0; k < c.size; ++k) {
        const bool disjoint = a.min[0] > c.max_plus_margin[0][k] || c.min[0][k] > ax ||  //
                              a.min[1] > c.max_plus_margin[1][k] || c.min[1][k] > ay ||  //
                              a.min[2] > c.max_plus_margin[2][k] || c.min[2][k] > az;
        if (!disjoint) mask |= std::uint64_t{1} << k;
    }
    return mask;
}

#ifdef PENALTY_HAS_AVX_LANES
// Four columns per step: the six comparisons of each lane or-ed (ordered, quiet: NaN is false,
// as the scalar `>`), then the lanes' "not disjoint" bits.
[[gnu::target("avx")]] std::uint64_t overlap_mask_avx(const Aabb& a, double margin, const BoxColumns& c) {
    const __m256d amin0 = _mm256_set1_pd(a.min[0]), amin1 = _mm256_set1_pd(a.min[1]), amin2 = _mm256_set1_pd(a.min[2]);
    const __m256d amax0 = _mm256_set1_pd(a.max[0] + margin), amax1 = _mm256_set1_pd(a.max[1] + margin),
                  amax2 = _mm256_set1_pd(a.max[2] + margin);
    std::uint64_t mask = 0;
    for (std::uint32_t k = 0; k < c.size; k += 4) {
        __m256d d = _mm256_cmp_pd(amin0, _mm256_load_pd(c.max_plus_margin[0] + k), _CMP_GT_OQ);
        d = _mm256_or_pd(d, _mm256_cmp_pd(_mm256_load_pd(c.min[0] + k), amax0, _CMP_GT_OQ));
        d = _mm256_or_pd(d, _mm256_cmp_pd(amin1, _mm256_load_pd(c.max_plus_margin[1] + k), _CMP_GT_OQ));
        d = _mm256_or_pd(d, _mm256_cmp_pd(_mm256_load_pd(c.min[1] + k), amax1, _CMP_GT_OQ));
        d = _mm256_or_pd(d, _mm256_cmp_pd(amin2, _mm256_load_pd(c.max_plus_margin[2] + k), _CMP_GT_OQ));
        d = _mm256_or_pd(d, _mm256_cmp_pd(_mm256_load_pd(c.min[2] + k), amax2, _CMP_GT_OQ));
        mask |= std::uint64_t(~_mm256_movemask_pd(d) & 0xF) << k;
    }
    // the spare columns of the last group
    return c.size >= 64 ? mask : mask & ((std::uint64_t{1} << c.size) - 1);
}
#endif

}  // namespace

std::uint64_t overlap_mask(const Aabb& a, double margin, const BoxColumns& columns, KernelPath path) {
#ifdef PENALTY_HAS_AVX_LANES
    if (path == KernelPath::avx) return overlap_mask_avx(a, margin, columns);
#endif
    (void)path;
    return overlap_mask_scalar(a, margin, columns);
}

}  // namespace penalty::detail
