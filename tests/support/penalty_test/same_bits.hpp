#pragma once
/// @file
/// Bitwise equality of doubles and vectors, for the tests that require results to the last bit
/// (SOFA's trajectories, thread counts, detection paths): +0 and −0 differ, a NaN equals only the
/// same NaN.

#include "penalty/core/types.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

namespace penalty::test {

inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

inline bool same_bits(const Vec3& a, const Vec3& b) {
    return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

inline bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

}  // namespace penalty::test
