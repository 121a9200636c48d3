#pragma once
/// @file
/// The leaf-level box tests of the dual-tree traversal (src/collision/collision_pipeline.cpp):
/// the boxes of one node's elements laid out as columns (structure of arrays), tested against
/// one box at a time, four columns per instruction on AVX. Internal (namespace detail), public
/// for its tests. The test is Aabb::overlaps with a margin m, with the same IEEE operations: the
/// boxes a and b are disjoint iff on some axis
///   a.min > b.max + m   or   b.min > a.max + m
/// (b.max + m and a.max + m rounded as in Aabb::overlaps; NaN compares false, as there).
#include "penalty/collision/collision_model.hpp"
#include "penalty/mechanics/kernel_path.hpp"

#include <cstdint>

namespace penalty::detail {

/// Up to kCapacity element boxes as columns: min[axis][k] and max[axis][k] + margin.
struct BoxColumns {
    static constexpr std::uint32_t kCapacity = 64;  // one bit each in a 64-bit mask
    // spare columns so that the last group of four reads initialised values; rows of a multiple
    // of four doubles, so that every group of four is 32-byte aligned
    static constexpr std::uint32_t kRow = kCapacity + 4;
    alignas(32) double min[3][kRow];
    alignas(32) double max_plus_margin[3][kRow];
    std::uint32_t slot[kCapacity];  // the tree slot of each column
    std::uint32_t size = 0;

    /// Appends box `b` of tree slot `s` (size < kCapacity).
    void push(const Aabb& b, double margin, std::uint32_t s) {
        for (int i = 0; i < 3; ++i) {
            min[i][size] = b.min[i];
            max_plus_margin[i][size] = b.max[i] + margin;
        }
        slot[size++] = s;
    }
    /// Fills the spare columns after the last one (call once after the pushes).
    void pad() {
        for (std::uint32_t k = size; k < size + 3; ++k)
            for (int i = 0; i < 3; ++i) min[i][k] = max_plus_margin[i][k] = 0.0;
    }
};

/// Bit k set iff `a` overlaps column k with `margin` (the margin the columns were pushed with).
[[nodiscard]] std::uint64_t overlap_mask(const Aabb& a, double margin, const BoxColumns& columns, KernelPath path);

}  // namespace penalty::detail
