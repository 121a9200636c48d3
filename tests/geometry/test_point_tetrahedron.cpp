// PointTetrahedron: signed distance to a tetrahedron against sampling of its faces.
#include "penalty/geometry/point_tetrahedron.hpp"
#include "sampling_references.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace penalty {
namespace {

using namespace test_geometry;

TEST(PointTetrahedron, SignedDistanceMatchesFaceSampling) {
    std::mt19937 g(31);
    int inside = 0, outside = 0;
    for (int s = 0; s < 300; ++s) {
        const Vec3 v[4] = {rand_vec(g, 1), rand_vec(g, 1), rand_vec(g, 1), rand_vec(g, 1)};
        const Vec3 p = rand_vec(g, 0.8);
        const auto r = point_tetrahedron_signed_distance(p, v[0], v[1], v[2], v[3]);
        const int f[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
        double brute = std::numeric_limits<double>::infinity();
        for (const auto& fk : f) brute = std::min(brute, brute_point_triangle(p, v[fk[0]], v[fk[1]], v[fk[2]], 120));
        EXPECT_LE(std::abs(r.signed_distance), brute + 1e-12);
        EXPECT_GE(std::abs(r.signed_distance), brute - 2e-2);
        EXPECT_NEAR((p - (r.closest + r.signed_distance * r.normal)).norm(), 0.0, 1e-10);
        (r.inside ? inside : outside)++;
    }
    EXPECT_GE(inside, 10);
    EXPECT_GE(outside, 100);
}

}  // namespace
}  // namespace penalty
