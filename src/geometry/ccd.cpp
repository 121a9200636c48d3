#include "penalty/geometry/ccd.hpp"

#include "penalty/geometry/point_triangle.hpp"
#include "penalty/geometry/segment_segment.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace penalty {

double point_triangle_distance(const Vec3& p, const Vec3& t1, const Vec3& t2, const Vec3& t3) {
    return std::sqrt(point_triangle_closest_point(p, t1, t2, t3).distance_squared);
}

double edge_edge_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return std::sqrt(segment_segment_closest_points(a, b, c, d).distance_squared);
}

namespace {

double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)); }

/// f(t) = det(A(t), B(t), C(t)) for A, B, C linear in t: its coefficients (t⁰ … t³), exact
/// expansion of the trilinear determinant.
std::array<double, 4> cubic_of(const Vec3& a0, const Vec3& da, const Vec3& b0, const Vec3& db, const Vec3& c0,
                               const Vec3& dc) {
    return {det3(a0, b0, c0), det3(da, b0, c0) + det3(a0, db, c0) + det3(a0, b0, dc),
            det3(da, db, c0) + det3(da, b0, dc) + det3(a0, db, dc), det3(da, db, dc)};
}

double eval_cubic(const std::array<double, 4>& k, double t) { return ((k[3] * t + k[2]) * t + k[1]) * t + k[0]; }

/// The first t in [from, 1] at which the features are coplanar (f(t) = 0, a sign change of the
/// cubic f) and `touching(t)`; the root's lower bracket (f still of its sign there) is returned,
/// −1 when there is none. Between the critical points of f (the roots of f′) the cubic is
/// monotone, so each piece holds at most one root, found by bisection.
template <class Touching>
double first_coplanar_touch(const std::array<double, 4>& k, double from, const Touching& touching) {
    std::array<double, 4> cuts{from, 1.0, 1.0, 1.0};
    int n = 1;
    // f′(t) = 3·k3·t² + 2·k2·t + k1
    const double qa = 3.0 * k[3], qb = 2.0 * k[2], qc = k[1];
    const auto add_cut = [&](double t) {
        if (t > from && t < 1.0) cuts[std::size_t(n++)] = t;
    };
    if (qa != 0.0) {
        const double disc = qb * qb - 4.0 * qa * qc;
        if (disc > 0.0) {
            const double r = std::sqrt(disc);
            const double q = -0.5 * (qb + (qb >= 0 ? r : -r));
            add_cut(q / qa);
            if (q != 0.0) add_cut(qc / q);
        }
    } else if (qb != 0.0) {
        add_cut(-qc / qb);
    }
    if (n == 3 && cuts[2] < cuts[1]) std::swap(cuts[1], cuts[2]);  // at most two critical points
    cuts[std::size_t(n)] = 1.0;
    for (int i = 0; i < n; ++i) {
        double lo = cuts[std::size_t(i)], hi = cuts[std::size_t(i) + 1];
        const double flo = eval_cubic(k, lo), fhi = eval_cubic(k, hi);
        if ((flo > 0.0 && fhi > 0.0) || (flo < 0.0 && fhi < 0.0)) continue;
        if (flo == 0.0) {
            if (touching(lo)) return lo;
            continue;
        }
        for (int it = 0; it < 100 && hi - lo > 0.0; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (mid <= lo || mid >= hi) break;
            const double fm = eval_cubic(k, mid);
            if ((fm > 0.0) == (flo > 0.0) && fm != 0.0) lo = mid;
            else hi = mid;
        }
        if (touching(lo) || touching(hi)) return lo;
    }
    return -1.0;
}

