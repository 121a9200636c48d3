#pragma once
/// @file
/// The AVX kernels' platform switch and helpers (KernelPath::avx). PENALTY_HAS_AVX_LANES is
/// defined, and <immintrin.h> included, only on x86-64 with GCC or Clang: the one place that
/// decides where the AVX paths are compiled. Helpers: four Vec3 gathered into three registers of
/// four lanes (x of the four, y of the four, z of the four) and padded rows stored back. Internal
/// (namespace detail); inlined into the callers' `[[gnu::target("avx")]]` functions. Loads read
/// exactly the three doubles of each Vec3.
#if defined(__x86_64__) && defined(__GNUC__)
#define PENALTY_HAS_AVX_LANES 1
#include <immintrin.h>

namespace penalty::detail {

struct Lanes3 {
    __m256d x, y, z;
};

/// Lane k holds the point p[k] (three doubles each).
[[gnu::target("avx"), gnu::always_inline]] inline Lanes3 load_lanes(const double* p0, const double* p1,
                                                                    const double* p2, const double* p3) {
    const __m128d a = _mm_loadu_pd(p0), b = _mm_loadu_pd(p1), c = _mm_loadu_pd(p2), d = _mm_loadu_pd(p3);
    return {_mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_unpacklo_pd(a, b)), _mm_unpacklo_pd(c, d), 1),
            _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_unpackhi_pd(a, b)), _mm_unpackhi_pd(c, d), 1),
            _mm256_set_pd(p3[2], p2[2], p1[2], p0[2])};
}

/// The four rows (r0[k], r1[k], r2[k], 0) for k = 0 … 3, each stored at the 32-byte aligned out[k].
[[gnu::target("avx"), gnu::always_inline]] inline void store_rows_padded(__m256d r0, __m256d r1, __m256d r2,
                                                                         double* out0, double* out1, double* out2,
                                                                         double* out3) {
    const __m256d zero = _mm256_setzero_pd();
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1);    // r0[0] r1[0] | r0[2] r1[2]
    const __m256d t1 = _mm256_unpackhi_pd(r0, r1);    // r0[1] r1[1] | r0[3] r1[3]
    const __m256d t2 = _mm256_unpacklo_pd(r2, zero);  // r2[0] 0     | r2[2] 0
    const __m256d t3 = _mm256_unpackhi_pd(r2, zero);  // r2[1] 0     | r2[3] 0
    _mm256_store_pd(out0, _mm256_permute2f128_pd(t0, t2, 0x20));
    _mm256_store_pd(out1, _mm256_permute2f128_pd(t1, t3, 0x20));
    _mm256_store_pd(out2, _mm256_permute2f128_pd(t0, t2, 0x31));
    _mm256_store_pd(out3, _mm256_permute2f128_pd(t1, t3, 0x31));
}

}  // namespace penalty::detail
#endif
