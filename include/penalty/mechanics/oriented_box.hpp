#pragma once
/// @file
/// SOFA's BoxROI oriented box (BoxROI::computeOrientedBoxes, isPointInOrientedBox): the
/// parallelogram p0, p1, p2, p3 = p0 + (p2 − p1) extruded by depth/2 on each side along its unit
/// normal n = (p1 − p0) × (p2 − p0)/|…|. With the side normals m0 = (p1 − p0) × n,
/// m1 = (p2 − p3) × (p6 − p3), m2 = (p3 − p0) × n, m3 = (p2 − p1) × (p6 − p2) (each normalised,
/// p6 = p2 + n·depth), w = |(p2 − p0)·m0| and l = |(p2 − p0)·m2|, a point p is inside when
/// |(p − p0)·m0| ≤ w, |(p − p2)·m1| ≤ w, |(p − p0)·m2| ≤ l, |(p − p2)·m3| ≤ l and
/// |(p − p0)·n| ≤ |depth/2|, every product as SOFA rounds it. (PlaneROI's box, regions_of_interest.hpp,
/// is the same shape with other rounding.)

#include "penalty/core/types.hpp"

namespace penalty {

class OrientedBox {
public:
    /// SOFA's ten numbers: p0 (3), p1 (3), p2 (3), depth.
    OrientedBox(const Vec3& p0, const Vec3& p1, const Vec3& p2, double depth);
    [[nodiscard]] bool contains(const Vec3& p) const;

private:
    Vec3 p0_, p2_, normal_, plane0_, plane1_, plane2_, plane3_;
    double width_, length_, depth_;
};

}  // namespace penalty
