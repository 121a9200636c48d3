#pragma once
/// @file
/// Lengths, areas and volumes of mesh elements as SOFA's sofa::geometry computes them (the masses
/// computed from a topology, DiagonalMass and MeshMatrixMass, share them; the rounding of a mass
/// depends on the formula).

#include "penalty/core/types.hpp"

#include <array>
#include <cmath>

namespace penalty {

/// sofa::geometry::Triangle::area (3D): ½ |(b − a) × (c − a)| (m²).
[[nodiscard]] inline double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
    return 0.5 * (b - a).cross(c - a).norm();
}

/// sofa::geometry::Quad::area: triangles (0, 1, 2) + (0, 2, 3) (m²).
[[nodiscard]] inline double quad_area(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return triangle_area(a, b, c) + triangle_area(a, c, d);
}

/// sofa::geometry::Tetrahedron::volume: |((b − a) × (c − a))·(d − a)| / 6 (m³).
[[nodiscard]] inline double tetrahedron_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return std::abs((b - a).cross(c - a).dot(d - a) / 6.0);
}

/// sofa::geometry::Hexahedron::volume: the sum of six tetrahedra, in SOFA's split and order (m³).
[[nodiscard]] inline double hexahedron_volume(const std::array<Vec3, 8>& n) {
    return tetrahedron_volume(n[0], n[5], n[1], n[6]) + tetrahedron_volume(n[0], n[1], n[3], n[6]) +
           tetrahedron_volume(n[1], n[3], n[6], n[2]) + tetrahedron_volume(n[6], n[3], n[0], n[7]) +
           tetrahedron_volume(n[6], n[7], n[0], n[5]) + tetrahedron_volume(n[7], n[5], n[4], n[0]);
}

}  // namespace penalty
