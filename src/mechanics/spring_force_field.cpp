#include "penalty/mechanics/spring_force_field.hpp"

#include <cmath>
#include <set>
#include <utility>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PENALTY_AVX_KERNELS 1
#endif

namespace penalty {

void SpringForceField::add_spring(const Spring& s) {
    if (!std::isfinite(s.ks) || s.ks < 0) throw_invalid_argument("SpringForceField: stiffness must be finite and >= 0, got ", s.ks);
    if (!std::isfinite(s.kd) || s.kd < 0) throw_invalid_argument("SpringForceField: damping must be finite and >= 0, got ", s.kd);
    if (!std::isfinite(s.rest_length) || s.rest_length < 0)
        throw_invalid_argument("SpringForceField: rest length must be finite and >= 0, got ", s.rest_length);
    if (s.a < 0 || s.b < 0) throw_invalid_argument("SpringForceField: negative spring index (", s.a, ", ", s.b, ")");
    springs_.push_back(s);
}

void SpringForceField::init() {
    for (const auto& s : springs_) {
        if (static_cast<std::size_t>(s.a) >= s1_->num_dofs() || static_cast<std::size_t>(s.b) >= s2_->num_dofs()) {
            throw_invalid_argument("SpringForceField: spring (", s.a, ", ", s.b, ") out of range for states of ",
                                   s1_->num_dofs(), " and ", s2_->num_dofs(), " DOFs");
        }
    }
    dfdx_.assign(springs_.size(), StiffnessColumns{});
}

void SpringForceField::set_kernel_path(KernelPath path) {
    if (!kernel_path_supported(path)) throw_invalid_argument("SpringForceField: kernel path ", to_string(path), " is not supported by this CPU");
    kernel_path_ = path;
}

std::vector<BaseState*> SpringForceField::states() const {
    if (s1_ == s2_) return {s1_};
    return {s1_, s2_};
}

void SpringForceField::add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                                 ConstVec3Span v2) {
    dfdx_.resize(springs_.size());
    energy_ = 0.0;
    for (std::size_t i = 0; i < springs_.size(); ++i) {
        const Spring& s = springs_[i];
        const auto a = static_cast<std::size_t>(s.a);
        const auto b = static_cast<std::size_t>(s.b);
        // SOFA's SpringForceField::computeSpringForce, operation by operation (the rounding of
        // every step is SOFA's): u = x_b − x_a, d = |u|, U = u·(1/d), elongation e = d − l0,
        // intensity f = ks·e + kd·(U·(v_b − v_a)), force f·U, dF/dX = (ks − f/d)·U·Uᵀ + f/d·I with
        // f/d computed as f·(1/d) and each entry ((ks − t)·U_j)·U_k.
        const Vec3 u = x2[b] - x1[a];
        const double d = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (d <= null_length_) {
            dfdx_[i] = StiffnessColumns{};
            continue;
        }
        const double inverse_length = 1.0 / d;
        const Vec3 n(u[0] * inverse_length, u[1] * inverse_length, u[2] * inverse_length);
        const double elongation = d - s.rest_length;
        energy_ += elongation * elongation * s.ks / 2;
        const Vec3 relative_velocity = v2[b] - v1[a];
        const double elongation_velocity = n[0] * relative_velocity[0] + n[1] * relative_velocity[1] + n[2] * relative_velocity[2];
        const double intensity = s.ks * elongation + s.kd * elongation_velocity;
        const Vec3 force(n[0] * intensity, n[1] * intensity, n[2] * intensity);
        f1[a] += force;
        f2[b] -= force;
        const double t = intensity * inverse_length;
        auto& m = dfdx_[i].column;  // m(j, k) is m[k][j]
        if (arithmetic_ == SpringArithmetic::quadular_bending_springs) {
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

namespace {
/// df1[a] += d, df2[b] −= d for each spring in order, d = SOFA's computeSpringDForce of
/// `Arithmetic` (see SpringArithmetic). The loop reads raw pointers held in locals, so that the
/// stores into df do not force the compiler to reload the spring list's bounds per spring; each
/// floating-point operation and its order are those of the straightforward loop.
template <SpringArithmetic Arithmetic, class Stiffness>
void spring_dforce(const Spring* springs, const Stiffness* dfdx, std::size_t count, Vec3* df1, Vec3* df2, const Vec3* dx1,
                   const Vec3* dx2, double k_factor) {
    for (std::size_t i = 0; i < count; ++i) {
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
        df1[a] += d;
        df2[b] -= d;
    }
}

#ifdef PENALTY_AVX_KERNELS
/// The same product with the three rows of m·dx in the lanes 0–2 of 256-bit registers (lane 3
/// computes 0·dx and is dropped): lane r does row r's operations of spring_dforce, in its order,
/// each an IEEE operation of the same operands, so every bit is the scalar loop's. The
/// differences dx_b − dx_a are formed in every lane (broadcast operands); df is updated spring by
/// spring in spring order (x and y in one 128-bit add, z alone).
template <SpringArithmetic Arithmetic, class Stiffness>
[[gnu::target("avx")]] void spring_dforce_avx(const Spring* springs, const Stiffness* dfdx, std::size_t count, Vec3* df1,
                                              Vec3* df2, const Vec3* dx1, const Vec3* dx2, double k_factor) {
    const __m256d k = _mm256_set1_pd(k_factor);
    for (std::size_t i = 0; i < count; ++i) {
        const auto a = static_cast<std::size_t>(springs[i].a);  // read once: the stores into df may alias
        const auto b = static_cast<std::size_t>(springs[i].b);
        const double* dxa = dx1[a].data();
        const double* dxb = dx2[b].data();
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
            d = _mm256_mul_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(m0, u0), _mm256_mul_pd(m1, u1)), _mm256_mul_pd(m2, u2)), k);
        }
        const __m128d d_xy = _mm256_castpd256_pd128(d);
        const __m128d d_z = _mm256_extractf128_pd(d, 1);
        double* fa = df1[a].data();
        _mm_storeu_pd(fa, _mm_add_pd(_mm_loadu_pd(fa), d_xy));
        _mm_store_sd(fa + 2, _mm_add_sd(_mm_load_sd(fa + 2), d_z));
        double* fb = df2[b].data();
        _mm_storeu_pd(fb, _mm_sub_pd(_mm_loadu_pd(fb), d_xy));
        _mm_store_sd(fb + 2, _mm_sub_sd(_mm_load_sd(fb + 2), d_z));
    }
}
#endif

