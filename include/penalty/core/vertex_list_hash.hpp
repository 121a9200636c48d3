#pragma once
/// @file
/// The set of vertex lists (faces, edges, vertex pairs) seen so far while a mesh's elements are
/// listed in their order: O(1) a lookup, where an ordered set took O(log n) and made a large
/// mesh's load grow as n log n. The first occurrence is what the loops keep, so the order is that
/// of the ordered set's loop. Open addressing: a std::unordered_set allocated a node a list, and
/// allocating and freeing millions of them was a tenth of a 10⁶-element mesh's load.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

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

/// A set of std::array<Index, N> (Index: a 32-bit vertex index; the caller sorts a list when its
/// order does not matter): linear probing, at most half full, VertexListHash. The list of N
/// indices all −1 (all ones) marks an empty slot; as a member it is held by a flag.
template <class Index, std::size_t N>
class VertexListSet {
public:
    using List = std::array<Index, N>;

    /// Room for `lists` members without growing.
    void reserve(std::size_t lists) {
        std::size_t slots = 32;
        while (slots < 2 * lists) slots *= 2;
        if (slots > slots_.size()) rehash(slots);
    }
    /// Adds v; true when it was not a member.
    bool insert(const List& v) {
        if (same(v, empty_list())) {
            const bool added = !has_empty_list_;
            has_empty_list_ = true;
            return added;
        }
        if (2 * (size_ + 1) > slots_.size()) rehash(slots_.empty() ? 32 : 2 * slots_.size());
        List& slot = slots_[probe(v)];
        if (same(slot, v)) return false;
        slot = v;
        ++size_;
        return true;
    }
    [[nodiscard]] bool contains(const List& v) const {
        if (same(v, empty_list())) return has_empty_list_;
        return !slots_.empty() && same(slots_[probe(v)], v);
    }
    [[nodiscard]] std::size_t size() const { return size_ + (has_empty_list_ ? 1 : 0); }

private:
    static_assert(sizeof(Index) == 4, "a 32-bit vertex index");
    static constexpr List empty_list() {
        List e{};
        e.fill(static_cast<Index>(~std::uint32_t{0}));
        return e;
    }
    /// a == b, inline (std::array's == is a call to memcmp: a third of a large load's time)
    [[nodiscard]] static bool same(const List& a, const List& b) {
        bool equal = true;
        for (std::size_t k = 0; k < N; ++k) equal &= a[k] == b[k];
        return equal;
    }
    /// v's slot, or the empty slot where it would go (the table is never full).
    [[nodiscard]] std::size_t probe(const List& v) const {
        const std::size_t mask = slots_.size() - 1;
        std::size_t i = VertexListHash{}(v)&mask;
        while (!same(slots_[i], v) && !same(slots_[i], empty_list())) i = (i + 1) & mask;
        return i;
    }
    void rehash(std::size_t slots) {
        std::vector<List> old(slots, empty_list());
        old.swap(slots_);
        for (const List& v : old)
            if (!same(v, empty_list())) slots_[probe(v)] = v;
    }
    std::vector<List> slots_;  // size 0 or a power of two
    std::size_t size_ = 0;     // members in slots_
    bool has_empty_list_ = false;
};

}  // namespace penalty
