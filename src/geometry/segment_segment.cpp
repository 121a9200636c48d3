#include "penalty/geometry/segment_segment.hpp"

#include <algorithm>

namespace penalty {

namespace {
double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }
}  // namespace

SegmentSegmentResult segment_segment_closest_points(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    SegmentSegmentResult r;
    const Vec3 d1 = b - a;
    const Vec3 d2 = d - c;
    const Vec3 w = a - c;
    const double aa = d1.squaredNorm();
    const double ee = d2.squaredNorm();
    const double f = d2.dot(w);
    constexpr double kTiny = 1e-300;
    double s = 0.0;
    double t = 0.0;
    if (aa <= kTiny && ee <= kTiny) {
        // both degenerate: two points
        r.parallel = true;
    } else if (aa <= kTiny) {
        // first segment is a point
        t = clamp01(f / ee);
        r.parallel = true;
    } else {
        const double cc = d1.dot(w);
        if (ee <= kTiny) {
            // second segment is a point
            s = clamp01(-cc / aa);
            r.parallel = true;
        } else {
            const double bb = d1.dot(d2);
            const double denom = aa * ee - bb * bb;  // >= 0
            // non-parallel: unconstrained minimiser on the first segment, clamped
            if (denom > 1e-14 * aa * ee) {
                s = clamp01((bb * f - cc * ee) / denom);
            } else {
                s = 0.0;
                r.parallel = true;
            }
            // best t for this s, then re-clamp s for the clamped t
            const double tnom = bb * s + f;
            if (tnom < 0.0) {
                t = 0.0;
                s = clamp01(-cc / aa);
            } else if (tnom > ee) {
                t = 1.0;
                s = clamp01((bb - cc) / aa);
            } else {
                t = tnom / ee;
            }
        }
    }
    r.s = s;
    r.t = t;
    r.p = a + s * d1;
    r.q = c + t * d2;
    r.distance_squared = (r.q - r.p).squaredNorm();
    return r;
}

}  // namespace penalty
