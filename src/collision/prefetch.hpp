#pragma once
// Software prefetch for the detection's loops that read per-element data in no memory order
// (kept pairs, candidates, tree order, SOFA's order): the data of the element used `kAhead`
// iterations later is fetched now. Worth it only when the data does not stay in cache: for
// models of more than `kMinElements` elements together (below that the prefetches are only
// extra instructions).
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

}  // namespace penalty::detail::prefetch
