#pragma once
/// @file
/// A Vec3 state holding given points, initialised (velocities, forces and work vectors sized), and
/// the force of one field on it.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"

#include <algorithm>

#include <utility>
#include <vector>

namespace penalty::test {

inline Vec3Object state_at(std::vector<Vec3> points) {
    Vec3Object s;
    s.position = std::move(points);
    s.init();
    return s;
}

/// The force of `field` alone on `s`, at the state's positions and velocities.
inline std::vector<Vec3> force_of(BaseForceField& field, Vec3Object& s) {
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    field.accumulate_force();
    return s.force;
}

}  // namespace penalty::test
