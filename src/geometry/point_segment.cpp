#include "penalty/geometry/point_segment.hpp"

#include <algorithm>

namespace penalty {

PointSegmentResult point_segment_closest_point(const Vec3& p, const Vec3& a, const Vec3& b) {
    PointSegmentResult r;
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    double t = 0.0;
    // degenerate segment: the point a (t = 0)
    if (len2 > 1e-300) {
        t = (p - a).dot(ab) / len2;
        if (!(t > 0.0)) t = 0.0;  // also catches NaN
        if (t > 1.0) t = 1.0;
    }
    r.t = t;
    r.closest = a + t * ab;
    r.distance_squared = (p - r.closest).squaredNorm();
    r.feature = t <= 0.0 ? SegmentFeature::A : (t >= 1.0 ? SegmentFeature::B : SegmentFeature::Interior);
    return r;
}

}  // namespace penalty
