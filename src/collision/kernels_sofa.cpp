// NewProximity, MinProximity and Discrete element intersectors (spec §5.3–5.5).
#include "kernels.hpp"

#include "penalty/geometry/segment_triangle.hpp"

#include <limits>

namespace penalty::detail {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// ---------------------------------------------------------------------------------------------
// NewProximity helpers. Every helper tests |d|² < R² (strict) and returns the number of outputs;
// `value` is the raw distance minus `cfull`.

// NP-PP: point p (element 1 side) vs point q (element 2 side)
int np_pp(PairCtx& c, const Vec3& p, const Vec3& q, double R, double cfull, std::int64_t id) {
    const Vec3 d = q - p;
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    if (!unit_normal(c, d, len, Guard::None, n)) return 0;
    return push(c, id, p, q, n, len - cfull);
}

// NP-LP: segment [a, b] vs point q, clamped projection; swap: the point is element 1.
// Zero-length segment: no contact (SOFA computes t = 0/0 and emits NaN, see differences doc).
int np_lp(PairCtx& c, const Vec3& a, const Vec3& b, const Vec3& q, double R, double cfull,
          std::int64_t id, bool swap) {
    const Vec3 ab = b - a;
    const double A = ab.squaredNorm();
    if (!(A > 0.0)) return 0;
    double alpha = (q - a).dot(ab) / A;
    if (alpha < 0.0) alpha = 0.0;
    else if (alpha > 1.0) alpha = 1.0;
    const Vec3 p = a + ab * alpha;
    const Vec3 pq = q - p;
    const double n2 = pq.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    if (!unit_normal(c, swap ? Vec3(-pq) : pq, len, Guard::None, n)) return 0;
    return swap ? push(c, id, q, p, n, len - cfull) : push(c, id, p, q, n, len - cfull);
}

// NP-LL: segment [p1, p2] vs segment [q1, q2] (interior closest points only unless parallel)
int np_ll(PairCtx& c, const Vec3& p1, const Vec3& p2, const Vec3& q1, const Vec3& q2, double R,
          double cfull, std::int64_t id, double det_threshold, double lo, double hi, Guard g) {
    const Vec3 ab = p2 - p1;
    const Vec3 cd = q2 - q1;
    const Vec3 ac = q1 - p1;
    const double a00 = ab.dot(ab);
    const double a11 = cd.dot(cd);
    const double a01 = -cd.dot(ab);
    const double b0 = ab.dot(ac);
    const double b1 = -cd.dot(ac);
    const double det = a00 * a11 - a01 * a01;
    double alpha = 0.5;
    double beta = 0.5;
    if (det < -det_threshold || det > det_threshold) {
        alpha = (b0 * a11 - b1 * a01) / det;
        beta = (b1 * a00 - b0 * a01) / det;
        if (alpha < lo || alpha > hi || beta < lo || beta > hi) return 0;
    }
    const Vec3 p = p1 + ab * alpha;
    const Vec3 q = q1 + cd * beta;
    const Vec3 pq = q - p;
    const double n2 = pq.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    if (!unit_normal(c, pq, len, g, n)) return 0;
    return push(c, id, p, q, n, len - cfull);
}

/// Gram system of point q against triangle (p1, p2, p3): α, β with q ≈ p1 + α AB + β AC.
struct Gram {
    Vec3 ab, ac;
    double g00, g01, g11, b0, b1, det, alpha, beta;
    bool degenerate;
};
Gram gram(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& q) {
    Gram g;
    g.ab = p2 - p1;
    g.ac = p3 - p1;
    const Vec3 aq = q - p1;
    g.g00 = g.ab.dot(g.ab);
    g.g11 = g.ac.dot(g.ac);
    g.g01 = g.ab.dot(g.ac);
    g.b0 = aq.dot(g.ab);
    g.b1 = aq.dot(g.ac);
    g.det = g.g00 * g.g11 - g.g01 * g.g01;
    // zero-area triangle: SOFA divides by det = 0 (NaN/inf); we report no contact
    g.degenerate = !(g.det > 0.0) || !(g.g00 > 0.0) || !(g.g11 > 0.0) ||
                   !(g.g00 + g.g11 - 2.0 * g.g01 > 0.0);
    g.alpha = g.degenerate ? 0.0 : (g.b0 * g.g11 - g.b1 * g.g01) / g.det;
    g.beta = g.degenerate ? 0.0 : (g.b1 * g.g00 - g.b0 * g.g01) / g.det;
    return g;
}

// NP-TP (ε = machine epsilon, flag checks on vertex/edge regions)
int np_tp(PairCtx& c, const Vec3& p1, const Vec3& p2, const Vec3& p3, std::uint32_t flags,
          const Vec3& q, double R, double cfull, std::int64_t id, bool swap) {
    using F = TriangleModel::Flags;
    const Gram g = gram(p1, p2, p3, q);
    if (g.degenerate) return 0;
    double alpha = g.alpha;
    double beta = g.beta;
    if (alpha < kEps || beta < kEps || alpha + beta > 1.0 - kEps) {
        const double pAB = g.b0 / g.g00;
        const double pAC = g.b1 / g.g11;
        if (pAB < kEps && pAC < kEps) {
            if (!(flags & F::kP1)) return 0;
            alpha = 0.0;
            beta = 0.0;
        } else if (pAB < 1.0 - kEps && pAB >= kEps && beta < kEps) {
            if (!(flags & F::kE12)) return 0;
            alpha = pAB;
            beta = 0.0;
        } else if (pAC < 1.0 - kEps && pAC >= kEps && alpha < kEps) {
            if (!(flags & F::kE31)) return 0;
            alpha = 0.0;
            beta = pAC;
        } else {
            const double pBC = (g.b1 - g.b0 + g.g00 - g.g01) / (g.g00 + g.g11 - 2.0 * g.g01);
            if (pBC < kEps) {
                if (!(flags & F::kP2)) return 0;
                alpha = 1.0;
                beta = 0.0;
            } else if (pBC > 1.0 - kEps) {
                if (!(flags & F::kP3)) return 0;
                alpha = 0.0;
                beta = 1.0;
            } else {
                if (!(flags & F::kE23)) return 0;
                alpha = 1.0 - pBC;
                beta = pBC;
            }
        }
    }
    const Vec3 p = p1 + g.ab * alpha + g.ac * beta;
    const Vec3 pq = q - p;
    const double n2 = pq.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    if (!unit_normal(c, swap ? Vec3(-pq) : pq, len, Guard::None, n)) return 0;
    return swap ? push(c, id, q, p, n, len - cfull) : push(c, id, p, q, n, len - cfull);
}

// SOFA's strict-interior triangle test (MinProximity, LocalMinDistance): thresholds 1e-6.
bool interior_projection(const Gram& g) {
    return !g.degenerate && !(g.alpha < 1e-6 || g.beta < 1e-6 || g.alpha + g.beta > 0.999999);
}

}  // namespace

