// The candidate filters of penalty/collision/candidate_filters.hpp (KernelParts::filter): the
// kernels' first tests alone. The scalar path calls the kernels' own helpers of kernels.hpp
// (gram, closest_feature, inside_triangle, line_line_points); the AVX path writes the same
// operations in four lanes. Near a sphere or a point most candidates fail these tests
// (CompositeCollisionPipeline_none, spheres against tori: 80 % of the Triangle–Sphere
// candidates, whose centre projects onto a vertex or an edge that another triangle owns), and
// the filter costs a fraction of the kernel a candidate.
#include "kernels/collision/candidate_filters.hpp"
#include "penalty/core/pair_key.hpp"

#include "collision/kernels.hpp"
#include "kernels/lanes.hpp"
#include "penalty/core/error.hpp"

namespace penalty::detail {

namespace {

using Keys = std::vector<std::uint64_t>;

/// A Triangle kernel's rule: the region constants, and whether a vertex or an edge the
/// triangle owns gives an output (NewProximity) or only the face's interior (MinProximity,
/// inside_lo and inside_hi its interior bounds).
struct TriangleRule {
    TriangleRegionConstants k;
    bool features;
};

TriangleRule triangle_rule(const IntersectionParams& params, const CollisionModel& m2) {
    const ModelType kind = m2.type();
    if (kind != ModelType::Point && kind != ModelType::Sphere && kind != ModelType::RigidSphere) {
        throw_invalid_argument("keep_triangle_candidates(): '", m2.name(), "' is a ", model_type_name(kind),
                               " model, not a Point, Sphere or RigidSphere model");
    }
    if (params.method == IntersectionMethod::NewProximity)
        return {kind == ModelType::Point ? kNewProximity.triangle_point : triangle_sphere_region(params), true};
    if (params.method == IntersectionMethod::MinProximity) {
        TriangleRegionConstants k{};  // only the interior bounds: no vertex or edge gives an output
        k.inside_lo = kMinProximity.interior_lo;
        k.inside_hi = kMinProximity.interior_hi;
        return {k, false};
    }
    throw_invalid_argument("keep_triangle_candidates(): no filter for ", intersection_method_name(params.method));
}

const LineLineConstants& line_line_rule(const IntersectionParams& params) {
    if (params.method == IntersectionMethod::NewProximity) return kNewProximity.line_line;
    if (params.method == IntersectionMethod::MinProximity) return kMinProximity.line_line;
    throw_invalid_argument("keep_line_line_candidates(): no filter for ", intersection_method_name(params.method));
}

template <class PointOf>
void keep_triangle_scalar(const TriangleModel& t, PointOf&& point_of, const TriangleRule& rule,
                          std::span<const std::uint64_t> keys, std::size_t begin, Keys& kept) {
    for (std::size_t i = begin; i < keys.size(); ++i) {
        const Index e1 = Index(pair_key::first(keys[i]));
        const Gram g = gram(t.p(e1, 0), t.p(e1, 1), t.p(e1, 2), point_of(Index(pair_key::second(keys[i]))));
        if (g.degenerate) continue;
        double alpha = 0.0;
        double beta = 0.0;
        const bool output = rule.features ? closest_feature(g, t.flags(e1), rule.k, alpha, beta)
                                          : inside_triangle(g.alpha, g.beta, rule.k.inside_lo, rule.k.inside_hi);
        if (output) kept.push_back(keys[i]);
    }
}

void keep_line_line_scalar(const LineModel& l1, const LineModel& l2, const LineLineConstants& k,
                           std::span<const std::uint64_t> keys, std::size_t begin, Keys& kept) {
    for (std::size_t i = begin; i < keys.size(); ++i) {
        const Index e1 = Index(pair_key::first(keys[i]));
        const Index e2 = Index(pair_key::second(keys[i]));
        Vec3 p;
        Vec3 q;
        if (line_line_points(l1.p1(e1), l1.p2(e1), l2.p1(e2), l2.p2(e2), k, p, q)) kept.push_back(keys[i]);
    }
}

#ifdef PENALTY_HAS_AVX_LANES
// In lanes, every sum, product and quotient as the scalar helpers write them, and their
// comparisons ordered as C++'s (<, >, >= false on NaN; "!(x > 0)" as not-greater, true on
// NaN). The lanes' regions and their owners' flags are bit masks of the four lanes.
[[gnu::target("avx"), gnu::always_inline]] inline __m256d dot3(__m256d ax, __m256d ay, __m256d az, __m256d bx,
                                                               __m256d by, __m256d bz) {
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ax, bx), _mm256_mul_pd(ay, by)), _mm256_mul_pd(az, bz));
}

