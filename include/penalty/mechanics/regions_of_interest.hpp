#pragma once
/// @file
/// SOFA's region-of-interest engines beyond the boxes of regions.hpp: the shapes of PlaneROI and
/// SphereROI, and the element selection every ROI shares (BaseROI::doUpdate, PlaneROI::doUpdate):
/// the indices, increasing, of the points and of the elements (edges, triangles, quads, tetrahedra,
/// hexahedra) inside the region.

#include "penalty/core/types.hpp"
#include "penalty/mechanics/topology.hpp"

#include <functional>
#include <span>
#include <vector>

namespace penalty {

/// SOFA's PlaneROI shape (PlaneROI::computePlane, isPointInPlane): a box spanned by three points
/// p0, p1, p2 (edges p0→p1 and p1→p2, the fourth corner p3 = p0 + p2 − p1) and a depth d,
/// centred on that rectangle along n = (p1−p0)×(p2−p0)/|…|. A point p is inside when
/// |(p−p0)·m0| ≤ w, |(p−p2)·m1| ≤ w, |(p−p0)·m2| ≤ l, |(p−p2)·m3| ≤ l and |(p−p0)·n| ≤ |d/2|,
/// with the side normals m0..m3 and w = |(p2−p0)·m0|, l = |(p2−p0)·m2| as SOFA computes them.
class PlaneRegion {
public:
    /// SOFA's ten numbers: p0 (3), p1 (3), p2 (3), depth.
    PlaneRegion(const Vec3& p0, const Vec3& p1, const Vec3& p2, double depth);
    [[nodiscard]] bool contains(const Vec3& p) const;

private:
    Vec3 p0_, p2_, normal_, side0_, side1_, side2_, side3_;
    double width_, length_, depth_;
};

/// A closed ball |p − c|² ≤ r² (SphereROI::isPointInSphere).
struct SphereRegion {
    Vec3 center;
    double radius;
    [[nodiscard]] bool contains(const Vec3& p) const { return (p - center).squaredNorm() <= radius * radius; }
};

/// The element lists an ROI tests (empty: not computed).
struct RoiElements {
    std::vector<Edge> edges;
    std::vector<Triangle> triangles;
    std::vector<Quad> quads;
    std::vector<Tetrahedron> tetrahedra;
    std::vector<Hexahedron> hexahedra;
};

/// What an ROI selects: indices, increasing, into the points and into each element list.
struct RoiSelection {
    std::vector<PointId> points;
    std::vector<PointId> edges;
    std::vector<PointId> triangles;
    std::vector<PointId> quads;
    std::vector<PointId> tetrahedra;
    std::vector<PointId> hexahedra;
};

/// Is point p inside the region (any of its shapes)?
using PointInRegion = std::function<bool(const Vec3&)>;

/// How an element is tested (BaseROI's `strict`): all of its points inside (strict, SOFA's
/// default; PlaneROI always), or its centre (the mean of its points) inside; MeshROI's non-strict
/// test (MeshROI::isEdgeInROI, ...): all of its points inside, or else its centre.
enum class ElementTest { all_points, center, all_points_or_center };

/// Optional extra filters on edges and triangles (SphereROI's edgeAngle / triAngle).
struct ElementFilters {
    std::function<bool(const Edge&)> edge;
    std::function<bool(const Triangle&)> triangle;
};

/// The points of `points` inside, and the elements of `elements` inside (their point indices
/// into `points`; an element with an index past `points` is never inside).
[[nodiscard]] RoiSelection select_in_region(std::span<const Vec3> points, const RoiElements& elements,
                                            const PointInRegion& inside, ElementTest test,
                                            const ElementFilters& filters = {});

/// SphereROI's edge filter (testEdgeAngle): the edge's unit direction e (rest positions) with
/// |e·d| < |cos angle| (d the normalised `direction`; angle in degrees).
[[nodiscard]] bool edge_passes_angle(const Vec3& a, const Vec3& b, const Vec3& unit_direction, double angle_degrees);
/// SphereROI's triangle filter (testTriangleAngle): n = (c−a)×(b−a) normalised, n·N < cos angle
/// (N the normalised `normal`; angle in degrees). As SOFA: the test keeps the triangles whose
/// normal is FAR from N, with n of the opposite winding.
[[nodiscard]] bool triangle_passes_angle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& unit_normal,
                                         double angle_degrees);

}  // namespace penalty