template <SpringArithmetic Arithmetic, class Stiffness>
void spring_dforce_on(KernelPath path, const Spring* springs, const Stiffness* dfdx, std::size_t count, Vec3* df1,
                      Vec3* df2, const Vec3* dx1, const Vec3* dx2, double k_factor) {
#ifdef PENALTY_AVX_KERNELS
    if (path == KernelPath::avx) {
        spring_dforce_avx<Arithmetic>(springs, dfdx, count, df1, df2, dx1, dx2, k_factor);
        return;
    }
#endif
    (void)path;
    spring_dforce<Arithmetic>(springs, dfdx, count, df1, df2, dx1, dx2, k_factor);
}
}  // namespace

void SpringForceField::add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                                  double /*b_factor*/) const {
    PENALTY_DEMAND(dfdx_.size() == springs_.size());
    if (arithmetic_ == SpringArithmetic::quadular_bending_springs)
        spring_dforce_on<SpringArithmetic::quadular_bending_springs>(kernel_path_, springs_.data(), dfdx_.data(), springs_.size(),
                                                                     df1.data(), df2.data(), dx1.data(), dx2.data(), k_factor);
    else
        spring_dforce_on<SpringArithmetic::spring_force_field>(kernel_path_, springs_.data(), dfdx_.data(), springs_.size(),
                                                               df1.data(), df2.data(), dx1.data(), dx2.data(), k_factor);
}

void SpringForceField::add_stiffness_triplets(TripletList& t, Index o1, Index o2, double factor) const {
    PENALTY_DEMAND(dfdx_.size() == springs_.size());
    for (std::size_t i = 0; i < springs_.size(); ++i) {
        const Index ra = o1 + 3 * springs_[i].a;
        const Index rb = o2 + 3 * springs_[i].b;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                const double v = factor * dfdx_[i](r, c);
                t.emplace_back(ra + r, ra + c, -v);
                t.emplace_back(ra + r, rb + c, v);
                t.emplace_back(rb + r, ra + c, v);
                t.emplace_back(rb + r, rb + c, -v);
            }
    }
}

MeshSpringParameters MeshSpringParameters::uniform(double k, double d) {
    MeshSpringParameters p;
    p.lines_stiffness = p.triangles_stiffness = p.quads_stiffness = p.tetras_stiffness = p.cubes_stiffness = k;
    p.lines_damping = p.triangles_damping = p.quads_damping = p.tetras_damping = p.cubes_damping = d;
    return p;
}

namespace {
template <class Element>
void add_element_springs(const std::vector<Element>& elements, double ks, double kd, std::span<const Vec3> x0,
                         std::set<std::pair<PointId, PointId>>& seen, std::vector<Spring>& out) {
    if (ks == 0.0 && kd == 0.0) return;
    if (!std::isfinite(ks) || ks < 0 || !std::isfinite(kd) || kd < 0)
        throw_invalid_argument("MeshSpringForceField: stiffness and damping must be finite and >= 0, got ", ks, ", ", kd);
    const std::size_t n = std::tuple_size<Element>::value;
    for (const auto& e : elements) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j) {
                const PointId a = e[i], b = e[j];
                const auto key = a < b ? std::make_pair(a, b) : std::make_pair(b, a);
                if (!seen.insert(key).second) continue;
                if (static_cast<std::size_t>(std::max(a, b)) >= x0.size())
                    throw_invalid_argument("MeshSpringForceField: vertex ", std::max(a, b), " has no rest position");
                const double l = (x0[static_cast<std::size_t>(b)] - x0[static_cast<std::size_t>(a)]).norm();
                if (!(l > 0.0)) throw_invalid_argument("MeshSpringForceField: zero rest length between vertices ", a, " and ", b);
                out.push_back(Spring{a, b, ks / l, kd / l, l});
            }
    }
}
}  // namespace

std::vector<Spring> mesh_springs(const MeshTopology& topo, std::span<const Vec3> x0, const MeshSpringParameters& p) {
    std::vector<Spring> out;
    std::set<std::pair<PointId, PointId>> seen;
    add_element_springs(topo.edges(), p.lines_stiffness, p.lines_damping, x0, seen, out);
    add_element_springs(topo.triangles(), p.triangles_stiffness, p.triangles_damping, x0, seen, out);
    add_element_springs(topo.quads(), p.quads_stiffness, p.quads_damping, x0, seen, out);
    add_element_springs(topo.tetrahedra(), p.tetras_stiffness, p.tetras_damping, x0, seen, out);
    add_element_springs(topo.hexahedra(), p.cubes_stiffness, p.cubes_damping, x0, seen, out);
    return out;
}

}  // namespace penalty
