#pragma once
/// @file
/// A hash of an element's vertex list, for the hash sets that find the faces (or edges) seen so
/// far while a mesh's elements are listed in their order: O(1) a lookup, where an ordered set took
/// O(log n) and made a large mesh's load grow as n log n. The first occurrence is what the list
/// keeps, so the order is that of the ordered set's loop.
#include <array>
#include <cstddef>
#include <cstdint>

namespace penalty {

struct VertexListHash {
    /// (Index: a 32-bit vertex index)
    template <class Index, std::size_t N>
    std::size_t operator()(const std::array<Index, N>& v) const {
        static_assert(sizeof(Index) == 4);
        std::uint64_t h = 0x9e3779b97f4a7c15ULL;
        for (const Index p : v) h = (h ^ static_cast<std::uint32_t>(p)) * 0xff51afd7ed558ccdULL;
        return static_cast<std::size_t>(h ^ (h >> 32));
    }
};

}  // namespace penalty
