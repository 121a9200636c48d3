#pragma once
/// @file
/// The candidate filter of NewProximity Triangle–Point and Triangle–Sphere (Triangle–RigidSphere
/// too): the first tests of those kernels, alone, run over all of a model pair's candidates
/// before the kernels (src/collision/kernels.hpp, KernelParts::filter). Internal (namespace
/// detail), public for its tests.
///
/// For a point q (a Point, or a sphere's centre) and a triangle (p1, p2, p3) the kernels solve
/// the Gram system q ≈ p1 + α AB + β AC, and give no output when the triangle is degenerate
/// (det = |AB|²|AC|² − (AB·AC)² ≤ 0, |AB|² ≤ 0, |AC|² ≤ 0 or |BC|² ≤ 0, or NaN) or when the
/// closest feature of the projection (the face, a vertex or an edge, by SOFA's thresholds of
/// the kernel: triangle_point, or triangle_sphere with its quirks §14.2) is a vertex or an edge
/// the triangle does not own (TriangleModel flags). The filter makes exactly those decisions,
/// with the same IEEE operations in the same order, so it keeps every candidate with an output
/// and the kernels give the kept ones the same outputs, bit for bit.
#include "penalty/collision/intersection.hpp"
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/kernel_path.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace penalty::detail {

/// Appends to `kept`, in their order, the candidates (triangle e1 << 32 | element e2 of m2) of
/// `keys` that pass NewProximity's degenerate and closest-feature tests (above) for m2's kind:
/// a PointModel (Triangle–Point's constants), a SphereModel or a RigidSphereModel (Triangle–
/// Sphere's, with params' quirks). KernelPath::avx: four candidates at a time in AVX lanes.
/// Element indices must be in range; throws std::invalid_argument for another kind of m2.
void keep_owned_feature_candidates(const IntersectionParams& params, const TriangleModel& t, const CollisionModel& m2,
                                   std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept,
                                   KernelPath path);

}  // namespace penalty::detail
