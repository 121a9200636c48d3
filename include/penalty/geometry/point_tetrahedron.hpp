#pragma once
/// @file
/// Signed distance from a point to a solid tetrahedron.

#include "penalty/core/types.hpp"

namespace penalty {

/// Result of point_tetrahedron_signed_distance.
struct PointTetrahedronResult {
    double signed_distance = 0.0;  ///< > 0 outside, ≤ 0 inside (depth below the nearest face)
    Vec3 closest = Vec3::Zero();   ///< closest point on the tetrahedron boundary (m)
    /// unit vector: from `closest` toward p when outside; outward normal of the nearest face when
    /// inside (p = closest + signed_distance·normal)
    Vec3 normal = Vec3::UnitX();
    int face = 0;  ///< face holding `closest`: face k is opposite vertex k
    bool inside = false;
};

/// Signed distance from p to the solid tetrahedron (p0, p1, p2, p3) (either orientation).
/// Flat tetrahedra (|volume| ≤ 1e-14 · (max edge)³) have no inside: the distance to the union of
/// the four faces is returned, ≥ 0.
[[nodiscard]] PointTetrahedronResult point_tetrahedron_signed_distance(const Vec3& p, const Vec3& p0, const Vec3& p1,
                                                                       const Vec3& p2, const Vec3& p3);

}  // namespace penalty
