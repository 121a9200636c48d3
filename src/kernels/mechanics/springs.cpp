#include "kernels/mechanics/springs.hpp"

#include "kernels/lanes.hpp"

#include "penalty/core/error.hpp"

#include <cmath>

namespace penalty::detail {
namespace {
/// f1[a] += t, f2[b] −= t of spring i, or, where `deferred` marks them, t and −t stored at 2i
/// and 2i + 1 (added after; x − t and x + (−t) are the same bits).
inline void add_spring_terms(const DeferredTerms& deferred, std::size_t i, Vec3& end_a, Vec3& end_b, const Vec3& t) {
    const unsigned mask = deferred.mask ? deferred.mask[i] : 0U;
    if (mask & 1U) deferred.terms[2 * i] = t;
    else end_a += t;
    if (mask & 2U) deferred.terms[2 * i + 1] = -t;
    else end_b -= t;
}

/// A spring's energy: added to `energy`, or stored at energies[i] (not null).
inline void add_energy(double* energies, std::size_t i, double e, double& energy) {
    if (energies) energies[i] = e;
    else energy += e;
}

/// SOFA's SpringForceField::computeSpringForce for springs [begin, end), operation by operation
/// (the rounding of every step is SOFA's): u = x_b − x_a, d = |u|, U = u·(1/d), elongation
/// e = d − l0, intensity f = ks·e + kd·(U·(v_b − v_a)), force f·U, dF/dX = (ks − f/d)·U·Uᵀ + f/d·I
/// with f/d computed as f·(1/d) and each entry ((ks − t)·U_j)·U_k (QuadularBendingSprings:
/// (ks − t)·((u_j/d)·(u_k/d))). A spring no longer than the null length gets no force and a zero
/// m. The energy ½·ks·e² is added spring by spring, in order (or stored per spring:
/// add_energy).
template <class Stiffness>
void spring_force(SpringArithmetic arithmetic, const Spring* springs, std::size_t begin, std::size_t end,
                  double null_length, Vec3* f1, Vec3* f2, const Vec3* x1, const Vec3* x2, const Vec3* v1,
                  const Vec3* v2, Stiffness* dfdx, double& energy, const DeferredTerms& deferred, double* energies) {
    for (std::size_t i = begin; i < end; ++i) {
        const Spring& s = springs[i];
        const auto a = static_cast<std::size_t>(s.a);
        const auto b = static_cast<std::size_t>(s.b);
        const Vec3 u = x2[b] - x1[a];
        const double d = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (d <= null_length) {
            dfdx[i] = Stiffness{};
            if (energies) energies[i] = 0.0;  // (the sum's terms are ≥ 0: adding +0 changes no bit)
            continue;
        }
        const double inverse_length = 1.0 / d;
        const Vec3 n(u[0] * inverse_length, u[1] * inverse_length, u[2] * inverse_length);
        const double elongation = d - s.rest_length;
        add_energy(energies, i, elongation * elongation * s.ks / 2, energy);
        const Vec3 relative_velocity = v2[b] - v1[a];
        const double elongation_velocity =
            n[0] * relative_velocity[0] + n[1] * relative_velocity[1] + n[2] * relative_velocity[2];
        const double intensity = s.ks * elongation + s.kd * elongation_velocity;
        const Vec3 force(n[0] * intensity, n[1] * intensity, n[2] * intensity);
        add_spring_terms(deferred, i, f1[a], f2[b], force);
        const double t = intensity * inverse_length;
        auto& m = dfdx[i].column;  // m(j, k) is m[k][j]
        if (arithmetic == SpringArithmetic::quadular_bending_springs) {
            // QuadularBendingSprings::computeLocalJacobian: (ks − t)·dyad(u/d, u/d) + t·I
            const Vec3 w(u[0] / d, u[1] / d, u[2] / d);
            for (std::size_t j = 0; j < 3; ++j) {
                for (std::size_t k = 0; k < 3; ++k) m[k][j] = (s.ks - t) * (w[j] * w[k]);
                m[j][j] += t;
            }
            continue;
        }
        for (std::size_t j = 0; j < 3; ++j) {
            for (std::size_t k = 0; k < 3; ++k) m[k][j] = (s.ks - t) * n[j] * n[k];
            m[j][j] += t;
        }
    }
}

#ifdef PENALTY_HAS_AVX_LANES
/// spring_force on springs [begin, end) but the last (end − begin) % 4, four springs in the four
/// lanes: lane k does spring_force's operations for spring i + k, in its order (target avx, no
/// fused multiply-add), so every bit is the scalar loop's; then the forces and the energy are
/// added spring by spring in spring order, and each spring's m is stored as its three padded
/// columns. Returns the first spring not done.
template <SpringArithmetic Arithmetic, class Stiffness>
[[gnu::target("avx")]] std::size_t spring_force_avx(const Spring* springs, std::size_t begin, std::size_t end,
                                                    double null_length, Vec3* f1, Vec3* f2, const Vec3* x1,
                                                    const Vec3* x2, const Vec3* v1, const Vec3* v2, Stiffness* dfdx,
                                                    double& energy, const DeferredTerms& deferred, double* energies) {
    const __m256d one = _mm256_set1_pd(1.0), two = _mm256_set1_pd(2.0), null = _mm256_set1_pd(null_length);
    std::size_t i = begin;
    for (; i + 4 <= end; i += 4) {
        const Spring* s = springs + i;
        std::size_t a[4], b[4];
        for (int k = 0; k < 4; ++k) {
            a[k] = static_cast<std::size_t>(s[k].a);
            b[k] = static_cast<std::size_t>(s[k].b);
        }
        const detail::Lanes3 xa =
            detail::load_lanes(x1[a[0]].data(), x1[a[1]].data(), x1[a[2]].data(), x1[a[3]].data());
        const detail::Lanes3 xb =
            detail::load_lanes(x2[b[0]].data(), x2[b[1]].data(), x2[b[2]].data(), x2[b[3]].data());
        const __m256d ks = _mm256_set_pd(s[3].ks, s[2].ks, s[1].ks, s[0].ks);
        const __m256d kd = _mm256_set_pd(s[3].kd, s[2].kd, s[1].kd, s[0].kd);
        const __m256d l0 = _mm256_set_pd(s[3].rest_length, s[2].rest_length, s[1].rest_length, s[0].rest_length);
        const __m256d ux = _mm256_sub_pd(xb.x, xa.x), uy = _mm256_sub_pd(xb.y, xa.y), uz = _mm256_sub_pd(xb.z, xa.z);
        const __m256d d = _mm256_sqrt_pd(
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ux, ux), _mm256_mul_pd(uy, uy)), _mm256_mul_pd(uz, uz)));
        // not d <= null length (unordered: a NaN length is a spring, as in the scalar test)
        const __m256d live = _mm256_cmp_pd(d, null, _CMP_NLE_UQ);
        const int live_lanes = _mm256_movemask_pd(live);
        const __m256d inverse_length = _mm256_div_pd(one, d);
        const __m256d nx = _mm256_mul_pd(ux, inverse_length), ny = _mm256_mul_pd(uy, inverse_length),
                      nz = _mm256_mul_pd(uz, inverse_length);
        const __m256d elongation = _mm256_sub_pd(d, l0);
        const __m256d spring_energy = _mm256_div_pd(_mm256_mul_pd(_mm256_mul_pd(elongation, elongation), ks), two);
        const detail::Lanes3 va =
            detail::load_lanes(v1[a[0]].data(), v1[a[1]].data(), v1[a[2]].data(), v1[a[3]].data());
        const detail::Lanes3 vb =
            detail::load_lanes(v2[b[0]].data(), v2[b[1]].data(), v2[b[2]].data(), v2[b[3]].data());
        const __m256d rx = _mm256_sub_pd(vb.x, va.x), ry = _mm256_sub_pd(vb.y, va.y), rz = _mm256_sub_pd(vb.z, va.z);
        const __m256d elongation_velocity =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, rx), _mm256_mul_pd(ny, ry)), _mm256_mul_pd(nz, rz));
        const __m256d intensity = _mm256_add_pd(_mm256_mul_pd(ks, elongation), _mm256_mul_pd(kd, elongation_velocity));
        alignas(32) double fx[4], fy[4], fz[4], e[4];
        _mm256_store_pd(fx, _mm256_mul_pd(nx, intensity));
        _mm256_store_pd(fy, _mm256_mul_pd(ny, intensity));
        _mm256_store_pd(fz, _mm256_mul_pd(nz, intensity));
        _mm256_store_pd(e, spring_energy);
        for (std::size_t k = 0; k < 4; ++k) {
            if (!(live_lanes & (1 << k))) {
                if (energies) energies[i + k] = 0.0;
                continue;
            }
            add_energy(energies, i + k, e[k], energy);
            add_spring_terms(deferred, i + k, f1[a[k]], f2[b[k]], Vec3(fx[k], fy[k], fz[k]));
        }
        const __m256d t = _mm256_mul_pd(intensity, inverse_length);
        const __m256d c = _mm256_sub_pd(ks, t);
        __m256d w[3];
        if constexpr (Arithmetic == SpringArithmetic::quadular_bending_springs) {
            w[0] = _mm256_div_pd(ux, d);
            w[1] = _mm256_div_pd(uy, d);
            w[2] = _mm256_div_pd(uz, d);
        } else {
            w[0] = nx;
            w[1] = ny;
            w[2] = nz;
        }
        for (int k = 0; k < 3; ++k) {  // column k: m[k][j] for j = 0, 1, 2; short springs get zeros
            __m256d row[3];
            for (int j = 0; j < 3; ++j) {
                __m256d m;
                if constexpr (Arithmetic == SpringArithmetic::quadular_bending_springs)
                    m = _mm256_mul_pd(c, _mm256_mul_pd(w[j], w[k]));
                else m = _mm256_mul_pd(_mm256_mul_pd(c, w[j]), w[k]);
                if (j == k) m = _mm256_add_pd(m, t);
                row[j] = _mm256_and_pd(m, live);
            }
            detail::store_rows_padded(row[0], row[1], row[2], dfdx[i].column[std::size_t(k)].data(),
                                      dfdx[i + 1].column[std::size_t(k)].data(),
                                      dfdx[i + 2].column[std::size_t(k)].data(),
                                      dfdx[i + 3].column[std::size_t(k)].data());
        }
    }
    return i;
}
#endif

