#pragma once
/// @file
/// Two 32-bit indices (an element of each of two models, two models, two surfaces) as one 64-bit
/// key, the first in the high half: ascending keys sort by the first index, then the second, and
/// radix sorts and hash maps take them as plain integers.
#include <cstdint>

namespace penalty::pair_key {

/// first << 32 | second (each below 2³²).
constexpr std::uint64_t make(std::uint64_t first, std::uint64_t second) { return first << 32 | second; }
/// The key of {min(a, b), max(a, b)}: an unordered pair.
constexpr std::uint64_t make_unordered(std::uint64_t a, std::uint64_t b) { return a < b ? make(a, b) : make(b, a); }
/// The index in the high half.
constexpr std::uint32_t first(std::uint64_t key) { return static_cast<std::uint32_t>(key >> 32); }
/// The index in the low half.
constexpr std::uint32_t second(std::uint64_t key) { return static_cast<std::uint32_t>(key); }

}  // namespace penalty::pair_key
