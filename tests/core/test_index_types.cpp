// DofIndex, ElementIndex, ModelIndex and PairKey (core/index_types.hpp): the kinds do not convert
// into each other nor from or to the integer, and do no arithmetic (compile-time checks); a
// PairKey orders, sorts and hashes as the integer first · 2³² + second did (computed here by a
// multiplication, not by the header's shift), on seeded random pairs; the halves and the integer
// round trip.
#include "penalty/core/index_types.hpp"
#include "penalty/core/pair_key.hpp"
#include "penalty/core/radix_sort.hpp"
#include "penalty/core/types.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <concepts>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace {

using penalty::DofIndex;
using penalty::ElementIndex;
using penalty::Index;
using penalty::ModelIndex;
using penalty::PairKey;

// --- compile-time: the kinds are apart ---------------------------------------------------------
static_assert(std::is_same_v<ElementIndex::value_type, Index>);
static_assert(!std::is_convertible_v<ElementIndex, DofIndex> && !std::is_convertible_v<DofIndex, ElementIndex>);
static_assert(!std::is_convertible_v<ModelIndex, ElementIndex> && !std::is_convertible_v<ElementIndex, ModelIndex>);
static_assert(!std::is_convertible_v<ModelIndex, DofIndex> && !std::is_convertible_v<DofIndex, ModelIndex>);
static_assert(!std::is_constructible_v<DofIndex, ElementIndex> && !std::is_constructible_v<ElementIndex, DofIndex>);
static_assert(!std::is_convertible_v<Index, DofIndex> && !std::is_convertible_v<int, ElementIndex>);
static_assert(!std::is_convertible_v<DofIndex, Index> && !std::is_convertible_v<ElementIndex, std::size_t>);
static_assert(std::is_constructible_v<DofIndex, Index> && std::is_constructible_v<ElementIndex, int>);
static_assert(!std::equality_comparable_with<ElementIndex, DofIndex>);
static_assert(!std::totally_ordered_with<ElementIndex, DofIndex>);
static_assert(!std::equality_comparable_with<ElementIndex, Index>);
static_assert(std::totally_ordered<ElementIndex> && std::totally_ordered<PairKey>);
// no arithmetic, within a kind or with an integer
template <class A, class B>
concept Adds = requires(A a, B b) {
    a + b;
};
template <class A, class B>
concept Subtracts = requires(A a, B b) {
    a - b;
};
static_assert(!Adds<ElementIndex, ElementIndex> && !Adds<ElementIndex, int> && !Adds<DofIndex, Index>);
static_assert(!Subtracts<ElementIndex, ElementIndex> && !Subtracts<ModelIndex, int>);
// zero cost: the integer's size, trivially copyable (memcpy, registers)
static_assert(sizeof(DofIndex) == sizeof(Index) && std::is_trivially_copyable_v<DofIndex>);
static_assert(sizeof(ElementIndex) == sizeof(Index) && std::is_trivially_copyable_v<ElementIndex>);
static_assert(sizeof(ModelIndex) == sizeof(Index) && std::is_trivially_copyable_v<ModelIndex>);
static_assert(sizeof(PairKey) == sizeof(std::uint64_t) && std::is_trivially_copyable_v<PairKey>);
static_assert(sizeof(std::vector<PairKey>::value_type[8]) == 8 * sizeof(std::uint64_t));
// a PairKey is made of two indices of one kind, not of two kinds
static_assert(std::is_constructible_v<PairKey, ModelIndex, ModelIndex>);
static_assert(!std::is_constructible_v<PairKey, ModelIndex, ElementIndex>);
static_assert(!std::is_convertible_v<PairKey, std::uint64_t> && !std::is_convertible_v<std::uint64_t, PairKey>);
// constexpr
static_assert(PairKey(1, 2).bits() == 0x0000000100000002ULL && PairKey(1, 2).first() == 1 &&
              PairKey(1, 2).second() == 2);
static_assert(PairKey(0, 0xFFFFFFFFu) < PairKey(1, 0) && PairKey::unordered(9, 4) == PairKey(4, 9));