/// df1[a] += d, df2[b] −= d for each spring in order, d = SOFA's computeSpringDForce of
/// `Arithmetic` (see SpringArithmetic). The loop reads raw pointers held in locals, so that the
/// stores into df do not force the compiler to reload the spring list's bounds per spring; each
/// floating-point operation and its order are those of the straightforward loop.
template <SpringArithmetic Arithmetic, bool Deferring, class Stiffness>
void spring_dforce(const Spring* springs, const Stiffness* dfdx, std::size_t begin, std::size_t end, Vec3* df1,
                   Vec3* df2, const Vec3* dx1, const Vec3* dx2, double k_factor, const DeferredTerms& deferred) {
    for (std::size_t i = begin; i < end; ++i) {
        const auto a = static_cast<std::size_t>(springs[i].a);
        const auto b = static_cast<std::size_t>(springs[i].b);
        const Vec3 dx = dx2[b] - dx1[a];
        const Stiffness& m = dfdx[i];
        Vec3 d;
        if constexpr (Arithmetic == SpringArithmetic::quadular_bending_springs) {
            // QuadularBendingSprings::addDForce: DfDx·(ddx·kFactor)
            const Vec3 s(dx[0] * k_factor, dx[1] * k_factor, dx[2] * k_factor);
            for (int r = 0; r < 3; ++r) d[r] = m(r, 0) * s[0] + m(r, 1) * s[1] + m(r, 2) * s[2];
        } else {
            // SOFA's computeSpringDForce: (dfdx·(dx_b − dx_a))·kFactor, rows summed left to right.
            for (int r = 0; r < 3; ++r) d[r] = (m(r, 0) * dx[0] + m(r, 1) * dx[1] + m(r, 2) * dx[2]) * k_factor;
        }
        if constexpr (Deferring) {
            add_spring_terms(deferred, i, df1[a], df2[b], d);
        } else {
            df1[a] += d;
            df2[b] -= d;
        }
    }
}

