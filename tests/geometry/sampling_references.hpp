#pragma once
// Dense-sampling references of the closest-point tests (tests/geometry/test_<primitive pair>.cpp):
// seeded random vectors, a point-triangle distance by barycentric sampling, a cylinder's surface
// samples.
#include "penalty/geometry/convex_distance.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace penalty::test_geometry {

inline Vec3 rand_vec(std::mt19937& g, double s) {
    std::uniform_real_distribution<double> u(-s, s);
    return Vec3(u(g), u(g), u(g));
}
inline Vec3 rand_unit(std::mt19937& g) {
    Vec3 v;
    do {
        v = rand_vec(g, 1.0);
    } while (v.squaredNorm() < 1e-3 || v.squaredNorm() > 1.0);
    return v.normalized();
}

// distance from p to the triangle by dense barycentric sampling (reference)
inline double brute_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
            const double u = double(i) / n, v = double(j) / n;
            best = std::min(best, (p - (a + u * (b - a) + v * (c - a))).norm());
        }
    return best;
}

// surface samples of a solid cylinder (side grid and both caps)
inline std::vector<Vec3> cylinder_surface(const CylinderShape& c, int n) {
    std::vector<Vec3> out;
    const Vec3 e1 = any_orthogonal(c.axis);
    const Vec3 e2 = c.axis.cross(e1);
    for (int i = 0; i < 4 * n; ++i) {
        const double th = 2.0 * std::numbers::pi * i / (4 * n);
        const Vec3 radial = std::cos(th) * e1 + std::sin(th) * e2;
        for (int j = 0; j <= n; ++j) {
            const double y = -c.half_height + 2.0 * c.half_height * j / n;
            out.push_back(c.center + y * c.axis + c.radius * radial);
        }
        for (int k = 0; k <= n; ++k) {
            const double rr = c.radius * k / n;
            out.push_back(c.center + c.half_height * c.axis + rr * radial);
            out.push_back(c.center - c.half_height * c.axis + rr * radial);
        }
    }
    return out;
}

}  // namespace penalty::test_geometry
