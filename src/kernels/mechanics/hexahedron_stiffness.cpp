#include "kernels/mechanics/hexahedron_stiffness.hpp"

#include "kernels/lanes.hpp"

namespace penalty::detail {

namespace {

constexpr int kSize = 24;

/// The scalar reference: row by row, each summed left to right.
HexahedronVector times_scalar(const HexahedronStiffness& k, const HexahedronVector& d) {
    HexahedronVector f;
    for (int i = 0; i < kSize; ++i) {
        double row = k(i, 0) * d[0];
        for (int j = 1; j < kSize; ++j) row += k(i, j) * d[j];
        f[i] = row;
    }
    return f;
}

#ifdef PENALTY_HAS_AVX_LANES
/// Rows 4r … 4r + 3 in the lanes of accumulator r (six named ones, kept in registers): column j's
/// 24 entries are six loads, each lane adding k_i,j·d_j to its row after k_i,j−1·d_j−1, as
/// times_scalar does.
[[gnu::target("avx")]] HexahedronVector times_avx(const HexahedronStiffness& k, const HexahedronVector& d) {
    const double* c = k.data();
    __m256d dj = _mm256_set1_pd(d[0]);
    __m256d r0 = _mm256_mul_pd(_mm256_loadu_pd(c), dj), r1 = _mm256_mul_pd(_mm256_loadu_pd(c + 4), dj),
            r2 = _mm256_mul_pd(_mm256_loadu_pd(c + 8), dj), r3 = _mm256_mul_pd(_mm256_loadu_pd(c + 12), dj),
            r4 = _mm256_mul_pd(_mm256_loadu_pd(c + 16), dj), r5 = _mm256_mul_pd(_mm256_loadu_pd(c + 20), dj);
    for (int j = 1; j < kSize; ++j) {
        c += kSize;
        dj = _mm256_set1_pd(d[j]);
        r0 = _mm256_add_pd(r0, _mm256_mul_pd(_mm256_loadu_pd(c), dj));
        r1 = _mm256_add_pd(r1, _mm256_mul_pd(_mm256_loadu_pd(c + 4), dj));
        r2 = _mm256_add_pd(r2, _mm256_mul_pd(_mm256_loadu_pd(c + 8), dj));
        r3 = _mm256_add_pd(r3, _mm256_mul_pd(_mm256_loadu_pd(c + 12), dj));
        r4 = _mm256_add_pd(r4, _mm256_mul_pd(_mm256_loadu_pd(c + 16), dj));
        r5 = _mm256_add_pd(r5, _mm256_mul_pd(_mm256_loadu_pd(c + 20), dj));
    }
    HexahedronVector f;
    double* out = f.data();
    _mm256_storeu_pd(out, r0);
    _mm256_storeu_pd(out + 4, r1);
    _mm256_storeu_pd(out + 8, r2);
    _mm256_storeu_pd(out + 12, r3);
    _mm256_storeu_pd(out + 16, r4);
    _mm256_storeu_pd(out + 20, r5);
    return f;
}
#endif

}  // namespace

HexahedronVector hexahedron_stiffness_times(KernelPath path, const HexahedronStiffness& k, const HexahedronVector& d) {
#ifdef PENALTY_HAS_AVX_LANES
    if (path != KernelPath::scalar) return times_avx(k, d);
#else
    (void)path;
#endif
    return times_scalar(k, d);
}

}  // namespace penalty::detail
