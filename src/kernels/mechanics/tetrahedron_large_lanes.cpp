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

/// The vector of W lanes, Lanes4 or Lanes8 (a member typedef keeps their may_alias, which a
/// template argument would drop).
template <std::size_t W>
struct LaneVector;
template <>
struct LaneVector<4> {
    using type = Lanes4;
};
template <>
struct LaneVector<8> {
    using type = Lanes8;
};

/// J(r, c) of a block's W elements (kCofactorOfEntry; never asked where J is 0).
template <std::size_t W>
struct LaneStrainDisplacement {
    using T = typename LaneVector<W>::type;
    const std::array<std::array<std::array<double, W>, 3>, 4>* cofactor;
    [[gnu::always_inline]] const T& operator()(int r, int c) const {
        const auto& entry = (*cofactor)[static_cast<std::size_t>(r / 3)][static_cast<std::size_t>(
            kCofactorOfEntry[static_cast<std::size_t>(r % 3)][static_cast<std::size_t>(c)])];
        return *reinterpret_cast<const T*>(entry.data());
    }
};
/// D/(36V)(i, k) of a block's W elements: the normal block (i, k < 3) and the shear diagonal.
template <std::size_t W>
struct LaneMaterial {
    using T = typename LaneVector<W>::type;
    const std::array<std::array<double, W>, 9>* normal;
    const std::array<std::array<double, W>, 3>* shear;
    [[gnu::always_inline]] const T& operator()(int i, int k) const {
        const auto& entry = i < 3 ? (*normal)[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(k)]
                                  : (*shear)[static_cast<std::size_t>(i) - 3];
        return *reinterpret_cast<const T*>(entry.data());
    }
};

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

/// TetrahedronFEMForceField::add_force's per-element part (method large) for the four elements
/// of a block, one per lane, each lane the scalar operations in their order: the frame R
/// (large_frame), stored into the block and into `rotation8` (the four lanes of an eight-lane
/// block's R where the avx512 product runs, else null), δ from the rotated vertices and the rest
/// coordinates `rest` (rest[1].x, rest[2].x, rest[2].y, rest[3].x, rest[3].y, rest[3].z),
/// F = element_force_of(δ), Rᵀ·F by [vertex][component] (sofa_vec::transpose_times) and the
/// element energies (large_element_energy).
[[gnu::target("avx")]] void large_force_block_avx(detail::TetrahedronLargeBlock& block, double* rotation8,
                                                  const Vec3* x, const Lanes4 (&rest)[6], Lanes4 (&r)[9],
                                                  Lanes4 (&delta)[12], Lanes4 (&force)[12], Lanes4 (&back)[4][3],
                                                  Lanes4& energy) {
    Lanes4 p[4][3];
    for (std::size_t v = 0; v < 4; ++v)
        for (std::size_t c = 0; c < 3; ++c) {
            const auto& dof = block.vertex[v];
            p[v][c] = Lanes4{x[dof[0]][c], x[dof[1]][c], x[dof[2]][c], x[dof[3]][c]};
        }
    // large_frame(p0, p1, p2): x̂ = normalized(p1 − p0), ẑ = normalized(x̂ × (p2 − p0)), ŷ = ẑ × x̂
    Lanes4 edge[3], x_axis[3], z_dir[3], z_axis[3], y_axis[3];
    for (std::size_t c = 0; c < 3; ++c) edge[c] = p[1][c] - p[0][c];
    normalized_lanes(edge, x_axis);
    for (std::size_t c = 0; c < 3; ++c) edge[c] = p[2][c] - p[0][c];
    cross_lanes(x_axis, edge, z_dir);
    normalized_lanes(z_dir, z_axis);
    cross_lanes(z_axis, x_axis, y_axis);
    for (std::size_t c = 0; c < 3; ++c) {
        r[c] = x_axis[c];
        r[3 + c] = y_axis[c];
        r[6 + c] = z_axis[c];
    }
    for (std::size_t i = 0; i < 9; ++i) {
        _mm256_store_pd(block.rotation[i].data(), r[i]);
        if (rotation8) _mm256_store_pd(rotation8 + i * detail::TetrahedronLargeBlock8::kLanes, r[i]);
    }
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
    element_force_of<Lanes4>(LaneStrainDisplacement<4>{&block.cofactor}, LaneMaterial<4>{&block.material, &block.shear},
                             delta, nullptr, force);
    // Rᵀ·F_k: row i = R(0,i)F₀ + R(1,i)F₁ + R(2,i)F₂
    for (std::size_t v = 0; v < 4; ++v)
        for (std::size_t i = 0; i < 3; ++i)
            back[v][i] = r[i] * force[3 * v] + r[3 + i] * force[3 * v + 1] + r[6 + i] * force[3 * v + 2];
    large_element_energy(delta, force, energy);
}
}  // namespace

