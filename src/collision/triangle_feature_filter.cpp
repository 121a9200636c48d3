// The candidate filter of NewProximity Triangle–Point and Triangle–Sphere (KernelParts::filter):
// the kernels' first tests, gram() and closest_feature() of kernels.hpp, alone (the scalar
// path calls them) and, on the AVX path, four candidates at a time. Near a sphere most
// candidates fail them (CompositeCollisionPipeline_none, spheres against tori: 80 % of the
// Triangle–Sphere candidates, whose centre projects onto a vertex or edge the triangle does
// not own), and the filter costs less than half of the kernel a candidate.
#include "penalty/collision/triangle_feature_filter.hpp"

#include "kernels.hpp"
#include "penalty/core/avx_lanes.hpp"
#include "penalty/core/error.hpp"

namespace penalty::detail {

namespace {

using Keys = std::vector<std::uint64_t>;

template <class PointOf>
void keep_owned_scalar(const TriangleModel& t, PointOf&& point_of, const TriangleRegionConstants& k,
                       std::span<const std::uint64_t> keys, std::size_t begin, Keys& kept) {
    for (std::size_t i = begin; i < keys.size(); ++i) {
        const Index e1 = Index(keys[i] >> 32);
        const Gram g = gram(t.p(e1, 0), t.p(e1, 1), t.p(e1, 2), point_of(Index(keys[i] & 0xffffffffu)));
        if (g.degenerate) continue;
        double alpha = 0.0;
        double beta = 0.0;
        if (closest_feature(g, t.flags(e1), k, alpha, beta)) kept.push_back(keys[i]);
    }
}

#ifdef PENALTY_HAS_AVX_LANES
// gram() and closest_feature() in lanes: every sum, product and quotient as the scalar code
// writes it (Eigen's Vec3 dot is (x·x' + y·y') + z·z'; no contraction, -ffp-contract=off), the
// comparisons ordered as C++'s (<, >, >= false on NaN; "!(x > 0)" as not-greater, true on NaN).
// The lanes' regions and their owners' flags are bit masks of the four lanes.
[[gnu::target("avx"), gnu::always_inline]] inline __m256d dot3(__m256d ax, __m256d ay, __m256d az, __m256d bx,
                                                               __m256d by, __m256d bz) {
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ax, bx), _mm256_mul_pd(ay, by)), _mm256_mul_pd(az, bz));
}

