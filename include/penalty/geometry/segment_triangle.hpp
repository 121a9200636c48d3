#pragma once
/// @file
/// Crossing of a segment through a triangle (the test of SOFA's Discrete Triangle–Line).

#include "penalty/core/types.hpp"

#include <optional>

namespace penalty {

/// A crossing point X = p0 + u(p1 − p0) + v(p2 − p0) = q0 + w(q1 − q0).
struct SegmentTriangleCrossing {
    double u = 0, v = 0, w = 0;
    Vec3 point = Vec3::Zero();
};

/// Solves the 3×3 system [p1−p0, p2−p0, −(q1−q0)] (u, v, w) = q0 − p0; a crossing exists iff
/// u ≥ 0, v ≥ 0, u + v ≤ 1, 0 ≤ w ≤ 1 (closed tests). Singular system (|det| ≤ 1e-300, i.e.
/// segment parallel to the plane or degenerate triangle/segment): std::nullopt.
[[nodiscard]] std::optional<SegmentTriangleCrossing> segment_triangle_crossing(const Vec3& p0, const Vec3& p1,
                                                                               const Vec3& p2, const Vec3& q0,
                                                                               const Vec3& q1);

}  // namespace penalty
