// Beyond SOFA: the Cylinder pairs (NewProximity / MinProximity semantics) and Tetrahedron–Point.
//
// Cylinder pairs: closest points between the *solid* cylinder and the other element.
//   contact iff d < R (strict), R = A + c1 + c2 (+ sphere radius), d = signed distance
//   (negative when a sphere centre is inside the cylinder, or minus the approximate
//   penetration depth for overlapping convex pairs);
//   value = d − Cfull, Cfull = C + c1 + c2 (+ sphere radius);
//   normal: unit, from the cylinder toward the other element;
//   id = e1 · size(model 2) + e2: one contact per (cylinder, element) pair. Both elements are
//   convex, so the pair has a single closest-point pair: this is "one contact per feature
//   pair" (see docs/collision.md).
#include "kernels.hpp"

#include "penalty/geometry/convex_distance.hpp"
#include "penalty/geometry/point_cylinder.hpp"
#include "penalty/geometry/point_tetrahedron.hpp"
#include "penalty/geometry/segment_segment.hpp"

#include <array>
#include <span>

namespace penalty::detail {

namespace {

std::int64_t pair_id(const PairCtx& c) { return std::int64_t(c.e1) * std::int64_t(c.m2.size()) + std::int64_t(c.e2); }

bool min_semantics(const PairCtx& c) { return c.p.method == IntersectionMethod::MinProximity; }

// distance (or minus penetration) between a cylinder and a convex shape, with the points and
// the normal from the cylinder toward the shape
struct ConvexContact {
    double d;
    Vec3 pa, pb, n;
    bool ok;
};

ConvexContact convex_contact(const ConvexShape& a, const ConvexShape& b, std::span<const Vec3> candidates) {
    const ConvexDistanceResult g = convex_distance(a, b);
    const Vec3 d = g.point_b - g.point_a;
    const double len = d.norm();
    if (!g.overlapping && len > 0.0) return {len, g.point_a, g.point_b, d / len, true};
    // overlapping (or exactly touching): approximate penetration along candidate directions
    const ConvexPenetrationResult p = convex_penetration(a, b, candidates);
    return {-p.depth, p.point_a, p.point_b, p.normal, true};
}

}  // namespace

int cylinder_sphere(PairCtx& c) {
    const auto& cm = static_cast<const CylinderModel&>(c.m1);
    const SphereElem s = sphere_elem(c.m2, c.e2);
    const PointCylinderResult r = point_cylinder_signed_distance(s.c, cm.shape(c.e1));
    const double sk = skins(c);
    if (!(r.signed_distance < c.p.alarm_distance + sk + s.r)) return 0;
    // r.normal is always a unit vector (outward normal when the centre is inside): never NaN
    const Vec3 p1 = min_semantics(c) ? s.point_by_normal(r.normal) : s.c;
    return push(c, pair_id(c), r.closest, p1, r.normal, r.signed_distance - (c.p.contact_distance + sk + s.r));
}

int cylinder_cylinder(PairCtx& c) {
    const auto& m1 = static_cast<const CylinderModel&>(c.m1);
    const auto& m2 = static_cast<const CylinderModel&>(c.m2);
    const CylinderShape a = m1.shape(c.e1);
    const CylinderShape b = m2.shape(c.e2);
    // candidate separating directions for the overlapping case (fixed size: no allocation)
    const SegmentSegmentResult ss =
        segment_segment_closest_points(a.center - a.half_height * a.axis, a.center + a.half_height * a.axis,
                                       b.center - b.half_height * b.axis, b.center + b.half_height * b.axis);
    const Vec3 w = ss.q - ss.p;
    const std::array<Vec3, 8> cand = {a.axis, b.axis, a.axis.cross(b.axis), b.center - a.center,
                                      w - w.dot(a.axis) * a.axis, w - w.dot(b.axis) * b.axis,
                                      // radial fallbacks (coincident or concentric axes give zero vectors above)
                                      m1.radial_direction(c.e1), m2.radial_direction(c.e2)};
    const ConvexContact k = convex_contact(ConvexShape::make_cylinder(a), ConvexShape::make_cylinder(b), cand);
    const double sk = skins(c);
    if (!(k.d < c.p.alarm_distance + sk)) return 0;
    return push(c, pair_id(c), k.pa, k.pb, k.n, k.d - (c.p.contact_distance + sk));
}

int cylinder_triangle(PairCtx& c) {
    const auto& m1 = static_cast<const CylinderModel&>(c.m1);
    const auto& t = static_cast<const TriangleModel&>(c.m2);
    const CylinderShape a = m1.shape(c.e1);
    const Vec3 &p0 = t.p(c.e2, 0), &p1 = t.p(c.e2, 1), &p2 = t.p(c.e2, 2);
    // candidate separating directions (fixed size: no allocation): the face normal, the axis, the
    // centre offset, per edge e (e × axis) and its radial direction ⟂ axis, a radial fallback
    std::array<Vec3, 10> cand;
    cand[0] = (p1 - p0).cross(p2 - p0);
    cand[1] = a.axis;
    cand[2] = (p0 + p1 + p2) / 3.0 - a.center;
    std::size_t k_cand = 3;
    for (const Vec3& e : {Vec3(p1 - p0), Vec3(p2 - p1), Vec3(p0 - p2)}) {
        const Vec3 x = e.cross(a.axis);
        cand[k_cand++] = x;
        cand[k_cand++] = x.cross(a.axis);
    }
    cand[k_cand] = m1.radial_direction(c.e1);
    const ConvexContact k = convex_contact(ConvexShape::make_cylinder(a), ConvexShape::triangle(p0, p1, p2), cand);
    const double sk = skins(c);
    if (!(k.d < c.p.alarm_distance + sk)) return 0;
    return push(c, pair_id(c), k.pa, k.pb, k.n, k.d - (c.p.contact_distance + sk));
}

int tetrahedron_point(PairCtx& c) {
    const auto& tm = static_cast<const TetrahedronModel&>(c.m1);
    const Vec3& P = static_cast<const PointModel&>(c.m2).point(c.e2);
    const PointTetrahedronResult r =
        point_tetrahedron_signed_distance(P, tm.p(c.e1, 0), tm.p(c.e1, 1), tm.p(c.e1, 2), tm.p(c.e1, 3));
    const double sk = skins(c);
    if (!(r.signed_distance < c.p.alarm_distance + sk)) return 0;
    Vec3 n = r.normal;
    if (r.signed_distance == 0.0 && !r.inside) {
        // on a flat tetrahedron: zero-distance policy
        if (!unit_normal(c, Vec3::Zero(), 0.0, Guard::None, n)) return 0;
    }
    return push(c, c.e2, r.closest, P, n, r.signed_distance - (c.p.contact_distance + sk));
}

}  // namespace penalty::detail
