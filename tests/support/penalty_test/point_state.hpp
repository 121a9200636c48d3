#pragma once
/// @file
/// A Vec3 state holding given points, initialised (velocities, forces and work vectors sized).

#include "penalty/mechanics/mechanical_object.hpp"

#include <utility>
#include <vector>

namespace penalty::test {

inline Vec3Object state_at(std::vector<Vec3> points) {
    Vec3Object s;
    s.position = std::move(points);
    s.init();
    return s;
}

}  // namespace penalty::test
