#pragma once
/// @file
/// The integer form of a PairKey (index_types.hpp), for the arrays that hold keys as integers
/// (the candidate element pairs: radix-sorted, filtered by vector kernels): these functions make
/// and read that integer through PairKey, which alone knows the packing (the first index in the
/// high half, so ascending integers sort by the first index, then the second).
#include "penalty/core/index_types.hpp"

#include <cstdint>

namespace penalty::pair_key {

/// PairKey(first, second).bits() (each below 2³²).
constexpr std::uint64_t make(std::uint32_t first, std::uint32_t second) { return PairKey(first, second).bits(); }
/// The index in the high half.
constexpr std::uint32_t first(std::uint64_t key) { return PairKey::from_bits(key).first(); }
/// The index in the low half.
constexpr std::uint32_t second(std::uint64_t key) { return PairKey::from_bits(key).second(); }

}  // namespace penalty::pair_key
