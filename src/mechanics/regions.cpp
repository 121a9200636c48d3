#include "penalty/mechanics/regions.hpp"

#include <algorithm>

namespace penalty {

AlignedBox AlignedBox::from_corners(const Vec3& a, const Vec3& b) { return {a.cwiseMin(b), a.cwiseMax(b)}; }

bool AlignedBox::contains(const Vec3& p) const {
    for (int k = 0; k < 3; ++k)
        if (p[k] < min[k] || p[k] > max[k]) return false;
    return true;
}

std::vector<PointId> points_in_boxes(std::span<const Vec3> points, std::span<const AlignedBox> boxes) {
    std::vector<PointId> inside;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& p = points[i];
        if (std::any_of(boxes.begin(), boxes.end(), [&](const AlignedBox& b) { return b.contains(p); }))
            inside.push_back(static_cast<PointId>(i));
    }
    return inside;
}

}  // namespace penalty
