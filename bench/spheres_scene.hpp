#pragma once
// The `spheres` scene of penalty_bench_detection, in one place for bench_detection.cpp and the
// Bullet comparison (bench_detection_bullet.cpp): n spheres of one radius, uniform in a cube whose
// side grows as n^(1/3), so the density (1e5 centres per m³, ~1.4 neighbours each) does not
// depend on n. Detected with NewProximity: a pair is reported when the centres are closer than
// 2·radius + alarm distance (np_sphere_sphere, model skins 0).
#include "../tests/collision/detection_scenes.hpp"
#include "penalty/collision/intersection.hpp"

#include <cmath>
#include <cstddef>
#include <random>

namespace penalty::bench {

inline constexpr double kSphereRadius = 0.005;           ///< m
inline constexpr double kSphereAlarmDistance = 0.005;    ///< IntersectionParams::alarm_distance, m
inline constexpr double kSphereContactDistance = 0.002;  ///< IntersectionParams::contact_distance, m

/// The sphere centres for n spheres (seed 1000, the same cloud for every run).
inline Vec3State sphere_cloud(std::size_t n) {
    std::mt19937 g(1000);
    const double half = 0.5 * std::cbrt(double(n) / 1e5);  // half the cube side, m
    return test::random_cloud(n, half, g);
}

/// The one self-colliding model of the scene.
inline CollisionModelParams sphere_model_params() {
    CollisionModelParams p;
    p.name = "spheres";
    p.node = 0;
    p.self_collision = true;
    return p;
}

/// NewProximity with the scene's alarm and contact distances.
inline IntersectionParams sphere_intersection_params() {
    IntersectionParams p = IntersectionParams::new_proximity();
    p.alarm_distance = kSphereAlarmDistance;
    p.contact_distance = kSphereContactDistance;
    return p;
}

}  // namespace penalty::bench
