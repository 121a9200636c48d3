#pragma once
// Seeded samples of the projective constraints' tests: a state of random points and velocities, a random vector.
#include "penalty/mechanics/mechanical_object.hpp"

#include <Eigen/Core>

#include <random>

namespace penalty::test_samples {

inline Vec3Object random_moving_points(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    Vec3Object s;
    for (std::size_t i = 0; i < n; ++i) s.position.emplace_back(u(rng), u(rng), u(rng));
    s.init();
    for (std::size_t i = 0; i < n; ++i) s.velocity[i] = Vec3(u(rng), u(rng), u(rng));
    return s;
}

inline Eigen::VectorXd random_vector(Eigen::Index n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) v[i] = u(rng);
    return v;
}

}  // namespace penalty::test_samples
