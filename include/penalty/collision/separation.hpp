#pragma once
/// @file
/// Early outs of the proximity kernels (src/collision/kernels_sofa.cpp): tests that rule out
/// every output of an element pair before the kernel computes its closest points. Internal
/// (namespace detail), public for their tests.
///
/// Every output of a NewProximity or MinProximity kernel joins a point p of one element to a
/// point q of the other and exists only if the computed distance |q − p| < R. The points lie on
/// their elements (a triangle's closest feature, a segment's clamped or interior parameter, a
/// point). So if a plane holds one element and leaves the other farther than R on one side, no
/// output exists. For two segments, the plane through one parallel to both holds it, and the
/// other lies in the parallel plane through its first point.
///
/// The tests are exactly conservative: plane_separates rejects only when the separation d
/// satisfies d² > 1.001 R² + 1e-15 S², S² ≥ the largest |p|² of the points involved, i.e.
/// d > 1.0005 R or more, plus about 3e-8 S. The kernels compute their points and distances to
/// within about 1e-14 S, and the test its own separation to within 1e-12 S (the plane is used
/// only when its normal is reliable: the two spanning directions more than about 1e-3 rad
/// apart), so a rejected pair is one the kernel rejects too: the outputs are the same, bit for
/// bit, only found sooner. NaN or infinite inputs compare false and are never rejected here
/// (the kernel decides).
#include "penalty/core/types.hpp"

namespace penalty::detail {

/// Whether the separation tests are worth their cost for a model pair whose Triangle or Line
/// element boxes have `longest_side` as their largest side, with the box margin R: only if it
/// exceeds 16 R. A shorter element's box, inflated by the margin, is already a close fit, and the
/// kernel's own early exits are as cheap as the test (measured: on every candidate, NewProximity
/// Triangle–Triangle on 0.46 m triangles with R = 0.5 made MeshSpringForceField's detection 17 %
/// slower, while against the 117–150 m elements of a pyramid floor it cut Gravity's by 15 %;
/// docs/performance.md). Decided once per model pair and tree build (PairCtx::separation_tests),
/// not per element pair, whose length check alone cost 3–4 % of the instructions.
[[nodiscard]] inline bool worth_separating(double longest_side, double R) { return longest_side > 16.0 * R; }

/// True only if every point q lies on the same side of the plane through `origin` spanned by
/// u and v, farther than R from it (with the file comment's allowance). False when the plane is
/// unreliable: u and v nearly parallel (|u × v|² ≤ 1e-6 |u|² |v|²), or |u|² |v|² or the bound
/// outside the normal floating-point range.
template <class... Q>
[[nodiscard]] inline bool plane_separates(const Vec3& origin, const Vec3& u, const Vec3& v, double R,
                                          const Q&... q) {
    const Vec3 n = u.cross(v);
    const double n2 = n.squaredNorm();
    const double u2 = u.squaredNorm();
    const double v2 = v.squaredNorm();
    const double uv2 = u2 * v2;
    if (!(uv2 > 1e-280) || !(n2 > 1e-6 * uv2)) return false;
    // S² = 2 (|origin|² + |u|² + |v|² + Σ |q|²) bounds |p|² of every point of both elements
    // (origin + u, q + a direction of the other element)
    const double S2 = 2.0 * (origin.squaredNorm() + u2 + v2 + (q.squaredNorm() + ...));
    // s² > (1.001 R² + 1e-15 S²) |n|²  ⇒  |s| / |n| > R + the allowance, s = n·(q − origin)
    const double limit = (1.001 * R * R + 1e-15 * S2) * n2;
    if (!(limit > 1e-290)) return false;  // an underflowing bound would reject too much
    int above = 0;
    int below = 0;
    const auto side = [&](const Vec3& p) {
        const double s = n.dot(p - origin);
        if (s * s > limit) (s > 0.0 ? above : below) += 1;
    };
    (side(q), ...);
    constexpr int count = int(sizeof...(Q));
    return above == count || below == count;
}

}  // namespace penalty::detail