template <class PointOf>
[[gnu::target("avx")]] std::size_t keep_owned_avx(const TriangleModel& t, PointOf&& point_of,
                                                  const TriangleRegionConstants& k,
                                                  std::span<const std::uint64_t> keys, Keys& kept) {
    using F = TriangleModel::Flags;
    const __m256d lo = _mm256_set1_pd(k.inside_lo), hi = _mm256_set1_pd(k.inside_hi);
    const __m256d vertex_a_ac = _mm256_set1_pd(k.vertex_a_ac), edge_lo = _mm256_set1_pd(k.edge_lo);
    const __m256d zero = _mm256_setzero_pd(), two = _mm256_set1_pd(2.0);
    if (keys.size() < 4) return 0;
    // the vertices as t.p(e, c) reads them, the pointers loaded once
    const Triangle* triangles = &t.triangle(0);
    const Vec3* x = t.state().position.data();
    const std::size_t n4 = keys.size() / 4 * 4;
    constexpr std::size_t kBlock = 64;
    std::uint64_t block[kBlock];
    std::size_t count = 0;
    for (std::size_t i = 0; i < n4; i += 4) {
        Index e1[4];
        const double* q[4];
        const double* v[3][4];
        for (int j = 0; j < 4; ++j) {
            e1[j] = Index(keys[i + j] >> 32);
            q[j] = point_of(Index(keys[i + j] & 0xffffffffu)).data();
            const Triangle& tri = triangles[e1[j]];
            for (int c = 0; c < 3; ++c) v[c][j] = x[tri[std::size_t(c)]].data();
        }
        const Lanes3 p1 = load_lanes(v[0][0], v[0][1], v[0][2], v[0][3]);
        const Lanes3 p2 = load_lanes(v[1][0], v[1][1], v[1][2], v[1][3]);
        const Lanes3 p3 = load_lanes(v[2][0], v[2][1], v[2][2], v[2][3]);
        const Lanes3 pq = load_lanes(q[0], q[1], q[2], q[3]);
        const __m256d abx = _mm256_sub_pd(p2.x, p1.x), aby = _mm256_sub_pd(p2.y, p1.y), abz = _mm256_sub_pd(p2.z, p1.z);
        const __m256d acx = _mm256_sub_pd(p3.x, p1.x), acy = _mm256_sub_pd(p3.y, p1.y), acz = _mm256_sub_pd(p3.z, p1.z);
        const __m256d aqx = _mm256_sub_pd(pq.x, p1.x), aqy = _mm256_sub_pd(pq.y, p1.y), aqz = _mm256_sub_pd(pq.z, p1.z);
        const __m256d g00 = dot3(abx, aby, abz, abx, aby, abz);
        const __m256d g11 = dot3(acx, acy, acz, acx, acy, acz);
        const __m256d g01 = dot3(abx, aby, abz, acx, acy, acz);
        const __m256d b0 = dot3(aqx, aqy, aqz, abx, aby, abz);
        const __m256d b1 = dot3(aqx, aqy, aqz, acx, acy, acz);
        const __m256d det = _mm256_sub_pd(_mm256_mul_pd(g00, g11), _mm256_mul_pd(g01, g01));
        const __m256d bc_den = _mm256_sub_pd(_mm256_add_pd(g00, g11), _mm256_mul_pd(two, g01));
        __m256d degenerate = _mm256_cmp_pd(det, zero, _CMP_NGT_UQ);
        degenerate = _mm256_or_pd(degenerate, _mm256_cmp_pd(g00, zero, _CMP_NGT_UQ));
        degenerate = _mm256_or_pd(degenerate, _mm256_cmp_pd(g11, zero, _CMP_NGT_UQ));
        degenerate = _mm256_or_pd(degenerate, _mm256_cmp_pd(bc_den, zero, _CMP_NGT_UQ));
        const int deg_bits = _mm256_movemask_pd(degenerate);
        const __m256d alpha = _mm256_div_pd(_mm256_sub_pd(_mm256_mul_pd(b0, g11), _mm256_mul_pd(b1, g01)), det);
        const __m256d beta = _mm256_div_pd(_mm256_sub_pd(_mm256_mul_pd(b1, g00), _mm256_mul_pd(b0, g01)), det);
        const __m256d alpha_low = _mm256_cmp_pd(alpha, lo, _CMP_LT_OQ);
        const __m256d beta_low = _mm256_cmp_pd(beta, lo, _CMP_LT_OQ);
        const __m256d outside =
            _mm256_or_pd(_mm256_or_pd(alpha_low, beta_low), _mm256_cmp_pd(_mm256_add_pd(alpha, beta), hi, _CMP_GT_OQ));
        const int outside_bits = _mm256_movemask_pd(outside) & ~deg_bits;
        int keep_bits = ~deg_bits & ~outside_bits & 0xF;
        if (outside_bits != 0) {
            const __m256d pab = _mm256_div_pd(b0, g00);
            const __m256d pac = _mm256_div_pd(b1, g11);
            const __m256d pbc = _mm256_div_pd(_mm256_sub_pd(_mm256_add_pd(_mm256_sub_pd(b1, b0), g00), g01), bc_den);
            // closest_feature's chain of regions, as lane masks (bit j: lane j)
            const int vertex_a = _mm256_movemask_pd(
                _mm256_and_pd(_mm256_cmp_pd(pab, lo, _CMP_LT_OQ), _mm256_cmp_pd(pac, vertex_a_ac, _CMP_LT_OQ)));
            const int edge_ab = _mm256_movemask_pd(_mm256_and_pd(
                _mm256_and_pd(_mm256_cmp_pd(pab, hi, _CMP_LT_OQ), _mm256_cmp_pd(pab, edge_lo, _CMP_GE_OQ)), beta_low));
            const int edge_ac = _mm256_movemask_pd(_mm256_and_pd(
                _mm256_and_pd(_mm256_cmp_pd(pac, hi, _CMP_LT_OQ), _mm256_cmp_pd(pac, edge_lo, _CMP_GE_OQ)), alpha_low));
            const int below_b = _mm256_movemask_pd(_mm256_cmp_pd(pbc, lo, _CMP_LT_OQ));
            const int above_c = _mm256_movemask_pd(_mm256_cmp_pd(pbc, hi, _CMP_GT_OQ));
            const int in_a = outside_bits & vertex_a;
            const int in_ab = outside_bits & ~vertex_a & edge_ab;
            const int in_ac = outside_bits & ~vertex_a & ~edge_ab & edge_ac;
            const int along_bc = outside_bits & ~vertex_a & ~edge_ab & ~edge_ac;
            const int in_b = along_bc & below_b;
            const int in_c = along_bc & ~below_b & above_c;
            const int in_bc = along_bc & ~below_b & ~above_c;
            // the lanes whose triangle owns each feature's flag
            const __m128i flags = _mm_set_epi32(int(t.flags(e1[3])), int(t.flags(e1[2])), int(t.flags(e1[1])),
                                                int(t.flags(e1[0])));
            const auto owns = [&flags](std::uint32_t flag) {
                const __m128i none = _mm_cmpeq_epi32(_mm_and_si128(flags, _mm_set1_epi32(int(flag))), _mm_setzero_si128());
                return ~_mm_movemask_ps(_mm_castsi128_ps(none)) & 0xF;
            };
            keep_bits |= (in_a & owns(F::kP1)) | (in_ab & owns(F::kE12)) | (in_ac & owns(k.edge_ac_flag)) |
                         (in_b & owns(F::kP2)) | (in_c & owns(F::kP3)) | (in_bc & owns(k.edge_bc_flag));
        }
        // appended without a branch a candidate
        std::uint64_t* end = block + count;
        for (int j = 0; j < 4; ++j) {
            *end = keys[i + j];
            end += (keep_bits >> j) & 1;
        }
        count = std::size_t(end - block);
        if (count > kBlock - 4) {
            kept.insert(kept.end(), block, block + count);
            count = 0;
        }
    }
    kept.insert(kept.end(), block, block + count);
    return n4;
}
#endif

}  // namespace

