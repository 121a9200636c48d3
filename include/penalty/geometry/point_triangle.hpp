#pragma once
/// @file
/// Closest point on a triangle (p0, p1, p2) to a point (exact), with its feature and barycentric
/// coordinates.

#include "penalty/core/types.hpp"

#include <cstdint>

namespace penalty {

/// The feature of the triangle that holds the closest point.
enum class TriangleFeature : std::uint8_t { V0, V1, V2, E01, E12, E20, Face };

/// Result of point_triangle_closest_point.
struct PointTriangleResult {
    Vec3 closest = Vec3::Zero();  ///< closest point (m)
    /// barycentric weights (w0, w1, w2) of `closest`: closest = w0 p0 + w1 p1 + w2 p2,
    /// each in [0, 1], summing to 1.
    Vec3 barycentric = Vec3(1.0, 0.0, 0.0);
    double distance_squared = 0.0;  ///< |p − closest|² (m²)
    TriangleFeature feature = TriangleFeature::V0;
    bool degenerate = false;  ///< zero-area triangle: the closest point over its three edges
};

/// Closest point of the solid triangle (p0, p1, p2) to p, by Voronoi-region classification.
/// A zero-area triangle (|(p1−p0)×(p2−p0)|² ≤ 1e-28 · (max squared edge length)²) is treated
/// as the union of its three edges (`degenerate` = true); never produces NaN for finite input.
[[nodiscard]] PointTriangleResult point_triangle_closest_point(const Vec3& p, const Vec3& p0, const Vec3& p1,
                                                               const Vec3& p2);

}  // namespace penalty
