#pragma once
// The cases of the vector kernels' tests (test_springs.cpp, test_tetrahedron_large_lanes.cpp, test_kernel_path.cpp):
// random springs and tetrahedra with degenerate ones, dx and df entries of every sign, bitwise comparisons.
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

namespace penalty::test_kernel_cases {

/// Bitwise equality of two Vec3 lists (−0 differs from +0, NaNs compare by payload).
inline void expect_same_bits(const std::vector<Vec3>& expected, const std::vector<Vec3>& actual,
                             const std::string& what) {
    ASSERT_EQ(expected.size(), actual.size()) << what;
    for (std::size_t i = 0; i < expected.size(); ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(0, std::memcmp(&expected[i][c], &actual[i][c], sizeof(double)))
                << what << ": DOF " << i << " component " << c << ": " << expected[i][c] << " against " << actual[i][c];
}

/// dx and df entries of every sign and size, zeros of both signs included.
inline double product_entry(std::mt19937& rng) {
    switch (rng() % 8) {
        case 0:
            return 0.0;
        case 1:
            return -0.0;
        case 2:
            return std::ldexp(std::uniform_real_distribution<double>(-1, 1)(rng), -40);
        default:
            return std::uniform_real_distribution<double>(-3, 3)(rng);
    }
}

/// With `special`, one draw in `period` a subnormal, one −∞ and one a NaN (`value` set, true);
/// else false, and the caller draws an ordinary value.
inline bool draw_special(std::mt19937& rng, bool special, unsigned period, double& value) {
    if (!special) return false;
    switch (rng() % period) {
        case 0:
            value = std::numeric_limits<double>::denorm_min() * double(1 + rng() % 1000);
            return true;
        case 1:
            value = -std::numeric_limits<double>::infinity();
            return true;
        case 2:
            value = std::numeric_limits<double>::quiet_NaN();
            return true;
        default:
            return false;
    }
}

inline void fill_products(Vec3Object& s, std::mt19937& rng) {
    for (auto& d : s.dx) d = Vec3(product_entry(rng), product_entry(rng), product_entry(rng));
    for (auto& d : s.df) d = Vec3(product_entry(rng), product_entry(rng), product_entry(rng));
}

/// DOFs whose df the product changed (the comparison is not vacuous).
inline int changed_dofs(const std::vector<Vec3>& before, const std::vector<Vec3>& after) {
    int n = 0;
    for (std::size_t i = 0; i < before.size(); ++i) n += before[i] != after[i] ? 1 : 0;
    return n;
}

inline bool avx_available() { return kernel_path_supported(KernelPath::avx); }

/// One spring list on two states (or one), with zero-length springs (coincident ends, a spring
/// from a DOF to itself), springs at the null length, long and short springs.
struct SpringCase {
    Vec3Object s1, s2;
    std::vector<Spring> springs;
};

inline void build_springs(SpringCase& c, std::mt19937& rng, std::size_t count, bool two_states) {
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 9; ++i) c.s1.position.emplace_back(u(rng), u(rng), u(rng));
    for (int i = 0; i < 9; ++i) c.s1.velocity.emplace_back(u(rng), u(rng), u(rng));
    c.s1.position[3] = c.s1.position[2];                      // coincident DOFs
    c.s1.position[5] = c.s1.position[4] + Vec3(1e-10, 0, 0);  // below the null length
    c.s1.position[7] = c.s1.position[6] + Vec3(0, 0, 1e-6);   // short, but a spring
    c.s1.init();
    c.s2.position = c.s1.position;
    c.s2.velocity = c.s1.velocity;
    for (auto& p : c.s2.position) p += Vec3(1e-3, 0, 0) * u(rng);
    c.s2.position[0] = c.s1.position[0];
    c.s2.init();
    for (std::size_t k = 0; k < count; ++k) {
        Index a = static_cast<Index>(rng() % 9);
        Index b = static_cast<Index>(rng() % 9);
        if (k % 5 == 0) b = a;  // zero length on one state
        if (k % 7 == 1) std::tie(a, b) = std::pair<Index, Index>{2, 3};
        if (k % 7 == 2) std::tie(a, b) = std::pair<Index, Index>{4, 5};
        if (k % 7 == 3) std::tie(a, b) = std::pair<Index, Index>{6, 7};
        c.springs.push_back(
            {a, b, 1000 * std::abs(u(rng)), 0.5 * std::abs(u(rng)), two_states ? 0.0 : std::abs(u(rng))});
    }
}

}  // namespace penalty::test_kernel_cases