#ifdef PENALTY_HAS_AVX_LANES
/// The three doubles of the Vec3 at byte offset `offset` of an array.
inline const double* at(const Vec3* base, std::ptrdiff_t offset) {
    return reinterpret_cast<const double*>(reinterpret_cast<const char*>(base) + offset);
}
inline double* at(Vec3* base, std::ptrdiff_t offset) {
    return reinterpret_cast<double*>(reinterpret_cast<char*>(base) + offset);
}

/// The same product with the three rows of m·dx in the lanes 0–2 of 256-bit registers (lane 3
/// computes 0·dx and is dropped): lane r does row r's operations of spring_dforce, in its order,
/// each an IEEE operation of the same operands, so every bit is the scalar loop's. The
/// differences dx_b − dx_a are formed in every lane (broadcast operands); df is updated spring by
/// spring in spring order (x and y in one 128-bit add, z alone). `ends`: the springs' ends as
/// byte offsets (SpringForceField::end_offsets_).
template <SpringArithmetic Arithmetic, bool Deferring, class Stiffness>
[[gnu::target("avx")]] void spring_dforce_avx(const std::array<std::ptrdiff_t, 2>* ends, const Stiffness* dfdx,
                                              std::size_t begin, std::size_t end, Vec3* df1, Vec3* df2, const Vec3* dx1,
                                              const Vec3* dx2, double k_factor, const DeferredTerms& deferred) {
    const __m256d k = _mm256_set1_pd(k_factor);
    const __m128d sign = _mm_set1_pd(-0.0);
    for (std::size_t i = begin; i < end; ++i) {
        const std::ptrdiff_t a = ends[i][0];  // read once: the stores into df may alias
        const std::ptrdiff_t b = ends[i][1];
        const double* dxa = at(dx1, a);
        const double* dxb = at(dx2, b);
        const __m256d u0 = _mm256_sub_pd(_mm256_broadcast_sd(dxb), _mm256_broadcast_sd(dxa));
        const __m256d u1 = _mm256_sub_pd(_mm256_broadcast_sd(dxb + 1), _mm256_broadcast_sd(dxa + 1));
        const __m256d u2 = _mm256_sub_pd(_mm256_broadcast_sd(dxb + 2), _mm256_broadcast_sd(dxa + 2));
        const auto& m = dfdx[i].column;
        const __m256d m0 = _mm256_load_pd(m[0].data());
        const __m256d m1 = _mm256_load_pd(m[1].data());
        const __m256d m2 = _mm256_load_pd(m[2].data());
        __m256d d;
        if constexpr (Arithmetic == SpringArithmetic::quadular_bending_springs) {
            const __m256d s0 = _mm256_mul_pd(u0, k), s1 = _mm256_mul_pd(u1, k), s2 = _mm256_mul_pd(u2, k);
            d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(m0, s0), _mm256_mul_pd(m1, s1)), _mm256_mul_pd(m2, s2));
        } else {
            d = _mm256_mul_pd(
                _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(m0, u0), _mm256_mul_pd(m1, u1)), _mm256_mul_pd(m2, u2)), k);
        }
        const __m128d d_xy = _mm256_castpd256_pd128(d);
        const __m128d d_z = _mm256_extractf128_pd(d, 1);
        // df_a += d, df_b −= d; where `deferred` marks them, d and −d (the sign flipped) stored
        const unsigned mask = Deferring ? deferred.mask[i] : 0U;
        if (mask & 1U) {
            double* t = deferred.terms[2 * i].data();
            _mm_storeu_pd(t, d_xy);
            _mm_store_sd(t + 2, d_z);
        } else {
            double* fa = at(df1, a);
            _mm_storeu_pd(fa, _mm_add_pd(_mm_loadu_pd(fa), d_xy));
            _mm_store_sd(fa + 2, _mm_add_sd(_mm_load_sd(fa + 2), d_z));
        }
        if (mask & 2U) {
            double* t = deferred.terms[2 * i + 1].data();
            _mm_storeu_pd(t, _mm_xor_pd(d_xy, sign));
            _mm_store_sd(t + 2, _mm_xor_pd(d_z, sign));
        } else {
            double* fb = at(df2, b);
            _mm_storeu_pd(fb, _mm_sub_pd(_mm_loadu_pd(fb), d_xy));
            _mm_store_sd(fb + 2, _mm_sub_sd(_mm_load_sd(fb + 2), d_z));
        }
    }
}
#endif