/// Additive conservative advancement of four moving vertices, the first `first_count` one
/// feature and the rest the other (point–triangle: 1 + 3, edge–edge: 2 + 2). `distance(x)` is
/// the pair's distance at the positions x; `coplanarity` the cubic whose roots are the times the
/// four points are coplanar (a touch needs one).
template <class Distance>
CcdResult advance(const std::array<Vec3, 4>& x0, const std::array<Vec3, 4>& x1, int first_count, double scale,
                  const CcdOptions& o, const Distance& distance, const std::array<double, 4>& coplanarity) {
    // displacements without their common translation (which changes no distance)
    std::array<Vec3, 4> delta;
    Vec3 mean = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
        delta[std::size_t(i)] = x1[std::size_t(i)] - x0[std::size_t(i)];
        mean += delta[std::size_t(i)];
    }
    mean *= 0.25;
    double first_max = 0.0, second_max = 0.0;
    for (int i = 0; i < 4; ++i) {
        delta[std::size_t(i)] -= mean;
        double& feature_max = i < first_count ? first_max : second_max;
        feature_max = std::max(feature_max, delta[std::size_t(i)].norm());
    }
    const double lp = first_max + second_max;  // bound on |d distance / dt|
    const double eps = o.touch_tolerance * (scale + lp);
    CcdResult r;
    std::array<Vec3, 4> x = x0;
    double d = distance(x);
    double t = 0.0;
    if (d <= eps) {
        r.hit = true;
        r.toi = 0.0;
        r.distance = d;
        return r;
    }
    if (!(lp > 0.0)) {  // no relative motion (or NaN: then no claim either way)
        r.distance = d;
        return r;
    }
    while (true) {
        const double step = o.advance_fraction * d / lp;
        if (t + step >= 1.0) {  // the rest of the motion cannot close the distance
            for (int i = 0; i < 4; ++i) x[std::size_t(i)] = x1[std::size_t(i)];
            r.distance = distance(x);
            r.toi = 1.0;
            return r;
        }
        t += step;
        // positions at t from the start (not accumulated: no drift)
        for (int i = 0; i < 4; ++i)
            x[std::size_t(i)] = x0[std::size_t(i)] + t * (x1[std::size_t(i)] - x0[std::size_t(i)]);
        d = distance(x);
        ++r.iterations;
        if (d <= eps) {
            r.hit = true;
            r.toi = t;
            r.distance = d;
            return r;
        }
        if (r.iterations >= o.max_iterations) break;
    }
    // A slow approach (or a graze, the features gliding past each other closer than the motion):
    // the rest of the motion by the coplanarity roots, at which the distance must fall to ε.
    const auto at = [&](double u) {
        std::array<Vec3, 4> y;
        for (int i = 0; i < 4; ++i)
            y[std::size_t(i)] = x0[std::size_t(i)] + u * (x1[std::size_t(i)] - x0[std::size_t(i)]);
        return y;
    };
    const double scale_cubed = std::pow(scale + lp, 3.0);
    const bool degenerate =
        std::abs(coplanarity[0]) + std::abs(coplanarity[1]) + std::abs(coplanarity[2]) + std::abs(coplanarity[3]) <=
        1e-14 * scale_cubed;
    if (degenerate) {  // coplanar throughout: no root tells; conservative
        r.hit = r.capped = true;
        r.toi = t;
        r.distance = d;
        return r;
    }
    const double root = first_coplanar_touch(coplanarity, t, [&](double u) { return distance(at(u)) <= eps; });
    if (root >= 0.0) {
        r.hit = true;
        r.toi = root;
        r.distance = distance(at(root));
    } else {
        r.toi = 1.0;
        r.distance = distance(x1);
    }
    return r;
}

double max_edge(const Vec3& a, const Vec3& b, const Vec3& c) {
    return std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
}

}  // namespace

CcdResult point_triangle_ccd(const Vec3& p0, const Vec3& t10, const Vec3& t20, const Vec3& t30, const Vec3& p1,
                             const Vec3& t11, const Vec3& t21, const Vec3& t31, const CcdOptions& options) {
    // coplanar when det(t2 − t1, t3 − t1, p − t1) = 0
    const std::array<double, 4> k = cubic_of(t20 - t10, (t21 - t11) - (t20 - t10), t30 - t10, (t31 - t11) - (t30 - t10),
                                             p0 - t10, (p1 - t11) - (p0 - t10));
    return advance(
        {p0, t10, t20, t30}, {p1, t11, t21, t31}, 1, max_edge(t10, t20, t30), options,
        [](const std::array<Vec3, 4>& x) { return point_triangle_distance(x[0], x[1], x[2], x[3]); }, k);
}

CcdResult edge_edge_ccd(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1, const Vec3& b1,
                        const Vec3& c1, const Vec3& d1, const CcdOptions& options) {
    // coplanar when det(b − a, c − a, d − a) = 0
    const std::array<double, 4> k =
        cubic_of(b0 - a0, (b1 - a1) - (b0 - a0), c0 - a0, (c1 - a1) - (c0 - a0), d0 - a0, (d1 - a1) - (d0 - a0));
    return advance(
        {a0, b0, c0, d0}, {a1, b1, c1, d1}, 2, std::max((b0 - a0).norm(), (d0 - c0).norm()), options,
        [](const std::array<Vec3, 4>& x) { return edge_edge_distance(x[0], x[1], x[2], x[3]); }, k);
}

CcdResult sphere_sphere_ccd(const Vec3& c10, const Vec3& c20, const Vec3& c11, const Vec3& c21, double r1, double r2) {
    // |u₀ + t·Δu|² = R²:  a·t² + 2·b·t + c = 0,  a = |Δu|², b = u₀·Δu, c = |u₀|² − R²
    const Vec3 u0 = c20 - c10;
    const Vec3 du = (c21 - c11) - u0;
    const double R = std::max(r1, r2);
    CcdResult r;
    r.distance = (u0 + du).norm() - R;
    const double a = du.squaredNorm();
    const double b = u0.dot(du);
    const double c = u0.squaredNorm() - R * R;
    if (!(c > 0.0) || !(b < 0.0) || !(a > 0.0)) return r;  // inside at the start, or not approaching
    const double disc = b * b - a * c;
    if (disc < 0.0) return r;                     // passes by
    const double t = c / (-b + std::sqrt(disc));  // the smaller root, without cancellation
    if (!(t <= 1.0)) return r;
    r.hit = true;
    r.toi = t;
    r.distance = (u0 + t * du).norm() - R;
    return r;
}

}  // namespace penalty
