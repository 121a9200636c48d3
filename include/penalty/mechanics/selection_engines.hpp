#pragma once
/// @file
/// SOFA's selection engines beyond the boxes, planes and balls of regions_of_interest.hpp:
///   - MeshROI's region (MeshROI::isPointInROI): the points inside a closed triangle mesh, by the
///     parity of the mesh triangles a ray from the point crosses;
///   - ProximityROI (ProximityROI::doUpdate): the N points nearest a set of centres, each within its
///     ball;
///   - ValuesFromPositions (ValuesFromPositions::doUpdate): a value per point and element,
///     interpolated along a direction, or the direction itself as a vector field.

#include "penalty/core/types.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <span>
#include <vector>

namespace penalty {

/// MeshROI's region: the bounding box of the ROI mesh's points (MeshROI::computeBoundingBox) and,
/// when `use_mesh` (computeMeshROI), its triangles. A point p is inside when it is in the box
/// (bounds included) and, with use_mesh, a ray from p to a point 100 beyond the box corner nearest
/// to p crosses an odd number of the triangles (MeshROI::isPointInROI, SOFA's operations: the
/// triangle normal N = (p1 − p0) × (p2 − p1), the crossing at d = N·(p0 − p)/N·v with d ≥ 0, and
/// the same-side tests of checkSameOrder). Without use_mesh every point is inside.
class MeshRegion {
public:
    /// Throws std::invalid_argument for a triangle index past the points.
    MeshRegion(std::vector<Vec3> points, std::vector<Triangle> triangles, bool use_mesh);
    /// The region over moved mesh points (MeshROI run again after its `ROIposition` changed): the
    /// triangles and the box stay (MeshROI::roiInit computes the box once, at init). Throws
    /// std::invalid_argument for a triangle index past the points.
    [[nodiscard]] MeshRegion moved(std::vector<Vec3> points) const;
    [[nodiscard]] bool contains(const Vec3& p) const;
    /// xmin ymin zmin xmax ymax zmax (MeshROI's `box` output); zeros without points.
    [[nodiscard]] const std::array<double, 6>& box() const { return box_; }

private:
    [[nodiscard]] bool in_box(const Vec3& p) const;
    void check_triangles() const;
    std::vector<Vec3> points_;
    std::vector<Triangle> triangles_;
    bool use_mesh_;
    std::array<double, 6> box_{};
};

/// What ProximityROI gives.
struct ProximitySelection {
    std::vector<PointId> indices;      ///< the selected points, in the order of SOFA's heap
    std::vector<Vec3> points;          ///< their positions (pointsInROI)
    std::vector<double> distances;     ///< their distance to the nearest centre whose ball holds them
    std::vector<PointId> indices_out;  ///< the others (with SOFA's bookkeeping, see proximity_roi)
};

/// ProximityROI::doUpdate: for each point, the least distance |c_j − p| over the centres whose
/// radius exceeds it (radii missing at the end repeat the last one); the `max_count` points of
/// least such distance kept in a max-heap (std::push_heap / std::pop_heap, ties and order as
/// SOFA's). No centre, no radius or max_count 0: SOFA leaves its outputs as they were, `indices`
/// holding its initial single 0; so does this (indices = {0}, the rest empty). As SOFA,
/// `indices_out` receives, when a point evicts the farthest kept one, the index of the heap's new
/// top after the eviction (SOFA reads a reference to the heap's front after pop_heap).
[[nodiscard]] ProximitySelection proximity_roi(std::span<const Vec3> points, std::span<const Vec3> centers,
                                               std::vector<double> radii, std::size_t max_count);

/// ValuesFromPositions' outputs.
struct ValuesFromPositionsResult {
    std::vector<double> point_values, edge_values, triangle_values, tetrahedron_values;
    std::vector<Vec3> point_vectors, edge_vectors, triangle_vectors, tetrahedron_vectors;
};

/// ValuesFromPositions::doUpdate. Scalar field: at a point (an element's centre, (p0 + p1)·0.5,
/// (p2 + p1 + p0)/3, (p3 + p2 + p1 + p0)/4) the value t = ((p·dir) − bmin)/(bmax − bmin)·(n − 1)
/// linearly interpolated between the n `input_values` (clamped to the first and last); vector
/// field: `direction` everywhere. [bmin, bmax]: SOFA takes the x extent of the scene's bounding box.
[[nodiscard]] ValuesFromPositionsResult values_from_positions(
    std::span<const Vec3> points, const std::vector<Edge>& edges, const std::vector<Triangle>& triangles,
    const std::vector<Tetrahedron>& tetrahedra, const Vec3& direction, std::span<const double> input_values,
    double bmin, double bmax, bool vector_field);

}  // namespace penalty
