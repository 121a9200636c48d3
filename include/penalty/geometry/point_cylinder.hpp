#pragma once
/// @file
/// Signed distance from a point to a solid (capped) cylinder.

#include "penalty/core/types.hpp"

#include <cstdint>

namespace penalty {

/// A solid cylinder: centre c, unit axis u, radius r ≥ 0, half height h ≥ 0 (m).
/// The solid is { x : |(x−c)·u| ≤ h, |(x−c) − ((x−c)·u)u| ≤ r }. End points c ∓ u h.
struct CylinderShape {
    Vec3 center = Vec3::Zero();
    Vec3 axis = Vec3::UnitY();  ///< unit vector
    double radius = 0.5;
    double half_height = 1.0;
};

/// Feature of the cylinder surface that holds the closest point.
enum class CylinderFeature : std::uint8_t { Side, CapBottom, CapTop, RimBottom, RimTop };

/// Result of point_cylinder_signed_distance.
struct PointCylinderResult {
    double signed_distance = 0.0;  ///< > 0 outside, < 0 inside (m)
    Vec3 closest = Vec3::Zero();   ///< closest point on the cylinder *surface* (m)
    /// unit direction from `closest` toward p when outside; the outward surface normal at
    /// `closest` when inside or on the surface (so p ≈ closest + signed_distance·normal)
    Vec3 normal = Vec3::UnitX();
    CylinderFeature feature = CylinderFeature::Side;
};

/// Signed distance from p to the solid cylinder and the closest surface point. A point on the
/// axis inside uses the nearest of the side (radial direction: any unit vector ⟂ u, chosen
/// deterministically) and the caps; zero radius or zero height are valid (segment, disk).
[[nodiscard]] PointCylinderResult point_cylinder_signed_distance(const Vec3& p, const CylinderShape& cyl);

/// A unit vector orthogonal to the unit vector u (deterministic choice).
[[nodiscard]] Vec3 any_orthogonal(const Vec3& u);

}  // namespace penalty