double large_add_force_avx(std::span<TetrahedronLargeBlock> blocks, std::span<TetrahedronLargeBlock8> blocks8,
                           std::span<const std::array<Vec3, 4>> rest_local,
                           std::span<const std::array<PointId, 4>> elements, std::span<Mat3> rotation, const Vec3* x,
                           Vec3* f) {
    double total = 0.0;
    for (std::size_t first = 0; first < elements.size(); first += 4) {
        const std::size_t lanes = std::min<std::size_t>(4, elements.size() - first);
        Lanes4 rest[6];
        for (std::size_t lane = 0; lane < 4; ++lane) {
            const auto& local = rest_local[first + (lane < lanes ? lane : 0)];
            rest[0][lane] = local[1][0];
            rest[1][lane] = local[2][0];
            rest[2][lane] = local[2][1];
            for (std::size_t c = 0; c < 3; ++c) rest[3 + c][lane] = local[3][c];
        }
        Lanes4 r[9], delta[12], force[12], back[4][3], energy;
        // R into both blocks (the eight-lane block's half of this block's elements, lanes past
        // the last element included: their products are never added)
        double* rotation8 = blocks8.empty() ? nullptr : blocks8[first / 8].rotation[0].data() + first % 8;
        large_force_block_avx(blocks[first / 4], rotation8, x, rest, r, delta, force, back, energy);
        for (std::size_t lane = 0; lane < lanes; ++lane) {
            const std::size_t e = first + lane;
            Mat3& frame = rotation[e];
            for (std::size_t i = 0; i < 9; ++i)
                frame(static_cast<Index>(i / 3), static_cast<Index>(i % 3)) = r[i][lane];
            total += energy[lane];
            for (std::size_t k = 0; k < 4; ++k) {
                Vec3& target = f[static_cast<std::size_t>(elements[e][k])];
                for (std::size_t c = 0; c < 3; ++c) target[static_cast<Index>(c)] += back[k][c][lane];
            }
        }
    }
    return total;
}

