#pragma once
/// @file
/// Closest point on a segment [a, b] to a point p (exact, clamped), with the closest feature.

#include "penalty/core/types.hpp"

#include <cstdint>

namespace penalty {

/// Which part of the segment holds the closest point.
enum class SegmentFeature : std::uint8_t { A, B, Interior };

/// Result of point_segment_closest_point.
struct PointSegmentResult {
    double t = 0.0;               ///< parameter of the closest point, in [0, 1] (0 = a, 1 = b)
    Vec3 closest = Vec3::Zero();  ///< a + t (b − a), world frame (m)
    double distance_squared = 0;  ///< |p − closest|² (m²)
    SegmentFeature feature = SegmentFeature::A;
};

/// Closest point of the segment [a, b] to p: t = clamp(((p − a)·(b − a)) / |b − a|², 0, 1).
/// Degenerate segment (|b − a|² ≤ 1e-300 or not finite ratio): t = 0, the segment is the point a.
[[nodiscard]] PointSegmentResult point_segment_closest_point(const Vec3& p, const Vec3& a, const Vec3& b);

}  // namespace penalty
