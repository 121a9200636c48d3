// stable_radix_sort (core/radix_sort.hpp): the order of std::stable_sort by key, for keys of every
// width up to 64 bits, with many equal keys, passes with one digit for all (skipped), and the
// short and degenerate lists; the scratch is reused from call to call.
#include "penalty/core/pair_key.hpp"
#include "penalty/core/radix_sort.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace {

using penalty::stable_radix_sort;
using Item = std::pair<std::uint64_t, std::uint32_t>;  // (key, original position)

TEST(RadixSort, EqualsStableSortByKeyForEveryKeyWidth) {
    std::mt19937_64 rng(20261127);
    std::vector<Item> swap;
    std::vector<std::size_t> counts;
    int lists = 0, with_ties = 0, skipped_digit = 0;
    for (const int bits : {1, 5, 11, 12, 22, 23, 33, 40, 63, 64}) {
        for (const std::size_t n : {0u, 1u, 2u, 7u, 300u, 2048u, 5000u}) {
            for (const bool gap : {false, true}) {
                // gap: the middle 22 bits zero in every key, so those passes are skipped
                std::vector<Item> v(n);
                const std::uint64_t mask = bits == 64 ? ~0ULL : (1ULL << bits) - 1;
                for (std::size_t i = 0; i < n; ++i) {
                    std::uint64_t key = rng() & mask;
                    if (i % 3 == 0 && i > 0) key = v[i / 2].first;  // ties
                    if (gap) key &= ~(((1ULL << 22) - 1) << 11);
                    v[i] = {key, static_cast<std::uint32_t>(i)};
                }
                std::vector<Item> expected = v;
                std::stable_sort(expected.begin(), expected.end(),
                                 [](const Item& a, const Item& b) { return a.first < b.first; });
                stable_radix_sort(v, swap, counts, [](const Item& x) { return x.first; });
                ASSERT_EQ(v, expected) << bits << " bits, n = " << n << (gap ? ", gap" : "");
                ++lists;
                for (std::size_t i = 1; i < n; ++i)
                    if (v[i].first == v[i - 1].first) {
                        ++with_ties;
                        break;
                    }
                skipped_digit += gap && bits > 22 && n > 2 ? 1 : 0;
            }
        }
    }
    EXPECT_EQ(lists, 140);
    EXPECT_GT(with_ties, 60);
    EXPECT_EQ(skipped_digit, 20);  // lists where some 11-bit digit is zero in every key
}

TEST(RadixSort, AllKeysZeroOrOneDigitLeaveTheOrder) {
    std::vector<Item> v, swap;
    std::vector<std::size_t> counts;
    for (std::uint32_t i = 0; i < 1000; ++i) v.push_back({0, i});
    const std::vector<Item> zeros = v;
    stable_radix_sort(v, swap, counts, [](const Item& x) { return x.first; });
    EXPECT_EQ(v, zeros);
    for (auto& x : v) x.first = std::numeric_limits<std::uint64_t>::max();
    const std::vector<Item> same = v;
    stable_radix_sort(v, swap, counts, [](const Item& x) { return x.first; });
    EXPECT_EQ(v, same);
}

TEST(RadixSort, PlainKeysSortAsStdSort) {
    std::mt19937_64 rng(7);
    std::vector<std::uint64_t> v(3000), swap;
    std::vector<std::size_t> counts;
    for (auto& k : v) {  // candidate keys: PairKey(elem1, elem2).bits()
        const auto elem1 = std::uint32_t(rng() % 700);
        const auto elem2 = std::uint32_t(rng() % 900);
        k = penalty::pair_key::make(elem1, elem2);
    }
    std::vector<std::uint64_t> expected = v;
    std::sort(expected.begin(), expected.end());
    stable_radix_sort(v, swap, counts, [](std::uint64_t k) { return k; });
    EXPECT_EQ(v, expected);
}

}  // namespace
