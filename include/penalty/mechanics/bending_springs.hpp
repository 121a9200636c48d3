#pragma once
/// @file
/// SOFA's TriangularBendingSprings: one spring across each edge shared by exactly two triangles,
/// between the two vertices opposite that edge (TriangularBendingSprings::applyTriangleCreation).
/// Order and ends as SOFA: springs in the topology's edge order; for edge e with the triangles
/// t0 < t1 around it, m1 = the vertex of t1 opposite e, m2 = the vertex of t0 opposite e; rest
/// length |x⁰_m1 − x⁰_m2| from the rest positions. The force law is SpringForceField's with
/// a = m1, b = m2 and a null length of 1e-4 m (TriangularBendingSprings::addForce).

#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <span>
#include <vector>

namespace penalty {

/// SOFA's TriangularBendingSprings null length (m): shorter springs give no force.
inline constexpr double kBendingSpringNullLength = 1e-4;

/// The bending springs of `topology` with stiffness ks (N/m) and damping kd (N·s/m), rest
/// lengths from `rest_positions` (throws std::invalid_argument for an index out of range).
std::vector<Spring> triangular_bending_springs(const MeshTopology& topology, std::span<const Vec3> rest_positions,
                                               double ks, double kd);

}  // namespace penalty
