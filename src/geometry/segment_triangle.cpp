#include "penalty/geometry/segment_triangle.hpp"

#include <cmath>

namespace penalty {

std::optional<SegmentTriangleCrossing> segment_triangle_crossing(const Vec3& p0, const Vec3& p1, const Vec3& p2,
                                                                 const Vec3& q0, const Vec3& q1) {
    Mat3 m;
    m.col(0) = p1 - p0;
    m.col(1) = p2 - p0;
    m.col(2) = -(q1 - q0);
    const double det = m.determinant();
    if (!(std::abs(det) > 1e-300)) return std::nullopt;
    const Vec3 x = m.inverse() * (q0 - p0);
    const double u = x[0];
    const double v = x[1];
    const double w = x[2];
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && w >= 0.0 && w <= 1.0) {
        SegmentTriangleCrossing c;
        c.u = u;
        c.v = v;
        c.w = w;
        c.point = q0 + w * (q1 - q0);
        return c;
    }
    return std::nullopt;
}

}  // namespace penalty
