#pragma once
/// @file
/// A 3 × 3-point cloth of 8 triangles in the plane y = 0 (points 1 m apart along x, 1.2 m along
/// z), for the tests of the triangle force fields and masses.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/topology.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace penalty::test {

struct Cloth {
    Vec3Object state;
    MeshTopology topology;
    Cloth() {
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) state.position.emplace_back(i, 0.0, 1.2 * j);
        state.init();
        topology.set_triangles(
            {{0, 1, 4}, {0, 4, 3}, {1, 2, 4}, {2, 5, 4}, {3, 4, 6}, {4, 7, 6}, {4, 5, 8}, {4, 8, 7}});
    }
    /// Stretches the cloth and lifts its points out of the plane, each by its own amount.
    void deform() {
        for (std::size_t i = 0; i < state.position.size(); ++i)
            state.position[i] = Vec3(1.1 * state.position[i].x(), 0.2 * std::sin(1.0 + static_cast<double>(i)),
                                     0.9 * state.position[i].z() + 0.02 * static_cast<double>(i));
    }
    /// The force of `ff` alone at the state's positions and velocities, flat (N).
    Eigen::VectorXd force(BaseForceField& ff) {
        std::fill(state.force.begin(), state.force.end(), Vec3::Zero());
        ff.accumulate_force();
        return Vec3Object::flat(state.force);
    }
};

}  // namespace penalty::test