template <SpringArithmetic Arithmetic, class Stiffness>
void spring_dforce_on(KernelPath path, const Spring* springs, const std::array<std::ptrdiff_t, 2>* ends,
                      const Stiffness* dfdx, std::size_t begin, std::size_t end, Vec3* df1, Vec3* df2, const Vec3* dx1,
                      const Vec3* dx2, double k_factor, const DeferredTerms& deferred) {
    // (the one-thread loop without the deferred mask's tests)
#ifdef PENALTY_HAS_AVX_LANES
    if (path == KernelPath::avx) {
        if (deferred.mask)
            spring_dforce_avx<Arithmetic, true>(ends, dfdx, begin, end, df1, df2, dx1, dx2, k_factor, deferred);
        else spring_dforce_avx<Arithmetic, false>(ends, dfdx, begin, end, df1, df2, dx1, dx2, k_factor, deferred);
        return;
    }
#endif
    (void)path;
    (void)ends;
    if (deferred.mask)
        spring_dforce<Arithmetic, true>(springs, dfdx, begin, end, df1, df2, dx1, dx2, k_factor, deferred);
    else spring_dforce<Arithmetic, false>(springs, dfdx, begin, end, df1, df2, dx1, dx2, k_factor, deferred);
}
}  // namespace

void spring_forces(KernelPath path, SpringArithmetic arithmetic, std::span<const Spring> springs, SpringRange range,
                   double null_length, Vec3* f1, Vec3* f2, const Vec3* x1, const Vec3* x2, const Vec3* v1,
                   const Vec3* v2, SpringStiffnessColumns* dfdx, double& energy) {
    PENALTY_DEMAND(range.first <= range.end && range.end <= springs.size());
    std::size_t done = range.first;
#ifdef PENALTY_HAS_AVX_LANES
    if (path == KernelPath::avx) {
        done = arithmetic == SpringArithmetic::quadular_bending_springs
                   ? spring_force_avx<SpringArithmetic::quadular_bending_springs>(
                         springs.data(), range.first, range.end, null_length, f1, f2, x1, x2, v1, v2, dfdx, energy,
                         range.deferred, range.energies)
                   : spring_force_avx<SpringArithmetic::spring_force_field>(springs.data(), range.first, range.end,
                                                                            null_length, f1, f2, x1, x2, v1, v2, dfdx,
                                                                            energy, range.deferred, range.energies);
    }
#endif
    (void)path;
    spring_force(arithmetic, springs.data(), done, range.end, null_length, f1, f2, x1, x2, v1, v2, dfdx, energy,
                 range.deferred, range.energies);
}

void spring_dforces(KernelPath path, SpringArithmetic arithmetic, std::span<const Spring> springs, SpringRange range,
                    const std::array<std::ptrdiff_t, 2>* ends, const SpringStiffnessColumns* dfdx, Vec3* df1, Vec3* df2,
                    const Vec3* dx1, const Vec3* dx2, double k_factor) {
    PENALTY_DEMAND(range.first <= range.end && range.end <= springs.size());
    if (arithmetic == SpringArithmetic::quadular_bending_springs)
        spring_dforce_on<SpringArithmetic::quadular_bending_springs>(
            path, springs.data(), ends, dfdx, range.first, range.end, df1, df2, dx1, dx2, k_factor, range.deferred);
    else
        spring_dforce_on<SpringArithmetic::spring_force_field>(path, springs.data(), ends, dfdx, range.first, range.end,
                                                               df1, df2, dx1, dx2, k_factor, range.deferred);
}

}  // namespace penalty::detail
