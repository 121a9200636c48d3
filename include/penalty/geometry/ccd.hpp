#pragma once
/// @file
/// Continuous collision detection of one feature pair over a linear motion (beyond SOFA: the
/// tunnelling guard, docs/no-tunnelling.md): does a point pass through a triangle, two edges
/// through each other, a sphere's centre into another sphere, while every vertex moves on a
/// straight line from its start to its end position during the step (t ∈ [0, 1])?
///
/// Point–triangle and edge–edge use additive conservative advancement (Li, Kaufman, Jiang,
/// "Codimensional Incremental Potential Contact", ACM TOG 40(4), 2021, §5 "additive CCD"): with
/// the common translation removed from the displacements Δ_i (Δ_i − mean Δ), the distance of the
/// pair cannot shrink faster than
///     l_p = |Δ_p| + max_k |Δ_tk|              (point–triangle: point p, triangle t1 t2 t3)
///     l_p = max(|Δ_a|, |Δ_b|) + max(|Δ_c|, |Δ_d|)   (edge–edge: [a, b] and [c, d])
/// per unit of t (the distance is 1-Lipschitz in each of the two features' positions, and each
/// feature's closest point is a convex combination of its vertices). From a time t at distance d,
/// no contact can happen before t + d/l_p, so advancing by c·d/l_p (c = advance_fraction < 1)
/// never passes a contact. The loop advances until the distance falls to the touch distance ε
/// (a hit: the features met, to ε) or t reaches 1 (no hit). Unlike the IPC paper's gap-preserving
/// stop at s·d₀, the loop goes on to the touch, so a near miss closer than s·d₀ is not a hit.
///
/// A slow approach, or a graze (the features gliding past each other closer than their motion),
/// would take many advances: after max_iterations the rest of the motion is decided exactly
/// instead, by the roots of the cubic f(t) whose zeros are the times the four points are coplanar
/// (det(t2 − t1, t3 − t1, p − t1), det(b − a, c − a, d − a)): f is monotone between the roots of
/// f′, each piece's sign change is bisected, and the first root at which the distance is ≤ ε is
/// the hit (a touch needs coplanarity). Motions coplanar throughout (f ≡ 0 to rounding) are
/// reported as hits (`capped`).
///
/// Guarantee: no false negative (exact arithmetic in the advancement; in the root phase, a touch
/// at a sign change of f). A pair whose distance reaches 0 at some t ∈ [0, 1] is a hit, with a
/// toi no later than the first touch (the distance at toi ≤ ε). False positives: pairs that come
/// within ε without touching, and `capped` coplanar motions. tests/geometry/test_ccd.cpp checks
/// the closed-form times of impact, 10⁵ seeded random motions per pair against a fine sampling of
/// the motion (no false negative) and measures the false-positive rate (0 of about 10⁵).
///
/// The sphere test is closed form: the centres' relative motion is linear, u(t) = u₀ + t·Δu.

#include "penalty/core/types.hpp"

namespace penalty {

/// Parameters of the conservative advancement.
struct CcdOptions {
    /// ε = touch_tolerance · L, with L the pair's length scale (its largest edge or segment at the
    /// start, plus l_p): a distance at or below ε is a touch. Dimensionless, > 0.
    double touch_tolerance = 1e-9;
    /// c: each advance is c·d/l_p (dimensionless, in (0, 1)); 0.9 as in the IPC paper.
    double advance_fraction = 0.9;
    /// Advances before the exact coplanarity-root test decides the rest of the motion, > 0.
    int max_iterations = 64;
};

/// What a continuous test found.
struct CcdResult {
    bool hit = false;       ///< the features touch (to ε) at some t ∈ [0, 1], or `capped`
    double toi = 1.0;       ///< t of the first touch found (≤ the true one), in [0, 1]; 1 without a hit
    double distance = 0.0;  ///< the pair's distance at toi (m); at t = 1 without a hit
    int iterations = 0;     ///< advances made
    bool capped = false;    ///< a hit by default: coplanar motion the root test cannot decide
};

/// Point p and triangle (t1, t2, t3), each vertex moving linearly from its `0` position (t = 0)
/// to its `1` position (t = 1). A point that starts within ε of the triangle is a hit at toi 0.
[[nodiscard]] CcdResult point_triangle_ccd(const Vec3& p0, const Vec3& t10, const Vec3& t20, const Vec3& t30,
                                           const Vec3& p1, const Vec3& t11, const Vec3& t21, const Vec3& t31,
                                           const CcdOptions& options = {});

/// Segments [a, b] and [c, d], each end moving linearly (as point_triangle_ccd).
[[nodiscard]] CcdResult edge_edge_ccd(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& d0, const Vec3& a1,
                                      const Vec3& b1, const Vec3& c1, const Vec3& d1, const CcdOptions& options = {});

/// Spheres of radii r1, r2 ≥ 0 whose centres move linearly (c1: c10 → c11, c2: c20 → c21): a hit
/// when, at some t ∈ (0, 1], the centre of one lies inside the other, |u(t)| < max(r1, r2) with
/// u = c2 − c1 (a radius 0 is a point). A pair already so at t = 0 is not a hit (it crossed in
/// an earlier step). Closed form: the first root of |u₀ + t·Δu|² = R² (R = max(r1, r2)); toi is
/// that root, distance |u(toi)| − R (0 up to rounding). Exact: no false positive or negative
/// beyond rounding.
[[nodiscard]] CcdResult sphere_sphere_ccd(const Vec3& c10, const Vec3& c20, const Vec3& c11, const Vec3& c21, double r1,
                                          double r2);

/// Distance (m) between point p and the solid triangle (t1, t2, t3).
[[nodiscard]] double point_triangle_distance(const Vec3& p, const Vec3& t1, const Vec3& t2, const Vec3& t3);
/// Distance (m) between the segments [a, b] and [c, d].
[[nodiscard]] double edge_edge_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace penalty
