#include "penalty/mechanics/oriented_box.hpp"

#include "sofa_vector_ops.hpp"

#include <cmath>

namespace penalty {

using sofa_vec::cross;
using sofa_vec::dot3;
using sofa_vec::normalized;

// BoxROI::computeOrientedBoxes.
OrientedBox::OrientedBox(const Vec3& p0, const Vec3& p1, const Vec3& p2, double depth)
    : p0_(p0), p2_(p2), depth_(depth) {
    normal_ = normalized(cross(p1 - p0, p2 - p0));
    const Vec3 p3 = p0 + (p2 - p1);
    const Vec3 p6 = p2 + sofa_vec::scaled(normal_, depth);
    plane0_ = normalized(cross(p1 - p0, normal_));
    plane1_ = normalized(cross(p2 - p3, p6 - p3));
    plane2_ = normalized(cross(p3 - p0, normal_));
    plane3_ = normalized(cross(p2 - p1, p6 - p2));
    width_ = std::fabs(dot3(p2 - p0, plane0_));
    length_ = std::fabs(dot3(p2 - p0, plane2_));
}

// BoxROI::isPointInOrientedBox.
bool OrientedBox::contains(const Vec3& p) const {
    const Vec3 pv0 = p - p0_;
    const Vec3 pv1 = p - p2_;
    if (!(std::fabs(dot3(pv0, plane0_)) <= width_ && std::fabs(dot3(pv1, plane1_)) <= width_)) return false;
    if (!(std::fabs(dot3(pv0, plane2_)) <= length_ && std::fabs(dot3(pv1, plane3_)) <= length_)) return false;
    return std::fabs(dot3(pv0, normal_)) <= std::fabs(depth_ / 2);
}

}  // namespace penalty
