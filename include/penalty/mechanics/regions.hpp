#pragma once
/// @file
/// Regions of interest: the points inside axis-aligned boxes (SOFA's BoxROI).

#include "penalty/core/types.hpp"
#include "penalty/mechanics/topology.hpp"

#include <span>
#include <vector>

namespace penalty {

/// A closed axis-aligned box [min, max] (m).
struct AlignedBox {
    Vec3 min;
    Vec3 max;
    /// From SOFA's six numbers xmin ymin zmin xmax ymax zmax; each pair is put in order
    /// (BoxROI::roiInit swaps a min written above its max).
    static AlignedBox from_corners(const Vec3& a, const Vec3& b);
    /// Bounds included (BoxROI::isPointInAlignedBox).
    [[nodiscard]] bool contains(const Vec3& p) const;
};

/// SOFA's BoxROI `indices`: the indices, increasing, of the points inside at least one box.
[[nodiscard]] std::vector<PointId> points_in_boxes(std::span<const Vec3> points, std::span<const AlignedBox> boxes);

}  // namespace penalty