/// The kept candidates, gathered in blocks of 64 and appended a block at a time.
struct KeptBlocks {
    explicit KeptBlocks(Keys& to) : kept(to) {}
    static constexpr std::size_t kBlock = 64;
    std::uint64_t block[kBlock];
    std::size_t count = 0;
    Keys& kept;
    /// Appends keys[j] for each bit j of `bits` (four keys), without a branch a key.
    void add4(const std::uint64_t* keys, int bits) {
        std::uint64_t* end = block + count;
        for (int j = 0; j < 4; ++j) {
            *end = keys[j];
            end += (bits >> j) & 1;
        }
        count = std::size_t(end - block);
        if (count > kBlock - 4) flush();
    }
    void flush() {
        kept.insert(kept.end(), block, block + count);
        count = 0;
    }
};

template <bool kFeatures, class PointOf>
[[gnu::target("avx")]] std::size_t keep_triangle_avx(const TriangleModel& t, PointOf&& point_of,
                                                     const TriangleRegionConstants& k,
                                                     std::span<const std::uint64_t> keys, Keys& kept) {
    using F = TriangleModel::Flags;
    if (keys.size() < 4) return 0;
    const __m256d lo = _mm256_set1_pd(k.inside_lo), hi = _mm256_set1_pd(k.inside_hi);
    const __m256d vertex_a_ac = _mm256_set1_pd(k.vertex_a_ac), edge_lo = _mm256_set1_pd(k.edge_lo);
    const __m256d zero = _mm256_setzero_pd(), two = _mm256_set1_pd(2.0);
    // the vertices as t.p(e, c) reads them, the pointers loaded once
    const Triangle* triangles = &t.triangle(0);
    const Vec3* x = t.state().position.data();
    const std::size_t n4 = keys.size() / 4 * 4;
    KeptBlocks out(kept);
    for (std::size_t i = 0; i < n4; i += 4) {
        Index e1[4];
        const double* q[4];
        const double* v[3][4];
        for (int j = 0; j < 4; ++j) {
            e1[j] = Index(pair_key::first(keys[i + j]));
            q[j] = point_of(Index(pair_key::second(keys[i + j]))).data();
            const Triangle& tri = triangles[e1[j]];
            for (int c = 0; c < 3; ++c) v[c][j] = x[tri[std::size_t(c)]].data();
        }
        const Lanes3 p1 = load_lanes(v[0][0], v[0][1], v[0][2], v[0][3]);
        const Lanes3 p2 = load_lanes(v[1][0], v[1][1], v[1][2], v[1][3]);
        const Lanes3 p3 = load_lanes(v[2][0], v[2][1], v[2][2], v[2][3]);
        const Lanes3 pq = load_lanes(q[0], q[1], q[2], q[3]);
        // gram()
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
        // inside_triangle()
        const __m256d alpha_low = _mm256_cmp_pd(alpha, lo, _CMP_LT_OQ);
        const __m256d beta_low = _mm256_cmp_pd(beta, lo, _CMP_LT_OQ);
        const __m256d outside =
            _mm256_or_pd(_mm256_or_pd(alpha_low, beta_low), _mm256_cmp_pd(_mm256_add_pd(alpha, beta), hi, _CMP_GT_OQ));
        const int outside_bits = _mm256_movemask_pd(outside) & ~deg_bits;
        int keep_bits = ~deg_bits & ~outside_bits & 0xF;
        if (kFeatures && outside_bits != 0) {
            // closest_feature()'s chain of regions, as lane masks
            const __m256d pab = _mm256_div_pd(b0, g00);
            const __m256d pac = _mm256_div_pd(b1, g11);
            const __m256d pbc = _mm256_div_pd(_mm256_sub_pd(_mm256_add_pd(_mm256_sub_pd(b1, b0), g00), g01), bc_den);
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
            const __m128i flags =
                _mm_set_epi32(int(t.flags(e1[3])), int(t.flags(e1[2])), int(t.flags(e1[1])), int(t.flags(e1[0])));
            const auto owns = [&flags](std::uint32_t flag) {
                const __m128i none =
                    _mm_cmpeq_epi32(_mm_and_si128(flags, _mm_set1_epi32(int(flag))), _mm_setzero_si128());
                return ~_mm_movemask_ps(_mm_castsi128_ps(none)) & 0xF;
            };
            keep_bits |= (in_a & owns(F::kP1)) | (in_ab & owns(F::kE12)) | (in_ac & owns(k.edge_ac_flag)) |
                         (in_b & owns(F::kP2)) | (in_c & owns(F::kP3)) | (in_bc & owns(k.edge_bc_flag));
        }
        out.add4(keys.data() + i, keep_bits);
    }
    out.flush();
    return n4;
}

