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
#include "penalty/collision/collision_model.hpp"
#include "penalty/core/types.hpp"

#include <cmath>

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

/// Whether a plane spanned by u and v with normal n = u × v is reliable enough for the tests:
/// u and v more than about 1e-3 rad from parallel (|n|² > 1e-6 |u|² |v|²), and |u|² |v|² in the
/// normal floating-point range. n2 = |n|², uv2 = |u|² |v|².
[[nodiscard]] inline bool reliable_plane(double n2, double uv2) { return uv2 > 1e-280 && n2 > 1e-6 * uv2; }

/// The file comment's allowance: a point at signed distance s from the plane (unit normal) is
/// beyond R when s² > separation_limit(R, S2), S2 ≥ the largest |p|² of the points involved.
[[nodiscard]] inline double separation_limit(double R, double S2) { return 1.001 * R * R + 1e-15 * S2; }

/// True only if every point q lies on the same side of the plane through `origin` spanned by
/// u and v, farther than R from it (with the file comment's allowance). False when the plane is
/// unreliable: u and v nearly parallel (|u × v|² ≤ 1e-6 |u|² |v|²), or |u|² |v|² or the bound
/// outside the normal floating-point range.
template <class... Q>
[[nodiscard]] inline bool plane_separates(const Vec3& origin, const Vec3& u, const Vec3& v, double R, const Q&... q) {
    const Vec3 n = u.cross(v);
    const double n2 = n.squaredNorm();
    const double u2 = u.squaredNorm();
    const double v2 = v.squaredNorm();
    const double uv2 = u2 * v2;
    if (!reliable_plane(n2, uv2)) return false;
    // S² = 2 (|origin|² + |u|² + |v|² + Σ |q|²) bounds |p|² of every point of both elements
    // (origin + u, q + a direction of the other element)
    const double S2 = 2.0 * (origin.squaredNorm() + u2 + v2 + (q.squaredNorm() + ...));
    // s² > (1.001 R² + 1e-15 S²) |n|²  ⇒  |s| / |n| > R + the allowance, s = n·(q − origin)
    const double limit = separation_limit(R, S2) * n2;
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

/// Planes that hold one element, for testing a whole box against it at once (the traversal's
/// row mode, collision_pipeline.cpp): a triangle's plane, or for a segment the three planes
/// through it parallel to a coordinate axis (normals d × e_x, d × e_y, d × e_z). If a box lies
/// farther than R from one of them, so does every point in the box, and every point of an
/// element whose box it contains is farther than R from every point of this element: a kernel
/// that joins a point of this element's plane or line to a point within the other element's
/// box, and needs their distance below R, has no output for the pair.
///
/// Same allowance as plane_separates: a box is cleared only when its gap g to the plane
/// satisfies g² > 1.001 R² + 1e-15 S², S² = 2 (|p1|² + |u|² + |v|² + the box's largest |corner|²).
/// The gap is computed from the box's centre and half extents to within about 1e-15 S; the
/// triangle's plane is used only when its normal is reliable (as plane_separates); a segment's
/// three normals are exact cross products with the axes of its computed direction, which is
/// within one rounding of the true one componentwise, so each is within about ε of
/// perpendicular to the true segment whatever its direction. NaN and infinities never clear.
struct ElementPlanes {
    Vec3 normal[3];  ///< not unit; the element lies in {x : normal·x = offset}
    double offset[3] = {};
    double normal2[3] = {};   ///< |normal|²
    int count = 0;            ///< 0: nothing is ever cleared (degenerate or unreliable element)
    double element_s2 = 0.0;  ///< 2 (|p1|² + |u|² + |v|²)
    double R2 = 0.0;          ///< 1.001 R²

    /// The plane of triangle (p1, p2, p3), when its normal is reliable.
    [[nodiscard]] static ElementPlanes triangle(const Vec3& p1, const Vec3& p2, const Vec3& p3, double R) {
        ElementPlanes e;
        const Vec3 u = p2 - p1;
        const Vec3 v = p3 - p1;
        e.element_s2 = 2.0 * (p1.squaredNorm() + u.squaredNorm() + v.squaredNorm());
        e.R2 = 1.001 * R * R;
        const Vec3 n = u.cross(v);
        const double n2 = n.squaredNorm();
        const double uv2 = u.squaredNorm() * v.squaredNorm();
        if (!(uv2 > 1e-280) || !(n2 > 1e-6 * uv2)) return e;
        e.add(n, n2, p1);
        return e;
    }

    /// The three axis-parallel planes through segment (p1, p2) (those whose normal is not 0).
    [[nodiscard]] static ElementPlanes segment(const Vec3& p1, const Vec3& p2, double R) {
        ElementPlanes e;
        const Vec3 d = p2 - p1;
        e.element_s2 = 2.0 * (p1.squaredNorm() + d.squaredNorm());
        e.R2 = 1.001 * R * R;
        const Vec3 normals[3] = {Vec3(0.0, d.z(), -d.y()), Vec3(-d.z(), 0.0, d.x()), Vec3(d.y(), -d.x(), 0.0)};
        for (const Vec3& n : normals) {
            const double n2 = n.squaredNorm();
            if (n2 > 1e-280) e.add(n, n2, p1);
        }
        return e;
    }

    /// True only if every point of `box`, grown by `pad` on every side, is farther than R (with
    /// the allowance) from one of the planes.
    [[nodiscard]] bool clears(const Aabb& box, double pad = 0.0) const {
        if (count == 0) return false;
        const Vec3 lo = box.min.array() - pad;
        const Vec3 hi = box.max.array() + pad;
        const Vec3 centre = 0.5 * (lo + hi);
        const Vec3 half = 0.5 * (hi - lo);
        const double corner2 = lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).squaredNorm();
        const double allowance = R2 + 1e-15 * (element_s2 + 2.0 * corner2);
        for (int k = 0; k < count; ++k) {
            const double s = normal[k].dot(centre) - offset[k];
            const double gap = std::abs(s) - normal[k].cwiseAbs().dot(half);
            const double limit = allowance * normal2[k];
            if (gap > 0.0 && limit > 1e-290 && gap * gap > limit) return true;
        }
        return false;
    }

private:
    void add(const Vec3& n, double n2, const Vec3& origin) {
        normal[count] = n;
        offset[count] = n.dot(origin);
        normal2[count] = n2;
        ++count;
    }
};

}  // namespace penalty::detail
