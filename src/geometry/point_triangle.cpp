#include "penalty/geometry/point_triangle.hpp"

#include "penalty/geometry/point_segment.hpp"

#include <algorithm>

namespace penalty {

namespace {

PointTriangleResult make(const Vec3& p, const Vec3& q, const Vec3& w, TriangleFeature f) {
    PointTriangleResult r;
    r.closest = q;
    r.barycentric = w;
    r.distance_squared = (p - q).squaredNorm();
    r.feature = f;
    return r;
}

// closest point over the three edges (zero-area triangle)
PointTriangleResult degenerate_closest(const Vec3& p, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const PointSegmentResult e01 = point_segment_closest_point(p, p0, p1);
    const PointSegmentResult e12 = point_segment_closest_point(p, p1, p2);
    const PointSegmentResult e20 = point_segment_closest_point(p, p2, p0);
    PointTriangleResult r;
    r.degenerate = true;
    r.closest = e01.closest;
    r.distance_squared = e01.distance_squared;
    r.barycentric = Vec3(1.0 - e01.t, e01.t, 0.0);
    r.feature = TriangleFeature::E01;
    if (e12.distance_squared < r.distance_squared) {
        r.closest = e12.closest;
        r.distance_squared = e12.distance_squared;
        r.barycentric = Vec3(0.0, 1.0 - e12.t, e12.t);
        r.feature = TriangleFeature::E12;
    }
    if (e20.distance_squared < r.distance_squared) {
        r.closest = e20.closest;
        r.distance_squared = e20.distance_squared;
        r.barycentric = Vec3(e20.t, 0.0, 1.0 - e20.t);
        r.feature = TriangleFeature::E20;
    }
    return r;
}

}  // namespace

PointTriangleResult point_triangle_closest_point(const Vec3& p, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const Vec3 ab = p1 - p0;
    const Vec3 ac = p2 - p0;
    const double l2max = std::max({ab.squaredNorm(), ac.squaredNorm(), (p2 - p1).squaredNorm()});
    if (ab.cross(ac).squaredNorm() <= 1e-28 * l2max * l2max) {
        return degenerate_closest(p, p0, p1, p2);
    }
    // Voronoi regions of the vertices, then of the edges, else the face
    const Vec3 ap = p - p0;
    const double d1 = ab.dot(ap);
    const double d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return make(p, p0, Vec3(1, 0, 0), TriangleFeature::V0);

    const Vec3 bp = p - p1;
    const double d3 = ab.dot(bp);
    const double d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3) return make(p, p1, Vec3(0, 1, 0), TriangleFeature::V1);

    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double t = d1 / (d1 - d3);
        return make(p, p0 + t * ab, Vec3(1.0 - t, t, 0.0), TriangleFeature::E01);
    }

    const Vec3 cp = p - p2;
    const double d5 = ab.dot(cp);
    const double d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6) return make(p, p2, Vec3(0, 0, 1), TriangleFeature::V2);

    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double t = d2 / (d2 - d6);
        return make(p, p0 + t * ac, Vec3(1.0 - t, 0.0, t), TriangleFeature::E20);
    }

    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return make(p, p1 + t * (p2 - p1), Vec3(0.0, 1.0 - t, t), TriangleFeature::E12);
    }

    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom;
    const double w = vc * denom;
    return make(p, p0 + v * ab + w * ac, Vec3(1.0 - v - w, v, w), TriangleFeature::Face);
}

}  // namespace penalty
