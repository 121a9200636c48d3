#pragma once
/// @file
/// Candidate filters of the proximity kernels whose candidates mostly fail their first tests:
/// those tests alone, run over all of a model pair's candidates before the kernel
/// (src/collision/kernels.hpp, KernelParts::filter), four candidates at a time in AVX lanes.
/// Each filter makes exactly the kernel's decisions, with the same IEEE operations in the same
/// order (Eigen's Vec3 dot is (x·x′ + y·y′) + z·z′; the build has -ffp-contract=off), so it
/// keeps every candidate with an output and the kernel gives the kept ones the same outputs,
/// bit for bit. Internal (namespace detail), public for its tests.
///
/// Triangle against a point q (a Point, or a sphere's centre): the kernels solve the Gram
/// system q ≈ p1 + α AB + β AC and give no output when the triangle is degenerate
/// (det = |AB|²|AC|² − (AB·AC)² ≤ 0, |AB|² ≤ 0, |AC|² ≤ 0 or |BC|² ≤ 0, or NaN), nor when
///  - NewProximity Triangle–Point and Triangle–Sphere: the closest feature of the projection
///    (the face, a vertex or an edge, by SOFA's thresholds of the kernel: triangle_point, or
///    triangle_sphere with its quirks §14.2) is a vertex or an edge the triangle does not own
///    (TriangleModel flags);
///  - MinProximity Triangle–Point and Triangle–Sphere: the projection is not strictly inside
///    (α, β ≥ 10⁻⁶ and α + β ≤ 0.999999 fail).
/// Segment against segment (NewProximity and MinProximity Line–Line): the closest points of
/// the two lines, α and β along them, unless the segments are parallel (|det| of the 2 × 2
/// normal equations at most the method's `parallel`), must lie in [lo, hi] (LineLineConstants).
#include "penalty/collision/intersection.hpp"
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/kernel_path.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace penalty::detail {

/// Appends to `kept`, in their order, the candidates (PairKey(triangle e1, element e2 of m2).bits()) of
/// `keys` that pass the first tests (above) of params.method's Triangle kernel against m2's
/// kind: a PointModel, a SphereModel or a RigidSphereModel. NewProximity or MinProximity;
/// element indices must be in range. Throws std::invalid_argument for another method or kind.
void keep_triangle_candidates(const IntersectionParams& params, const TriangleModel& t, const CollisionModel& m2,
                              std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept, KernelPath path);

/// Appends to `kept`, in their order, the candidates (PairKey(segment e1 of l1, segment e2
/// of l2).bits()) of `keys` whose closest points pass params.method's Line–Line test (above): NewProximity
/// or MinProximity (throws std::invalid_argument for another method).
void keep_line_line_candidates(const IntersectionParams& params, const LineModel& l1, const LineModel& l2,
                               std::span<const std::uint64_t> keys, std::vector<std::uint64_t>& kept, KernelPath path);

}  // namespace penalty::detail