// The integer of (first, second) as the packed keys had it, by arithmetic rather than a shift.
std::uint64_t packed_by_product(std::uint32_t first, std::uint32_t second) {
    return std::uint64_t(first) * 4294967296ULL + std::uint64_t(second);
}

// Pairs drawn from a few ranges: small values (many equal firsts, so the second decides), the
// whole 32-bit range, and the ends (0, 2³² − 1), each draw in a written-out order.
std::vector<std::pair<std::uint32_t, std::uint32_t>> index_pair_draws(std::mt19937& rng, std::size_t n) {
    std::uniform_int_distribution<std::uint32_t> small(0, 6);
    std::uniform_int_distribution<std::uint32_t> any(0, std::numeric_limits<std::uint32_t>::max());
    std::uniform_int_distribution<int> range(0, 2);
    const auto draw = [&](int r) -> std::uint32_t {
        if (r == 0) return small(rng);
        if (r == 1) return any(rng);
        const std::uint32_t low = small(rng);
        return low % 2 == 0 ? low : std::numeric_limits<std::uint32_t>::max() - low;
    };
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs(n);
    for (auto& p : pairs) {
        const int r1 = range(rng);
        const std::uint32_t first = draw(r1);
        const int r2 = range(rng);
        const std::uint32_t second = draw(r2);
        p = {first, second};
    }
    return pairs;
}

TEST(PairKey, OrdersAsThePackedIntegerOnRandomPairs) {
    std::mt19937 rng(20261130);
    const auto pairs = index_pair_draws(rng, 4000);
    std::size_t less = 0, equal = 0, greater = 0, equal_first = 0;
    for (std::size_t i = 0; i + 1 < pairs.size(); ++i) {
        for (std::size_t j = i + 1; j < std::min(pairs.size(), i + 8); ++j) {
            const PairKey a(pairs[i].first, pairs[i].second), b(pairs[j].first, pairs[j].second);
            const std::uint64_t ia = packed_by_product(pairs[i].first, pairs[i].second);
            const std::uint64_t ib = packed_by_product(pairs[j].first, pairs[j].second);
            ASSERT_EQ(a < b, ia < ib) << a << " " << b;
            ASSERT_EQ(a == b, ia == ib) << a << " " << b;
            ASSERT_EQ(a > b, ia > ib) << a << " " << b;
            ASSERT_EQ(a <=> b, ia <=> ib) << a << " " << b;
            less += ia < ib ? 1 : 0;
            equal += ia == ib ? 1 : 0;
            greater += ia > ib ? 1 : 0;
            equal_first += pairs[i].first == pairs[j].first ? 1 : 0;
        }
    }
    // every outcome met, and many pairs decided by their second index
    EXPECT_GT(less, 1000u);
    EXPECT_GT(greater, 1000u);
    EXPECT_GT(equal, 10u);
    EXPECT_GT(equal_first, 1000u);
}

TEST(PairKey, SortsAsThePackedIntegersByStdSortAndByTheRadixSortOfItsBits) {
    std::mt19937 rng(7);
    const auto pairs = index_pair_draws(rng, 5000);
    std::vector<PairKey> keys;
    std::vector<std::uint64_t> integers;
    for (const auto& p : pairs) {
        keys.emplace_back(p.first, p.second);
        integers.push_back(packed_by_product(p.first, p.second));
    }
    std::vector<PairKey> by_radix = keys, swap;
    std::vector<std::size_t> counts;
    penalty::stable_radix_sort(by_radix, swap, counts, [](PairKey k) { return k.bits(); });
    std::sort(keys.begin(), keys.end());
    std::sort(integers.begin(), integers.end());
    ASSERT_EQ(keys.size(), integers.size());
    for (std::size_t i = 0; i < keys.size(); ++i) {
        ASSERT_EQ(keys[i].bits(), integers[i]) << i;
        ASSERT_EQ(by_radix[i], keys[i]) << i;
    }
}

