#include "kernels/collision/triangle_normals.hpp"

#include "kernels/lanes.hpp"
#include "penalty/core/error.hpp"

namespace penalty::detail {

namespace {

Vec3 unit_normal(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const Vec3 n = (p1 - p0).cross(p2 - p0);
    const double len = n.norm();
    // SOFA normalises without a guard; a zero-area triangle keeps a zero normal here
    return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

void triangle_normals_scalar(const Vec3* x, const Triangle* t, std::size_t begin, std::size_t end, Vec3* normals) {
    for (std::size_t i = begin; i < end; ++i)
        normals[i] = unit_normal(x[std::size_t(t[i][0])], x[std::size_t(t[i][1])], x[std::size_t(t[i][2])]);
}

#ifdef PENALTY_HAS_AVX_LANES
// Four triangles a step, lane k = triangle i + k: the scalar path's operations lane by lane
// (no fused multiply-add: target avx only, and the build has -ffp-contract=off).
// Returns the number of triangles done (count − count % 4); the caller does the rest with the
// scalar loop (not called from here: GCC leaves out the vzeroupper before such a tail call, and
// the SSE code after it then runs with the upper halves of the registers dirty, ~10 % slower).
[[gnu::target("avx")]] std::size_t triangle_normals_avx(const Vec3* x, const Triangle* t, std::size_t count,
                                                        Vec3* normals) {
    const __m256d zero = _mm256_setzero_pd();
    std::size_t i = 0;
    for (; i + 4 <= count; i += 4) {
        const Triangle* q = t + i;
        Lanes3 p[3];  // p[k]: vertex k of the four triangles
        for (std::size_t k = 0; k < 3; ++k)
            p[k] = load_lanes(x[std::size_t(q[0][k])].data(), x[std::size_t(q[1][k])].data(),
                              x[std::size_t(q[2][k])].data(), x[std::size_t(q[3][k])].data());
        const Lanes3& p0 = p[0];
        const Lanes3& p1 = p[1];
        const Lanes3& p2 = p[2];
        const __m256d ux = _mm256_sub_pd(p1.x, p0.x), uy = _mm256_sub_pd(p1.y, p0.y), uz = _mm256_sub_pd(p1.z, p0.z);
        const __m256d vx = _mm256_sub_pd(p2.x, p0.x), vy = _mm256_sub_pd(p2.y, p0.y), vz = _mm256_sub_pd(p2.z, p0.z);
        // u × v = (uy·vz − uz·vy, uz·vx − ux·vz, ux·vy − uy·vx)
        const __m256d nx = _mm256_sub_pd(_mm256_mul_pd(uy, vz), _mm256_mul_pd(uz, vy));
        const __m256d ny = _mm256_sub_pd(_mm256_mul_pd(uz, vx), _mm256_mul_pd(ux, vz));
        const __m256d nz = _mm256_sub_pd(_mm256_mul_pd(ux, vy), _mm256_mul_pd(uy, vx));
        // |n| = sqrt((nx² + ny²) + nz²); n / |n| where |n| > 0 (ordered: NaN is false), else 0
        const __m256d len = _mm256_sqrt_pd(
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, nx), _mm256_mul_pd(ny, ny)), _mm256_mul_pd(nz, nz)));
        const __m256d positive = _mm256_cmp_pd(len, zero, _CMP_GT_OQ);
        const __m256d ox = _mm256_and_pd(positive, _mm256_div_pd(nx, len));
        const __m256d oy = _mm256_and_pd(positive, _mm256_div_pd(ny, len));
        const __m256d oz = _mm256_and_pd(positive, _mm256_div_pd(nz, len));
        // back to one Vec3 per triangle: (x, y) pairs of lanes 0, 1 and 2, 3, then z
        const __m256d xy_lo = _mm256_unpacklo_pd(ox, oy);  // x0 y0 | x2 y2
        const __m256d xy_hi = _mm256_unpackhi_pd(ox, oy);  // x1 y1 | x3 y3
        alignas(32) double z[4];
        _mm256_store_pd(z, oz);
        Vec3* out = normals + i;
        _mm_storeu_pd(out[0].data(), _mm256_castpd256_pd128(xy_lo));
        _mm_storeu_pd(out[1].data(), _mm256_castpd256_pd128(xy_hi));
        _mm_storeu_pd(out[2].data(), _mm256_extractf128_pd(xy_lo, 1));
        _mm_storeu_pd(out[3].data(), _mm256_extractf128_pd(xy_hi, 1));
        for (int k = 0; k < 4; ++k) out[k][2] = z[k];
    }
    return i;
}
#endif

}  // namespace

void triangle_normals(std::span<const Vec3> x, std::span<const Triangle> triangles, std::span<Vec3> normals,
                      KernelPath path) {
    PENALTY_DEMAND(triangles.size() == normals.size());
    std::size_t done = 0;
#ifdef PENALTY_HAS_AVX_LANES
    if (path == KernelPath::avx)
        done = triangle_normals_avx(x.data(), triangles.data(), triangles.size(), normals.data());
#endif
    (void)path;
    triangle_normals_scalar(x.data(), triangles.data(), done, triangles.size(), normals.data());
}

}  // namespace penalty::detail
