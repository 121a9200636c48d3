#pragma once
/// @file
/// Stable least-significant-digit radix sort by a 64-bit unsigned key: the order of std::sort by
/// (key, position), without its comparisons (a comparison sort of a few thousand random keys
/// mispredicts about one branch in two). Used where detection and response sort keys each step:
/// the candidate pairs, the outputs in SOFA's order, the contact ids.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace penalty {

/// Bits of a radix digit: 2048 counters a pass (16 KiB), which stay in the first-level cache.
inline constexpr int kRadixDigitBits = 11;

/// Sorts v by key(element) (a std::uint64_t), equal keys in their order in v. One pass of 11 bits
/// per digit the keys use (up to the highest bit set in any key); a pass where every key has the
/// same digit is skipped. `swap` and `counts` are scratch (kept by the caller: no allocation once
/// they are large enough). Linear in v's size; for short lists a comparison sort is faster.
template <class T, class KeyOf>
void stable_radix_sort(std::vector<T>& v, std::vector<T>& swap, std::vector<std::size_t>& counts, KeyOf key_of) {
    constexpr std::size_t kBuckets = std::size_t(1) << kRadixDigitBits;
    const std::size_t n = v.size();
    if (n < 2) return;
    std::uint64_t used = 0;
    for (const T& x : v) used |= key_of(x);
    const int passes = (std::bit_width(used) + kRadixDigitBits - 1) / kRadixDigitBits;
    if (passes == 0) return;  // every key 0: already in order
    // the counts of every pass in one read of the keys
    counts.assign(std::size_t(passes) * kBuckets, 0);
    for (const T& x : v) {
        const std::uint64_t k = key_of(x);
        for (int p = 0; p < passes; ++p)
            ++counts[std::size_t(p) * kBuckets + ((k >> (p * kRadixDigitBits)) & (kBuckets - 1))];
    }
    if (swap.size() < n) swap.resize(n);
    T* from = v.data();
    T* to = swap.data();
    for (int p = 0; p < passes; ++p) {
        std::size_t* count = counts.data() + std::size_t(p) * kBuckets;
        const int shift = p * kRadixDigitBits;
        if (count[(key_of(from[0]) >> shift) & (kBuckets - 1)] == n) continue;  // one digit for all: the order stays
        std::size_t start = 0;
        for (std::size_t b = 0; b < kBuckets; ++b) {
            const std::size_t c = count[b];
            count[b] = start;
            start += c;
        }
        for (std::size_t i = 0; i < n; ++i) to[count[(key_of(from[i]) >> shift) & (kBuckets - 1)]++] = from[i];
        std::swap(from, to);
    }
    if (from != v.data()) std::copy(from, from + n, v.data());
}

}  // namespace penalty
