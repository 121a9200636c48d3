#pragma once
/// @file
/// Closest points between two segments [a, b] and [c, d] (exact, clamped).

#include "penalty/core/types.hpp"

namespace penalty {

/// Result of segment_segment_closest_points.
struct SegmentSegmentResult {
    double s = 0.0;               ///< parameter on [a, b] in [0, 1]
    double t = 0.0;               ///< parameter on [c, d] in [0, 1]
    Vec3 p = Vec3::Zero();        ///< a + s (b − a) (m)
    Vec3 q = Vec3::Zero();        ///< c + t (d − c) (m)
    double distance_squared = 0;  ///< |q − p|² (m²)
    bool parallel = false;        ///< the directions are parallel (or a segment is degenerate):
                                  ///< the closest pair is not unique; one minimiser is returned
};

/// Closest points between segments [a, b] and [c, d]: minimises |c + t(d − c) − a − s(b − a)|²
/// over s, t ∈ [0, 1]. Parallel and zero-length segments are handled (no NaN): for parallel
/// segments the minimiser with the smallest s is returned among those found by clamping.
[[nodiscard]] SegmentSegmentResult segment_segment_closest_points(const Vec3& a, const Vec3& b, const Vec3& c,
                                                                  const Vec3& d);

}  // namespace penalty
