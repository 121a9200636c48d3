#pragma once
/// PointerIndex: a map from object addresses to indices for tables rebuilt again and again (a
/// solver's system is built again whenever contacts come or go, every step in a pile of bodies).
/// Open addressing with linear probing, at most half full, Fibonacci hashing of the address;
/// clear() keeps the slots, so a table refilled to the same size allocates nothing. The first
/// index given for a pointer stays (emplace does not overwrite), as with std::unordered_map.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace penalty {

/// The hash of an address for open-addressing tables (PointerIndex, the
/// mapping graph's groups): the address without its low 3 bits (alignment), times 2⁶⁴/φ
/// (Fibonacci hashing). A table masks the product's low bits to its size.
[[nodiscard]] inline std::uint64_t address_hash(const void* p) {
    return std::uint64_t(reinterpret_cast<std::uintptr_t>(p) >> 3) * 0x9E3779B97F4A7C15ULL;
}

template <class T>
class PointerIndex {
public:
    static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();

    /// Forgets every entry; keeps the capacity.
    void clear() {
        if (size_ == 0 && !has_null_) return;
        for (Slot& s : slots_) s = Slot{};
        size_ = 0;
        has_null_ = false;
    }
    [[nodiscard]] std::size_t size() const { return size_ + (has_null_ ? 1 : 0); }

    /// The index stored for p, or npos.
    [[nodiscard]] std::size_t find(const T* p) const {
        if (p == nullptr) return has_null_ ? null_index_ : npos;
        if (slots_.empty()) return npos;
        const Slot& s = slots_[probe(p)];
        return s.pointer == p ? s.index : npos;
    }
    [[nodiscard]] bool contains(const T* p) const { return find(p) != npos; }
    /// Stores p → index unless p is there already; returns the index stored for p and whether
    /// it was added now.
    std::pair<std::size_t, bool> emplace(const T* p, std::size_t index) {
        if (p == nullptr) {
            if (has_null_) return {null_index_, false};
            has_null_ = true;
            null_index_ = index;
            return {index, true};
        }
        if (2 * (size_ + 1) > slots_.size()) grow();
        Slot& s = slots_[probe(p)];
        if (s.pointer == p) return {s.index, false};
        s = Slot{p, index};
        ++size_;
        return {index, true};
    }

private:
    struct Slot {
        const T* pointer = nullptr;
        std::size_t index = 0;
    };
    [[nodiscard]] std::size_t home(const T* p) const { return std::size_t(address_hash(p)) & (slots_.size() - 1); }
    /// p's slot, or the empty slot where it would go (the table is never full).
    [[nodiscard]] std::size_t probe(const T* p) const {
        std::size_t i = home(p);
        while (slots_[i].pointer != nullptr && slots_[i].pointer != p) i = (i + 1) & (slots_.size() - 1);
        return i;
    }
    void grow() {
        std::vector<Slot> old(slots_.empty() ? 32 : 2 * slots_.size());
        old.swap(slots_);
        for (const Slot& s : old)
            if (s.pointer != nullptr) slots_[probe(s.pointer)] = s;
    }
    std::vector<Slot> slots_;  // size 0 or a power of two
    std::size_t size_ = 0;     // non-null entries
    bool has_null_ = false;
    std::size_t null_index_ = 0;
};

}  // namespace penalty