[[gnu::target("avx")]] std::size_t keep_line_line_avx(const LineModel& l1, const LineModel& l2,
                                                      const LineLineConstants& k, std::span<const std::uint64_t> keys,
                                                      Keys& kept) {
    if (keys.size() < 4) return 0;
    const __m256d lo = _mm256_set1_pd(k.lo), hi = _mm256_set1_pd(k.hi);
    const __m256d parallel = _mm256_set1_pd(k.parallel), minus_parallel = _mm256_set1_pd(-k.parallel);
    const __m256d sign = _mm256_set1_pd(-0.0);  // x ^ sign = −x, exactly (zeros' signs too)
    const std::size_t n4 = keys.size() / 4 * 4;
    KeptBlocks out(kept);
    for (std::size_t i = 0; i < n4; i += 4) {
        const double* v[4][4];  // p1, p2, q1, q2 of each lane
        for (int j = 0; j < 4; ++j) {
            const Index e1 = Index(pair_key::first(keys[i + j]));
            const Index e2 = Index(pair_key::second(keys[i + j]));
            v[0][j] = l1.p1(e1).data();
            v[1][j] = l1.p2(e1).data();
            v[2][j] = l2.p1(e2).data();
            v[3][j] = l2.p2(e2).data();
        }
        const Lanes3 p1 = load_lanes(v[0][0], v[0][1], v[0][2], v[0][3]);
        const Lanes3 p2 = load_lanes(v[1][0], v[1][1], v[1][2], v[1][3]);
        const Lanes3 q1 = load_lanes(v[2][0], v[2][1], v[2][2], v[2][3]);
        const Lanes3 q2 = load_lanes(v[3][0], v[3][1], v[3][2], v[3][3]);
        // line_line_points()
        const __m256d abx = _mm256_sub_pd(p2.x, p1.x), aby = _mm256_sub_pd(p2.y, p1.y), abz = _mm256_sub_pd(p2.z, p1.z);
        const __m256d cdx = _mm256_sub_pd(q2.x, q1.x), cdy = _mm256_sub_pd(q2.y, q1.y), cdz = _mm256_sub_pd(q2.z, q1.z);
        const __m256d acx = _mm256_sub_pd(q1.x, p1.x), acy = _mm256_sub_pd(q1.y, p1.y), acz = _mm256_sub_pd(q1.z, p1.z);
        const __m256d a00 = dot3(abx, aby, abz, abx, aby, abz);
        const __m256d a11 = dot3(cdx, cdy, cdz, cdx, cdy, cdz);
        const __m256d a01 = _mm256_xor_pd(dot3(cdx, cdy, cdz, abx, aby, abz), sign);  // −(cd·ab)
        const __m256d b0 = dot3(abx, aby, abz, acx, acy, acz);
        const __m256d b1 = _mm256_xor_pd(dot3(cdx, cdy, cdz, acx, acy, acz), sign);  // −(cd·ac)
        const __m256d det = _mm256_sub_pd(_mm256_mul_pd(a00, a11), _mm256_mul_pd(a01, a01));
        const int solved = _mm256_movemask_pd(
            _mm256_or_pd(_mm256_cmp_pd(det, minus_parallel, _CMP_LT_OQ), _mm256_cmp_pd(det, parallel, _CMP_GT_OQ)));
        const __m256d alpha = _mm256_div_pd(_mm256_sub_pd(_mm256_mul_pd(b0, a11), _mm256_mul_pd(b1, a01)), det);
        const __m256d beta = _mm256_div_pd(_mm256_sub_pd(_mm256_mul_pd(b1, a00), _mm256_mul_pd(b0, a01)), det);
        __m256d out_of_range = _mm256_or_pd(_mm256_cmp_pd(alpha, lo, _CMP_LT_OQ), _mm256_cmp_pd(alpha, hi, _CMP_GT_OQ));
        out_of_range = _mm256_or_pd(out_of_range, _mm256_cmp_pd(beta, lo, _CMP_LT_OQ));
        out_of_range = _mm256_or_pd(out_of_range, _mm256_cmp_pd(beta, hi, _CMP_GT_OQ));
        // parallel segments (not solved) take α = β = ½ and always pass
        const int keep_bits = ~(solved & _mm256_movemask_pd(out_of_range)) & 0xF;
        out.add4(keys.data() + i, keep_bits);
    }
    out.flush();
    return n4;
}
#endif

}  // namespace

