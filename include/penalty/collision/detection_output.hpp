#pragma once
/// @file
/// SOFA's DetectionOutput (spec §5.1): one proximity pair between element e1 of model 1 and
/// element e2 of model 2 (models in the intersector's registered order).

#include "penalty/core/index_types.hpp"
#include "penalty/core/types.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace penalty {

/// One detected proximity. Plain data.
struct DetectionOutput {
    ElementIndex elem1;   ///< element of model 1
    ElementIndex elem2;   ///< element of model 2
    std::int64_t id = 0;  ///< deduplication key: per id the response keeps the first minimal value
    /// point[0] on/for element 1, point[1] on/for element 2 (world, m). Which point (surface or
    /// centre) depends on the method and pair, see docs/collision.md.
    std::array<Vec3, 2> point = {Vec3::Zero(), Vec3::Zero()};
    Vec3 normal = Vec3::UnitX();  ///< unit, from element 1 toward element 2
    double value = 0.0;           ///< distance minus the full contact distance (m); < 0 = closer
                                  ///< than desired
};

using DetectionOutputList = std::vector<DetectionOutput>;

}  // namespace penalty
