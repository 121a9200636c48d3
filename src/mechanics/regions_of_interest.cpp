#include "penalty/mechanics/regions_of_interest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace penalty {

namespace {

/// SOFA's Vec::normalize: divided by its norm when the norm exceeds machine epsilon, else kept.
Vec3 normalized_as_sofa(Vec3 v) {
    const double n = v.norm();
    if (n > std::numeric_limits<double>::epsilon()) v /= n;
    return v;
}

}  // namespace

// PlaneROI::computePlane (one plane).
PlaneRegion::PlaneRegion(const Vec3& p0, const Vec3& p1, const Vec3& p2, double depth)
    : p0_(p0), p2_(p2), depth_(depth) {
    normal_ = normalized_as_sofa((p1 - p0).cross(p2 - p0));
    const Vec3 p3 = p0 + (p2 - p1);
    const Vec3 p4 = p0 + normal_ * (depth / 2);
    const Vec3 p6 = p2 + normal_ * (depth / 2);
    side0_ = normalized_as_sofa((p1 - p0).cross(p4 - p0));
    side1_ = normalized_as_sofa((p2 - p3).cross(p6 - p3));
    side2_ = normalized_as_sofa((p3 - p0).cross(p4 - p0));
    side3_ = normalized_as_sofa((p2 - p1).cross(p6 - p2));
    width_ = std::fabs((p2 - p0).dot(side0_));
    length_ = std::fabs((p2 - p0).dot(side2_));
}

// PlaneROI::isPointInPlane.
bool PlaneRegion::contains(const Vec3& p) const {
    const Vec3 from0 = p - p0_;
    const Vec3 from2 = p - p2_;
    if (!(std::fabs(from0.dot(side0_)) <= width_ && std::fabs(from2.dot(side1_)) <= width_)) return false;
    if (!(std::fabs(from0.dot(side2_)) <= length_ && std::fabs(from2.dot(side3_)) <= length_)) return false;
    return std::fabs(from0.dot(normal_)) <= std::fabs(depth_ / 2);
}

namespace {

template <class Element>
void select_elements(std::span<const Vec3> points, const std::vector<Element>& elements, const PointInRegion& inside,
                     ElementTest test, const std::function<bool(const Element&)>& filter, std::vector<PointId>& out) {
    for (std::size_t i = 0; i < elements.size(); ++i) {
        const Element& e = elements[i];
        // an element with a point past the list is never inside (SOFA would read past its end)
        if (std::any_of(e.begin(), e.end(), [&](PointId id) { return id < 0 || std::size_t(id) >= points.size(); }))
            continue;
        bool in = false;
        if (test != ElementTest::center) {
            in = true;
            for (PointId id : e)
                if (!inside(points[static_cast<std::size_t>(id)])) {
                    in = false;
                    break;
                }
        }
        if (test == ElementTest::center || (test == ElementTest::all_points_or_center && !in)) {
            // BaseROI's getCenter: Σ points / n
            Vec3 center = Vec3::Zero();
            for (PointId id : e) center += points[static_cast<std::size_t>(id)];
            center = center / static_cast<double>(e.size());
            in = inside(center);
        }
        if (in && filter) in = filter(e);
        if (in) out.push_back(static_cast<PointId>(i));
    }
}

}  // namespace

RoiSelection select_in_region(std::span<const Vec3> points, const RoiElements& elements, const PointInRegion& inside,
                              ElementTest test, const ElementFilters& filters) {
    RoiSelection s;
    for (std::size_t i = 0; i < points.size(); ++i)
        if (inside(points[i])) s.points.push_back(static_cast<PointId>(i));
    select_elements<Edge>(points, elements.edges, inside, test, filters.edge, s.edges);
    select_elements<Triangle>(points, elements.triangles, inside, test, filters.triangle, s.triangles);
    select_elements<Quad>(points, elements.quads, inside, test, {}, s.quads);
    select_elements<Tetrahedron>(points, elements.tetrahedra, inside, test, {}, s.tetrahedra);
    select_elements<Hexahedron>(points, elements.hexahedra, inside, test, {}, s.hexahedra);
    return s;
}

// SphereROI::testEdgeAngle.
bool edge_passes_angle(const Vec3& a, const Vec3& b, const Vec3& unit_direction, double angle_degrees) {
    const Vec3 e = normalized_as_sofa(b - a);
    return std::fabs(e.dot(unit_direction)) < std::fabs(std::cos(angle_degrees * std::numbers::pi / 180.0));
}

// SphereROI::testTriangleAngle.
bool triangle_passes_angle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& unit_normal, double angle_degrees) {
    const Vec3 n = normalized_as_sofa((c - a).cross(b - a));
    return n.dot(unit_normal) < std::cos(angle_degrees * std::numbers::pi / 180.0);
}

}  // namespace penalty