// =============================================================================================
// NewProximity
int np_sphere_sphere(PairCtx& c) {
    const SphereElem s1 = sphere_elem(c.m1, c.e1);
    const SphereElem s2 = sphere_elem(c.m2, c.e2);
    const double sk = skins(c);
    return np_pp(c, s1.c, s2.c, c.p.alarm_distance + sk + s1.r + s2.r,
                 c.p.contact_distance + sk + s1.r + s2.r, id_big(c));
}

int np_sphere_point(PairCtx& c) {
    const SphereElem s = sphere_elem(c.m1, c.e1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    return np_pp(c, s.c, q, c.p.alarm_distance + sk + s.r, c.p.contact_distance + sk + s.r, id_big(c));
}

int np_point_point(PairCtx& c) {
    const Vec3& p = static_cast<const PointModel&>(c.m1).point(c.e1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    return np_pp(c, p, q, c.p.alarm_distance + sk, c.p.contact_distance + sk, id_big(c));
}

int np_line_point(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    return np_lp(c, l.p1(c.e1), l.p2(c.e1), q, c.p.alarm_distance + sk, c.p.contact_distance + sk, c.e2, false);
}

int np_line_line(PairCtx& c) {
    const auto& l1 = static_cast<const LineModel&>(c.m1);
    const auto& l2 = static_cast<const LineModel&>(c.m2);
    const double sk = skins(c);
    return np_ll(c, l1.p1(c.e1), l1.p2(c.e1), l2.p1(c.e2), l2.p2(c.e2), c.p.alarm_distance + sk,
                 c.p.contact_distance + sk, id_big(c), 1e-12, 1e-6, 0.999999, Guard::None);
}

int np_line_sphere(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const double sk = skins(c);
    return np_lp(c, l.p1(c.e1), l.p2(c.e1), s.c, c.p.alarm_distance + sk + s.r,
                 c.p.contact_distance + sk + s.r, c.e2, false);
}

int np_triangle_point(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    return np_tp(c, t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), t.flags(c.e1), q,
                 c.p.alarm_distance + sk, c.p.contact_distance + sk, c.e2, false);
}

int np_triangle_sphere(PairCtx& c) {
    using F = TriangleModel::Flags;
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const std::uint32_t flags = t.flags(c.e1);
    const bool fix = c.p.quirks.fix_newproximity_triangle_sphere_edge_flags;
    const bool fix_range = c.p.quirks.fix_newproximity_triangle_sphere_edge_range;
    const double lo = fix_range ? 1e-6 : -std::numeric_limits<double>::infinity();
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk + s.r;
    const Vec3& p1 = t.p(c.e1, 0);
    const Gram g = gram(p1, t.p(c.e1, 1), t.p(c.e1, 2), s.c);
    if (g.degenerate) return 0;
    double alpha = g.alpha;
    double beta = g.beta;
    // this routine's own thresholds (1e-6 / 0.999999, and 1e-7 for pAC at vertex A)
    if (alpha < 1e-6 || beta < 1e-6 || alpha + beta > 0.999999) {
        const double pAB = g.b0 / g.g00;
        const double pAC = g.b1 / g.g11;
        if (pAB < 1e-6 && pAC < (fix_range ? 1e-6 : 1e-7)) {
            if (!(flags & F::kP1)) return 0;
            alpha = 0.0;
            beta = 0.0;
        } else if (pAB < 0.999999 && pAB >= lo && beta < 1e-6) {
            if (!(flags & F::kE12)) return 0;
            alpha = pAB;
            beta = 0.0;
        } else if (pAC < 0.999999 && pAC >= lo && alpha < 1e-6) {
            // SOFA checks FLAG_E12 here (§14.2)
            if (!(flags & (fix ? F::kE31 : F::kE12))) return 0;
            alpha = 0.0;
            beta = pAC;
        } else {
            const double pBC = (g.b1 - g.b0 + g.g00 - g.g01) / (g.g00 + g.g11 - 2.0 * g.g01);
            if (pBC < 1e-6) {
                if (!(flags & F::kP2)) return 0;
                alpha = 1.0;
                beta = 0.0;
            } else if (pBC > 0.999999) {
                if (!(flags & F::kP3)) return 0;
                alpha = 0.0;
                beta = 1.0;
            } else {
                // SOFA checks FLAG_E31 here (§14.2)
                if (!(flags & (fix ? F::kE23 : F::kE31))) return 0;
                alpha = 1.0 - pBC;
                beta = pBC;
            }
        }
    }
    const Vec3 p = p1 + g.ab * alpha + g.ac * beta;
    const Vec3 pq = s.c - p;
    const double n2 = pq.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    unit_normal(c, pq, len, Guard::Sofa, n);
    return push(c, c.e2, p, s.point_by_normal(n), n, len - (c.p.contact_distance + sk + s.r));
}

int np_triangle_line(PairCtx& c) {
    using F = TriangleModel::Flags;
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const auto& l = static_cast<const LineModel&>(c.m2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const double cf = c.p.contact_distance + sk;
    const Vec3& p1 = t.p(c.e1, 0);
    const Vec3& p2 = t.p(c.e1, 1);
    const Vec3& p3 = t.p(c.e1, 2);
    const Vec3& q1 = l.p1(c.e2);
    const Vec3& q2 = l.p2(c.e2);
    const std::uint32_t f = t.flags(c.e1);
    const std::int64_t id = c.e2;
    int n = 0;
    // owned triangle vertices vs the line (vertex is point[0])
    if (f & F::kP1) n += np_lp(c, q1, q2, p1, R, cf, id, true);
    if (f & F::kP2) n += np_lp(c, q1, q2, p2, R, cf, id, true);
    if (f & F::kP3) n += np_lp(c, q1, q2, p3, R, cf, id, true);
    // line end points vs the triangle (no flag check on the line side)
    n += np_tp(c, p1, p2, p3, f, q1, R, cf, id, false);
    n += np_tp(c, p1, p2, p3, f, q2, R, cf, id, false);
    if (c.p.use_line_line) {
        if (f & F::kE12) n += np_ll(c, p1, p2, q1, q2, R, cf, id, 1e-12, 1e-6, 0.999999, Guard::None);
        if (f & F::kE23) n += np_ll(c, p2, p3, q1, q2, R, cf, id, 1e-12, 1e-6, 0.999999, Guard::None);
        if (f & F::kE31) n += np_ll(c, p3, p1, q1, q2, R, cf, id, 1e-12, 1e-6, 0.999999, Guard::None);
    }
    return n;
}

int np_triangle_triangle(PairCtx& c) {
    using F = TriangleModel::Flags;
    auto& t1 = static_cast<TriangleModel&>(c.m1);
    auto& t2 = static_cast<TriangleModel&>(c.m2);
    const Triangle& a = t1.triangle(c.e1);
    const Triangle& b = t2.triangle(c.e2);
    if (&t1 == &t2) {
        for (auto i : a)
            for (auto j : b)
                if (i == j) return 0;  // neighbours in the same model
    }
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const double cf = c.p.contact_distance + sk;
    const Vec3 &p1 = t1.p(c.e1, 0), &p2 = t1.p(c.e1, 1), &p3 = t1.p(c.e1, 2);
    const Vec3 &q1 = t2.p(c.e2, 0), &q2 = t2.p(c.e2, 1), &q3 = t2.p(c.e2, 2);
    const std::uint32_t f1 = t1.flags(c.e1);
    const std::uint32_t f2 = t2.flags(c.e2);
    const std::int64_t id1 = std::int64_t(c.e1) * 3;
    const std::int64_t id2 = std::int64_t(t1.size()) * 3 + std::int64_t(c.e2) * 12;

    // §14.4: SOFA overwrites the stored normals according to bothSide
    if (!c.p.quirks.fix_newproximity_triangle_triangle_normal_overwrite) {
        const bool both1 = t1.params().both_side;
        const bool both2 = t2.params().both_side;
        if (!(both1 && both2)) {
            if (!both1) t2.set_normal(c.e2, -t1.normal(c.e1));
            else t1.set_normal(c.e1, -t2.normal(c.e2));
        }
    }

    int n = 0;
    // vertices of e1 against e2 (vertex is point[0]); §14.3: vertex 1 without its flag
    const bool v1 = !c.p.quirks.fix_newproximity_triangle_triangle_vertex1_flag || (f1 & F::kP1);
    if (v1) n += np_tp(c, q1, q2, q3, f2, p1, R, cf, id1 + 0, true);
    if (f1 & F::kP2) n += np_tp(c, q1, q2, q3, f2, p2, R, cf, id1 + 1, true);
    if (f1 & F::kP3) n += np_tp(c, q1, q2, q3, f2, p3, R, cf, id1 + 2, true);
    // owned vertices of e2 against e1
    if (f2 & F::kP1) n += np_tp(c, p1, p2, p3, f1, q1, R, cf, id2 + 0, false);
    if (f2 & F::kP2) n += np_tp(c, p1, p2, p3, f1, q2, R, cf, id2 + 1, false);
    if (f2 & F::kP3) n += np_tp(c, p1, p2, p3, f1, q3, R, cf, id2 + 2, false);
    if (c.p.use_line_line) {
        const std::uint32_t e[3] = {F::kE12, F::kE23, F::kE31};
        const Vec3* pa[3][2] = {{&p1, &p2}, {&p2, &p3}, {&p3, &p1}};
        const Vec3* qa[3][2] = {{&q1, &q2}, {&q2, &q3}, {&q3, &q1}};
        for (int i = 0; i < 3; ++i) {
            if (!(f1 & e[i])) continue;
            for (int j = 0; j < 3; ++j) {
                if (!(f2 & e[j])) continue;
                n += np_ll(c, *pa[i][0], *pa[i][1], *qa[j][0], *qa[j][1], R, cf, id2 + 3 + 3 * i + j,
                           1e-12, 1e-6, 0.999999, Guard::None);
            }
        }
    }
    return n;
}

// =============================================================================================
// Sphere–sphere routine shared by Discrete, MinProximity and LocalMinDistance (rigid pairs):
// no contact iff |d|² > (Aeff + r1 + r2)² (equality accepted); surface points for rigid spheres.
namespace {
int sphere_sphere_sofa(PairCtx& c, double aeff, double ceff) {
    const SphereElem s1 = sphere_elem(c.m1, c.e1);
    const SphereElem s2 = sphere_elem(c.m2, c.e2);
    const double r = s1.r + s2.r;
    const Vec3 d = s2.c - s1.c;
    const double n2 = d.squaredNorm();
    if (n2 > (aeff + r) * (aeff + r)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    if (!unit_normal(c, d, len, Guard::None, n)) return 0;
    return push(c, id_big(c), s1.point_by_normal(-n), s2.point_by_normal(n), n, len - r - ceff);
}
}  // namespace

int discrete_sphere_sphere(PairCtx& c) { return sphere_sphere_sofa(c, c.p.alarm_distance, c.p.contact_distance); }

int lmd_rigid_sphere_pair(PairCtx& c) { return sphere_sphere_sofa(c, c.p.alarm_distance, c.p.contact_distance); }

int discrete_triangle_line(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const auto& l = static_cast<const LineModel&>(c.m2);
    const auto x = segment_triangle_crossing(t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), l.p1(c.e2), l.p2(c.e2));
    if (!x) return 0;
    return push(c, c.e2, x->point, x->point, t.normal(c.e1), 0.0);
}

// =============================================================================================
// MinProximity
int min_sphere_sphere(PairCtx& c) {
    const double sk = skins(c);
    return sphere_sphere_sofa(c, c.p.alarm_distance + sk, c.p.contact_distance + sk);
}

int min_sphere_point(PairCtx& c) {
    const SphereElem s = sphere_elem(c.m1, c.e1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + s.r + sk;
    const Vec3 d = q - s.c;
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    unit_normal(c, d, len, Guard::Sofa, n);
    return push(c, c.e1, s.point_by_normal(-n), q, n, len - (c.p.contact_distance + s.r + sk));
}

int min_point_point(PairCtx& c) {
    const Vec3& p = static_cast<const PointModel&>(c.m1).point(c.e1);
    const Vec3& q = static_cast<const PointModel&>(c.m2).point(c.e2);
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 d = q - p;
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    unit_normal(c, d, len, Guard::Sofa, n);
    return push(c, id_big(c), p, q, n, len - (c.p.contact_distance + sk));
}

int min_line_point(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const Vec3& P = static_cast<const PointModel&>(c.m2).point(c.e2);
    const Vec3& a = l.p1(c.e1);
    const Vec3 ab = l.p2(c.e1) - a;
    const double A = ab.squaredNorm();
    if (!(A > 0.0)) return 0;  // SOFA: t = NaN, no contact
    const double t = (P - a).dot(ab) / A;
    const Vec3 Q = t <= 0.0 ? a : (t >= 1.0 ? Vec3(l.p2(c.e1)) : Vec3(a + t * ab));
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 d = P - Q;
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    unit_normal(c, d, len, Guard::Sofa, n);
    return push(c, c.e2, Q, P, n, len - (c.p.contact_distance + sk));
}

int min_line_line(PairCtx& c) {
    const auto& l1 = static_cast<const LineModel&>(c.m1);
    const auto& l2 = static_cast<const LineModel&>(c.m2);
    const double sk = skins(c);
    return np_ll(c, l1.p1(c.e1), l1.p2(c.e1), l2.p1(c.e2), l2.p2(c.e2), c.p.alarm_distance + sk,
                 c.p.contact_distance + sk, id_big(c), 1e-15, 1e-6, 0.999999, Guard::Sofa);
}

int min_line_sphere(PairCtx& c) {
    const auto& l = static_cast<const LineModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const Vec3& p1 = l.p1(c.e1);
    const Vec3& p2 = l.p2(c.e1);
    const Vec3 ba = p1 - p2;
    const double A = ba.squaredNorm();
    if (!(A > 0.0)) return 0;
    // t measured from p2 toward p1
    const double t = ba.dot(s.c - p2) / A;
    if (t < 1e-6 || t > 0.999999) return 0;
    // §14.1: SOFA applies t from p1 toward p2 (mirror about the midpoint)
    const Vec3 Q = c.p.quirks.fix_minproximity_line_sphere_mirror ? Vec3(p2 + t * ba) : Vec3(p1 + t * (p2 - p1));
    const double sk = skins(c);
    const double R = c.p.alarm_distance + s.r + sk;
    const Vec3 d = s.c - Q;
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    unit_normal(c, d, len, Guard::Sofa, n);
    return push(c, c.e2, Q, s.point_by_normal(n), n, len - (c.p.contact_distance + s.r + sk));
}

int min_triangle_point(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const Vec3& P = static_cast<const PointModel&>(c.m2).point(c.e2);
    const Gram g = gram(t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), P);
    if (!interior_projection(g)) return 0;
    const Vec3 Q = t.p(c.e1, 0) + g.alpha * g.ab + g.beta * g.ac;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + sk;
    const Vec3 d = P - Q;
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    unit_normal(c, d, len, Guard::Sofa, n);
    if (c.p.use_surface_normals) n = t.normal(c.e1);
    return push(c, c.e2, Q, P, n, len - (c.p.contact_distance + sk));
}

int min_triangle_sphere(PairCtx& c) {
    const auto& t = static_cast<const TriangleModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const Gram g = gram(t.p(c.e1, 0), t.p(c.e1, 1), t.p(c.e1, 2), s.c);
    if (!interior_projection(g)) return 0;
    const Vec3 Q = t.p(c.e1, 0) + g.alpha * g.ab + g.beta * g.ac;
    const double sk = skins(c);
    const double R = c.p.alarm_distance + s.r + sk;
    const Vec3 d = s.c - Q;
    const double n2 = d.squaredNorm();
    if (!(n2 < R * R)) return 0;
    const double len = std::sqrt(n2);
    Vec3 n;
    unit_normal(c, d, len, Guard::Sofa, n);
    return push(c, c.e2, Q, s.point_by_normal(n), n, len - (c.p.contact_distance + s.r + sk));
}

}  // namespace penalty::detail
