#pragma once
// Software prefetch, the one place of the library's prefetches (kernel layer). The detection's
// loops that read per-element data in no memory order (kept pairs, candidates, tree order, SOFA's
// order) fetch the data of the element used `kAhead` iterations later now; worth it only when
// the data does not stay in cache: for models of more than `kMinElements` elements together
// (below that the prefetches are only extra instructions). A subtree's products fetch the first
// word of the small objects (contact-point states and mappings) they call kObjectsAhead calls
// later.
#include <cstddef>

namespace penalty::detail::prefetch {

inline constexpr std::size_t kAhead = 16;
inline constexpr std::size_t kMinElements = 32768;

[[nodiscard]] inline bool worth_it(std::size_t elements) { return elements > kMinElements; }

/// Fetches the `bytes` at `p` (at most two cache lines: its first and last byte).
inline void object(const void* p, std::size_t bytes) {
    __builtin_prefetch(p);
    __builtin_prefetch(static_cast<const char*>(p) + bytes - 1);
}

/// How many objects ahead a subtree's products fetch the next objects' first words.
inline constexpr std::size_t kObjectsAhead = 8;

/// Fetches the cache line of `p`'s first byte (nothing for a null pointer).
inline void first_word(const void* p) { __builtin_prefetch(p); }

}  // namespace penalty::detail::prefetch
