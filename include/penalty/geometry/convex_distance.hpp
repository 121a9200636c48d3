#pragma once
/// @file
/// Distance and closest points between two convex primitives (point, segment, triangle, solid
/// cylinder) by GJK, plus an approximate penetration for overlapping pairs.

#include "penalty/core/types.hpp"
#include "penalty/geometry/point_cylinder.hpp"

#include <cstdint>
#include <span>

namespace penalty {

/// A convex primitive described by its support function.
struct ConvexShape {
    enum class Kind : std::uint8_t { kPoint, kSegment, kTriangle, kCylinder };
    Kind kind = Kind::kPoint;
    Vec3 v[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  ///< vertices (point/segment/triangle)
    CylinderShape cylinder;                                  ///< when kind == kCylinder

    static ConvexShape point(const Vec3& p);
    static ConvexShape segment(const Vec3& a, const Vec3& b);
    static ConvexShape triangle(const Vec3& a, const Vec3& b, const Vec3& c);
    static ConvexShape make_cylinder(const CylinderShape& c);

    /// A point of the shape maximising d·x (d need not be unit; d = 0 gives a valid point).
    [[nodiscard]] Vec3 support(const Vec3& d) const;
    /// A point inside the shape (centroid or centre).
    [[nodiscard]] Vec3 inner_point() const;
};

/// Result of convex_distance.
struct ConvexDistanceResult {
    double distance = 0.0;        ///< ≥ 0; 0 when the shapes overlap or touch (m)
    Vec3 point_a = Vec3::Zero();  ///< closest point on A (m)
    Vec3 point_b = Vec3::Zero();  ///< closest point on B (m)
    bool overlapping = false;     ///< the shapes intersect (distance ≤ 1e-12 · scale)
    int iterations = 0;
};

/// Euclidean distance between convex shapes A and B and a pair of closest points, by GJK with
/// an exact closest-point-on-simplex subalgorithm. Relative accuracy of the distance: about
/// `relative_tolerance` (stops when |v|² − v·w ≤ tol·|v|²) or at `max_iterations`.
[[nodiscard]] ConvexDistanceResult convex_distance(const ConvexShape& a, const ConvexShape& b,
                                                   double relative_tolerance = 1e-12, int max_iterations = 128);

/// Result of convex_penetration.
struct ConvexPenetrationResult {
    double depth = 0.0;           ///< overlap along `normal` (m), > 0 when overlapping
    Vec3 normal = Vec3::UnitX();  ///< unit, from A toward B (moving B by depth·normal separates
                                  ///< the pair along this direction)
    Vec3 point_a = Vec3::Zero();  ///< deepest point of A along +normal
    Vec3 point_b = Vec3::Zero();  ///< deepest point of B along −normal
};

/// Approximate penetration of overlapping shapes: the separating-axis overlap
/// depth(n) = max_A n·x − min_B n·y is evaluated for each candidate direction n and its opposite;
/// the smallest is returned. Exact when the true minimum translation direction is a candidate.
/// Zero candidate vectors are skipped; if none remain, normal = (1,0,0).
[[nodiscard]] ConvexPenetrationResult convex_penetration(const ConvexShape& a, const ConvexShape& b,
                                                         std::span<const Vec3> candidates);

}  // namespace penalty
