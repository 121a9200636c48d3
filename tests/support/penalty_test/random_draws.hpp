#pragma once
// Seeded random draws in a fixed order. C++ leaves the order of evaluation of a call's arguments
// (and of an operator's operands) open: Vec3(u(g), u(g), u(g)) draws z first under g++ and x first
// under clang, so a seeded test would see other data under each compiler. These helpers draw in
// g++'s order (right to left), the data the seeded tests' bounds were set on, under every compiler.
#include "penalty/core/types.hpp"

#include <random>

namespace penalty::test {

/// Vec3(d(g), d(g), d(g)) as g++ evaluates it: z, then y, then x.
template <class Distribution, class Generator>
Vec3 draw_vec3(Distribution& d, Generator& g) {
    const double z = d(g);
    const double y = d(g);
    const double x = d(g);
    return Vec3(x, y, z);
}

}  // namespace penalty::test