void keep_owned_feature_candidates(const IntersectionParams& params, const TriangleModel& t, const CollisionModel& m2,
                                   std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept,
                                   KernelPath path) {
    const ModelType kind = m2.type();
    if (kind != ModelType::Point && kind != ModelType::Sphere && kind != ModelType::RigidSphere) {
        throw_invalid_argument("keep_owned_feature_candidates(): '", m2.name(), "' is a ", model_type_name(kind),
                               " model, not a Point, Sphere or RigidSphere model");
    }
    const TriangleRegionConstants k =
        kind == ModelType::Point ? kNewProximity.triangle_point : triangle_sphere_region(params);
    kept.reserve(kept.size() + keys.size());
    with_element_points(m2, [&](auto&& point_of) {
        std::size_t done = 0;
#ifdef PENALTY_HAS_AVX_LANES
        if (path == KernelPath::avx) done = keep_owned_avx(t, point_of, k, keys, kept);
#endif
        (void)path;
        keep_owned_scalar(t, point_of, k, keys, done, kept);
    });
}

void filter_np_triangle_feature(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2,
                                std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept) {
    keep_owned_feature_candidates(params, static_cast<const TriangleModel&>(m1), m2, keys, kept, best_kernel_path());
}

}  // namespace penalty::detail
