#include "kernels/mechanics/tetrahedron_large_lanes.hpp"

#ifdef PENALTY_HAS_AVX_LANES
#include "kernels/mechanics/tetrahedron_large.hpp"

#include <algorithm>
#include <limits>

namespace penalty::detail {
namespace {
/// Four doubles, one element's value per lane; every operator is lane-wise IEEE arithmetic.
typedef double Lanes4 __attribute__((vector_size(32), __may_alias__));
/// Eight doubles, the same (KernelPath::avx512's product only).
typedef double Lanes8 __attribute__((vector_size(64), __may_alias__));
/// Four and eight lanes as lanes_at reads them.
struct FourLanes {
    using type = Lanes4;
};
struct EightLanes {
    using type = Lanes8;
};
using Block4 = TetrahedronLargeLanes<4>;
using Block8 = TetrahedronLargeLanes<8>;
using Elements = std::span<const std::array<PointId, 4>>;

/// The vertices of elements first … first + W − 1, W in a row: the element list itself, or for a
/// last block a copy in `tail` whose missing elements have the first one's vertices (their
/// results are never added).
template <std::size_t W>
[[gnu::always_inline]] inline const std::array<PointId, 4>* lane_vertices(Elements elements, std::size_t first,
                                                                          std::array<std::array<PointId, 4>, W>& tail) {
    if (first + W <= elements.size()) return elements.data() + first;
    for (std::size_t lane = 0; lane < W; ++lane)
        tail[lane] = elements[first + lane < elements.size() ? first + lane : first];
    return tail.data();
}

/// sofa_vec::normalized lane by lane: v/√(v·v), or v itself where √(v·v) ≤ ε (or NaN).
[[gnu::target("avx"), gnu::always_inline]] inline void normalized_lanes(const Lanes4 (&v)[3], Lanes4 (&out)[3]) {
    const Lanes4 norm = _mm256_sqrt_pd(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const __m256d keep = _mm256_cmp_pd(norm, _mm256_set1_pd(std::numeric_limits<double>::epsilon()), _CMP_GT_OQ);
    for (std::size_t c = 0; c < 3; ++c) out[c] = _mm256_blendv_pd(v[c], v[c] / norm, keep);
}
/// sofa_vec::cross lane by lane.
[[gnu::always_inline]] inline void cross_lanes(const Lanes4 (&a)[3], const Lanes4 (&b)[3], Lanes4 (&out)[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/// TetrahedronFEMForceField::add_force's per-element part (method large) for four elements, lanes
/// `first` … `first` + 3 of a block, one per lane, each lane the scalar operations in their order:
/// the frame R (large_frame), stored into the block, δ from the rotated vertices and the rest
/// coordinates `rest` (rest[1].x, rest[2].x, rest[2].y, rest[3].x, rest[3].y, rest[3].z),
/// F = element_force_of(δ), Rᵀ·F by [vertex][component] (sofa_vec::transpose_times) and the
/// element energies (large_element_energy).
template <class Block>
[[gnu::target("avx")]] void large_force_lanes_avx(Block& block, std::size_t first,
                                                  const std::array<PointId, 4>* vertices, const Vec3* x,
                                                  const Lanes4 (&rest)[6], Lanes4 (&delta)[12], Lanes4 (&force)[12],
                                                  Lanes4 (&back)[4][3], Lanes4& energy) {
    Lanes4 p[4][3];
    for (std::size_t v = 0; v < 4; ++v)
        for (std::size_t c = 0; c < 3; ++c) {
            const auto dof = [&](std::size_t lane) { return static_cast<std::size_t>(vertices[lane][v]); };
            p[v][c] = Lanes4{x[dof(0)][c], x[dof(1)][c], x[dof(2)][c], x[dof(3)][c]};
        }
    // large_frame(p0, p1, p2): x̂ = normalized(p1 − p0), ẑ = normalized(x̂ × (p2 − p0)), ŷ = ẑ × x̂
    Lanes4 edge[3], x_axis[3], z_dir[3], z_axis[3], y_axis[3];
    for (std::size_t c = 0; c < 3; ++c) edge[c] = p[1][c] - p[0][c];
    normalized_lanes(edge, x_axis);
    for (std::size_t c = 0; c < 3; ++c) edge[c] = p[2][c] - p[0][c];
    cross_lanes(x_axis, edge, z_dir);
    normalized_lanes(z_dir, z_axis);
    cross_lanes(z_axis, x_axis, y_axis);
    Lanes4 r[9];
    for (std::size_t c = 0; c < 3; ++c) {
        r[c] = x_axis[c];
        r[3 + c] = y_axis[c];
        r[6 + c] = z_axis[c];
    }
    for (std::size_t i = 0; i < 9; ++i) _mm256_store_pd(block.rotation[i].data() + first, r[i]);
    // each vertex rotated (sofa_vec::times), then δ = rest − (R·p_k − R·p_0) in the entries J couples
    Lanes4 deformed[4][3];
    for (std::size_t v = 0; v < 4; ++v)
        for (std::size_t i = 0; i < 3; ++i)
            deformed[v][i] = r[3 * i] * p[v][0] + r[3 * i + 1] * p[v][1] + r[3 * i + 2] * p[v][2];
    const Lanes4 zero = {0.0, 0.0, 0.0, 0.0};
    for (auto& d : delta) d = zero;
    delta[3] = rest[0] - (deformed[1][0] - deformed[0][0]);
    delta[6] = rest[1] - (deformed[2][0] - deformed[0][0]);
    delta[7] = rest[2] - (deformed[2][1] - deformed[0][1]);
    for (std::size_t c = 0; c < 3; ++c) delta[9 + c] = rest[3 + c] - (deformed[3][c] - deformed[0][c]);
    element_force_of<Lanes4>(LaneStrainDisplacement<FourLanes, Block>{block, first},
                             LaneMaterial<FourLanes, Block>{block, first}, delta, nullptr, force);
    // Rᵀ·F_k: row i = R(0,i)F₀ + R(1,i)F₁ + R(2,i)F₂
    for (std::size_t v = 0; v < 4; ++v)
        for (std::size_t i = 0; i < 3; ++i)
            back[v][i] = r[i] * force[3 * v] + r[3 + i] * force[3 * v + 1] + r[6 + i] * force[3 * v + 2];
    large_element_energy(delta, force, energy);
}
}  // namespace

/// The last part of a force (Add: f += Rᵀ·F_k) or product (df −= Rᵀ·F_k) for the lanes of
/// elements first … first + lanes − 1, element by element, vertex by vertex, but for the terms
/// that `deferred` marks (bit k of element e, when not null), which go to terms[e·4 + k] instead.
template <bool Add, class LanesW>
[[gnu::always_inline]] inline void store_or_apply_lanes(const LanesW (&back)[4][3],
                                                        const std::array<PointId, 4>* vertices, std::size_t lanes,
                                                        Vec3* out, const DeferredTerms& deferred, std::size_t first) {
    for (std::size_t e = 0; e < lanes; ++e) {
        const unsigned mask = deferred.mask ? deferred.mask[first + e] : 0U;
        for (std::size_t v = 0; v < 4; ++v) {
            if ((mask >> v) & 1U) {
                Vec3& term = deferred.terms[4 * (first + e) + v];
                for (std::size_t c = 0; c < 3; ++c) term[static_cast<Index>(c)] = back[v][c][e];
            } else {
                Vec3& target = out[static_cast<std::size_t>(vertices[e][v])];
                for (std::size_t c = 0; c < 3; ++c) {
                    if constexpr (Add) target[static_cast<Index>(c)] += back[v][c][e];
                    else target[static_cast<Index>(c)] -= back[v][c][e];
                }
            }
        }
    }
}

template <std::size_t W>
double large_add_force_avx(std::span<TetrahedronLargeLanes<W>> blocks, std::span<const std::array<Vec3, 4>> rest_local,
                           Elements elements, ElementRange range, const Vec3* x, Vec3* f, const DeferredTerms& deferred,
                           double* energies) {
    double total = 0.0;
    for (std::size_t first = range.first; first < range.end; first += 4) {
        const std::size_t lanes = std::min<std::size_t>(4, range.end - first);
        Lanes4 rest[6];
        for (std::size_t lane = 0; lane < 4; ++lane) {
            const auto& local = rest_local[first + (lane < lanes ? lane : 0)];
            rest[0][lane] = local[1][0];
            rest[1][lane] = local[2][0];
            rest[2][lane] = local[2][1];
            for (std::size_t c = 0; c < 3; ++c) rest[3 + c][lane] = local[3][c];
        }
        Lanes4 delta[12], force[12], back[4][3], energy;
        std::array<std::array<PointId, 4>, 4> tail;
        const std::array<PointId, 4>* vertices = lane_vertices<4>(elements, first, tail);
        large_force_lanes_avx(blocks[first / W], W == 4 ? 0 : first % W, vertices, x, rest, delta, force, back, energy);
        for (std::size_t lane = 0; lane < lanes; ++lane) {
            if (energies) energies[first + lane] = energy[lane];
            else total += energy[lane];
        }
        store_or_apply_lanes<true>(back, vertices, lanes, f, deferred, first);
    }
    return total;
}
template double large_add_force_avx<4>(std::span<Block4>, std::span<const std::array<Vec3, 4>>, Elements, ElementRange,
                                       const Vec3*, Vec3*, const DeferredTerms&, double*);
template double large_add_force_avx<8>(std::span<Block8>, std::span<const std::array<Vec3, 4>>, Elements, ElementRange,
                                       const Vec3*, Vec3*, const DeferredTerms&, double*);

/// TetrahedronFEMForceField::add_dforce (method large) for four elements at once, one per lane:
/// each lane does its element's operations of the scalar loop (R·dx per vertex, element_force_of,
/// Rᵀ·F per vertex), in the same order, with IEEE lane-wise operations and no fused multiply-add,
/// so each lane's F has the scalar loop's bits; df −= Rᵀ·F is then done element by element,
/// vertex by vertex, in the scalar loop's order (the deferred terms stored, see the header).
[[gnu::target("avx")]] void large_dforce_avx(const Block4* blocks, Elements elements, ElementRange range, Vec3* df,
                                             const Vec3* dx, double k_factor, const DeferredTerms& deferred) {
    const Lanes4 k = {k_factor, k_factor, k_factor, k_factor};
    for (std::size_t first = range.first; first < range.end; first += 4) {
        const Block4& block = blocks[first / 4];
        std::array<std::array<PointId, 4>, 4> tail;
        const std::array<PointId, 4>* vertices = lane_vertices<4>(elements, first, tail);
        const auto* r = reinterpret_cast<const Lanes4*>(block.rotation.data());
        Lanes4 local[12];  // R·dx_k (sofa_vec::times: row i = R(i,0)dx₀ + R(i,1)dx₁ + R(i,2)dx₂)
        for (std::size_t v = 0; v < 4; ++v) {
            const auto dof = [&](std::size_t lane) { return static_cast<std::size_t>(vertices[lane][v]); };
            Lanes4 d[3];
            for (std::size_t c = 0; c < 3; ++c)
                d[c] = Lanes4{dx[dof(0)][c], dx[dof(1)][c], dx[dof(2)][c], dx[dof(3)][c]};
            for (std::size_t i = 0; i < 3; ++i)
                local[3 * v + i] = r[3 * i] * d[0] + r[3 * i + 1] * d[1] + r[3 * i + 2] * d[2];
        }
        Lanes4 force[12];
        element_force_of(LaneStrainDisplacement<FourLanes, Block4>{block, 0}, LaneMaterial<FourLanes, Block4>{block, 0},
                         local, &k, force);
        // Rᵀ·F_k (sofa_vec::transpose_times: row i = R(0,i)F₀ + R(1,i)F₁ + R(2,i)F₂), by [vertex][component]
        Lanes4 back[4][3];
        for (std::size_t v = 0; v < 4; ++v)
            for (std::size_t i = 0; i < 3; ++i)
                back[v][i] = r[i] * force[3 * v] + r[3 + i] * force[3 * v + 1] + r[6 + i] * force[3 * v + 2];
        store_or_apply_lanes<false>(back, vertices, std::min<std::size_t>(4, range.end - first), df, deferred, first);
    }
}

/// large_dforce_avx for eight elements at once (KernelPath::avx512): the same operations per lane
/// and the same order of the df updates. (Its own function, not one template with the four-lane
/// one: GCC unrolled and spilled the template's four-lane instance differently, 7–10 % slower.)
[[gnu::target("avx512f")]] void large_dforce_avx512(const Block8* blocks, Elements elements, ElementRange range,
                                                    Vec3* df, const Vec3* dx, double k_factor,
                                                    const DeferredTerms& deferred) {
    const Lanes8 k = {k_factor, k_factor, k_factor, k_factor, k_factor, k_factor, k_factor, k_factor};
    for (std::size_t first = range.first; first < range.end; first += 8) {
        const Block8& block = blocks[first / 8];
        std::array<std::array<PointId, 4>, 8> tail;
        const std::array<PointId, 4>* vertices = lane_vertices<8>(elements, first, tail);
        const auto* r = reinterpret_cast<const Lanes8*>(block.rotation.data());
        Lanes8 local[12];
        for (std::size_t v = 0; v < 4; ++v) {
            const auto dof = [&](std::size_t lane) { return static_cast<std::size_t>(vertices[lane][v]); };
            Lanes8 d[3];
            for (std::size_t c = 0; c < 3; ++c)
                d[c] = Lanes8{dx[dof(0)][c], dx[dof(1)][c], dx[dof(2)][c], dx[dof(3)][c],
                              dx[dof(4)][c], dx[dof(5)][c], dx[dof(6)][c], dx[dof(7)][c]};
            for (std::size_t i = 0; i < 3; ++i)
                local[3 * v + i] = r[3 * i] * d[0] + r[3 * i + 1] * d[1] + r[3 * i + 2] * d[2];
        }
        Lanes8 force[12];
        element_force_of(LaneStrainDisplacement<EightLanes, Block8>{block, 0},
                         LaneMaterial<EightLanes, Block8>{block, 0}, local, &k, force);
        Lanes8 back[4][3];
        for (std::size_t v = 0; v < 4; ++v)
            for (std::size_t i = 0; i < 3; ++i)
                back[v][i] = r[i] * force[3 * v] + r[3 + i] * force[3 * v + 1] + r[6 + i] * force[3 * v + 2];
        store_or_apply_lanes<false>(back, vertices, std::min<std::size_t>(8, range.end - first), df, deferred, first);
    }
}

}  // namespace penalty::detail
#endif