/// TetrahedronFEMForceField::add_dforce (method large) for four elements at once, one per lane:
/// each lane does its element's operations of the scalar loop (R·dx per vertex, element_force_of,
/// Rᵀ·F per vertex), in the same order, with IEEE lane-wise operations and no fused
/// multiply-add, so each lane's F has the scalar loop's bits; df −= Rᵀ·F is then done element
/// by element, vertex by vertex, in the scalar loop's order.
[[gnu::target("avx")]] void large_dforce_avx(const detail::TetrahedronLargeBlock* blocks, std::size_t element_count,
                                             Vec3* df, const Vec3* dx, double k_factor) {
    const Lanes4 k = {k_factor, k_factor, k_factor, k_factor};
    for (std::size_t first = 0; first < element_count; first += 4) {
        const detail::TetrahedronLargeBlock& block = blocks[first / 4];
        const auto* r = reinterpret_cast<const Lanes4*>(block.rotation.data());
        Lanes4 local[12];  // R·dx_k (sofa_vec::times: row i = R(i,0)dx₀ + R(i,1)dx₁ + R(i,2)dx₂)
        for (std::size_t v = 0; v < 4; ++v) {
            const auto& dof = block.vertex[v];
            Lanes4 d[3];
            for (std::size_t c = 0; c < 3; ++c)
                d[c] = Lanes4{dx[dof[0]][c], dx[dof[1]][c], dx[dof[2]][c], dx[dof[3]][c]};
            for (std::size_t i = 0; i < 3; ++i)
                local[3 * v + i] = r[3 * i] * d[0] + r[3 * i + 1] * d[1] + r[3 * i + 2] * d[2];
        }
        Lanes4 force[12];
        element_force_of(LaneStrainDisplacement<4>{&block.cofactor}, LaneMaterial<4>{&block.material, &block.shear},
                         local, &k, force);
        // Rᵀ·F_k (sofa_vec::transpose_times: row i = R(0,i)F₀ + R(1,i)F₁ + R(2,i)F₂), by [vertex][component]
        Lanes4 back[4][3];
        for (std::size_t v = 0; v < 4; ++v)
            for (std::size_t i = 0; i < 3; ++i)
                back[v][i] = r[i] * force[3 * v] + r[3 + i] * force[3 * v + 1] + r[6 + i] * force[3 * v + 2];
        const std::size_t lanes = std::min<std::size_t>(4, element_count - first);
        for (std::size_t e = 0; e < lanes; ++e)
            for (std::size_t v = 0; v < 4; ++v) {
                Vec3& target = df[block.vertex[v][e]];
                for (std::size_t c = 0; c < 3; ++c) target[static_cast<Index>(c)] -= back[v][c][e];
            }
    }
}

/// large_dforce_avx for eight elements at once (KernelPath::avx512): the same operations per
/// lane and the same order of the df updates. (Its own function, not one template with the
/// four-lane one: GCC unrolled and spilled the template's four-lane instance differently, 7–10 %
/// slower.)
[[gnu::target("avx512f")]] void large_dforce_avx512(const detail::TetrahedronLargeBlock8* blocks,
                                                    std::size_t element_count, Vec3* df, const Vec3* dx,
                                                    double k_factor) {
    const Lanes8 k = {k_factor, k_factor, k_factor, k_factor, k_factor, k_factor, k_factor, k_factor};
    for (std::size_t first = 0; first < element_count; first += 8) {
        const detail::TetrahedronLargeBlock8& block = blocks[first / 8];
        const auto* r = reinterpret_cast<const Lanes8*>(block.rotation.data());
        Lanes8 local[12];
        for (std::size_t v = 0; v < 4; ++v) {
            const auto& dof = block.vertex[v];
            Lanes8 d[3];
            for (std::size_t c = 0; c < 3; ++c)
                d[c] = Lanes8{dx[dof[0]][c], dx[dof[1]][c], dx[dof[2]][c], dx[dof[3]][c],
                              dx[dof[4]][c], dx[dof[5]][c], dx[dof[6]][c], dx[dof[7]][c]};
            for (std::size_t i = 0; i < 3; ++i)
                local[3 * v + i] = r[3 * i] * d[0] + r[3 * i + 1] * d[1] + r[3 * i + 2] * d[2];
        }
        Lanes8 force[12];
        element_force_of(LaneStrainDisplacement<8>{&block.cofactor}, LaneMaterial<8>{&block.material, &block.shear},
                         local, &k, force);
        Lanes8 back[4][3];
        for (std::size_t v = 0; v < 4; ++v)
            for (std::size_t i = 0; i < 3; ++i)
                back[v][i] = r[i] * force[3 * v] + r[3 + i] * force[3 * v + 1] + r[6 + i] * force[3 * v + 2];
        const std::size_t lanes = std::min<std::size_t>(8, element_count - first);
        for (std::size_t e = 0; e < lanes; ++e)
            for (std::size_t v = 0; v < 4; ++v) {
                Vec3& target = df[block.vertex[v][e]];
                for (std::size_t c = 0; c < 3; ++c) target[static_cast<Index>(c)] -= back[v][c][e];
            }
    }
}

}  // namespace penalty::detail
#endif