TEST(PairKey, HalvesAndIntegerRoundTrip) {
    std::mt19937 rng(11);
    for (const auto& [first, second] : index_pair_draws(rng, 2000)) {
        const PairKey key(first, second);
        ASSERT_EQ(key.first(), first);
        ASSERT_EQ(key.second(), second);
        ASSERT_EQ(key.bits(), packed_by_product(first, second));
        ASSERT_EQ(PairKey::from_bits(key.bits()), key);
        // the integer form of pair_key.hpp is the same integer
        ASSERT_EQ(penalty::pair_key::make(first, second), key.bits());
        ASSERT_EQ(penalty::pair_key::first(key.bits()), first);
        ASSERT_EQ(penalty::pair_key::second(key.bits()), second);
        // unordered: {min, max} whichever way given
        const PairKey u = PairKey::unordered(first, second);
        ASSERT_EQ(u, PairKey::unordered(second, first));
        ASSERT_EQ(u.first(), std::min(first, second));
        ASSERT_EQ(u.second(), std::max(first, second));
    }
    // from two indices of one kind: their values as the halves
    const PairKey models(ModelIndex(3), ModelIndex(4000000000LL));
    EXPECT_EQ(models.first(), 3u);
    EXPECT_EQ(models.second(), 4000000000u);
    EXPECT_EQ(PairKey(ElementIndex(7), ElementIndex(0)), PairKey(7, 0));
    EXPECT_EQ(PairKey(), PairKey(0, 0));
}

TEST(PairKey, HashesAsItsIntegerAndKeysHashTables) {
    std::mt19937 rng(13);
    const auto pairs = index_pair_draws(rng, 3000);
    std::unordered_map<PairKey, std::size_t> position;
    std::unordered_map<std::uint64_t, std::size_t> reference;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        const PairKey key(pairs[i].first, pairs[i].second);
        ASSERT_EQ(std::hash<PairKey>{}(key), std::hash<std::uint64_t>{}(packed_by_product(key.first(), key.second())));
        position.emplace(key, i);  // the first position of each key, as the integer table keeps
        reference.emplace(key.bits(), i);
    }
    ASSERT_EQ(position.size(), reference.size());
    EXPECT_LT(position.size(), pairs.size());  // repeated pairs met
    for (const auto& [bits, i] : reference) ASSERT_EQ(position.at(PairKey::from_bits(bits)), i);
    // the same hash, the same bucket count: the tables place the keys alike
    ASSERT_EQ(position.bucket_count(), reference.bucket_count());
    for (const auto& [bits, i] : reference)
        ASSERT_EQ(position.bucket(PairKey::from_bits(bits)), reference.bucket(bits));
}

TEST(StrongIndex, RoundTripsOrdersWithinItsKindAndHashesAsTheInteger) {
    const ElementIndex e(42);
    EXPECT_EQ(e.value(), 42);
    EXPECT_EQ(e.slot(), 42u);
    EXPECT_EQ(ElementIndex().value(), 0);
    EXPECT_EQ(DofIndex(-1).value(), -1);  // negative values are kept (the checks that refuse them read them)
    std::mt19937 rng(17);
    std::uniform_int_distribution<Index> draw(-5, 1000000);
    std::unordered_set<DofIndex> set;
    std::vector<Index> inserted;
    for (int i = 0; i < 1000; ++i) {
        const Index a = draw(rng);
        const Index b = draw(rng);
        ASSERT_EQ(DofIndex(a) < DofIndex(b), a < b);
        ASSERT_EQ(ElementIndex(a) == ElementIndex(b), a == b);
        ASSERT_EQ(ModelIndex(a) >= ModelIndex(b), a >= b);
        ASSERT_EQ(std::hash<ElementIndex>{}(ElementIndex(a)), std::hash<Index>{}(a));
        set.insert(DofIndex(a));
        inserted.push_back(a);
    }
    for (const Index a : inserted) ASSERT_TRUE(set.contains(DofIndex(a)));
    EXPECT_FALSE(set.contains(DofIndex(-6)));
    std::ostringstream text;
    text << ElementIndex(12) << " " << DofIndex(-3) << " " << PairKey(5, 6);
    EXPECT_EQ(text.str(), "12 -3 (5, 6)");
}

}  // namespace