void keep_triangle_candidates(const IntersectionParams& params, const TriangleModel& t, const CollisionModel& m2,
                              std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept, KernelPath path) {
    const TriangleRule rule = triangle_rule(params, m2);
    kept.reserve(kept.size() + keys.size());
    with_element_points(m2, [&](auto&& point_of) {
        std::size_t done = 0;
#ifdef PENALTY_HAS_AVX_LANES
        if (path == KernelPath::avx) {
            done = rule.features ? keep_triangle_avx<true>(t, point_of, rule.k, keys, kept)
                                 : keep_triangle_avx<false>(t, point_of, rule.k, keys, kept);
        }
#endif
        (void)path;
        keep_triangle_scalar(t, point_of, rule, keys, done, kept);
    });
}

void keep_line_line_candidates(const IntersectionParams& params, const LineModel& l1, const LineModel& l2,
                               std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept, KernelPath path) {
    const LineLineConstants& k = line_line_rule(params);
    kept.reserve(kept.size() + keys.size());
    std::size_t done = 0;
#ifdef PENALTY_HAS_AVX_LANES
    if (path == KernelPath::avx) done = keep_line_line_avx(l1, l2, k, keys, kept);
#endif
    (void)path;
    keep_line_line_scalar(l1, l2, k, keys, done, kept);
}

void filter_triangle_candidates(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2,
                                std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept) {
    keep_triangle_candidates(params, static_cast<const TriangleModel&>(m1), m2, keys, kept, best_kernel_path());
}

void filter_line_line_candidates(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2,
                                 std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept) {
    keep_line_line_candidates(params, static_cast<const LineModel&>(m1), static_cast<const LineModel&>(m2), keys, kept,
                              best_kernel_path());
}

}  // namespace penalty::detail
