// VertexListSet: the open-addressing set of vertex lists of the mesh loops (faces, edges, spring
// pairs), checked against std::set on seeded random lists, with the list of all −1 (its empty
// slot's mark), growth from empty and after reserve, and signed and unsigned indices.

#include "penalty/core/vertex_list_hash.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>

namespace {

using penalty::VertexListSet;

template <class Index, std::size_t N>
void agree_with_a_set(std::uint32_t seed, std::size_t reserved) {
    using List = std::array<Index, N>;
    VertexListSet<Index, N> set;
    set.reserve(reserved);
    std::set<List> reference;
    std::mt19937 random(seed);
    // r^N ≈ 20 000 possible lists for 20 000 draws: about a third of the draws repeat a member
    const std::size_t draws = 20000;
    const int r = static_cast<int>(std::lround(std::pow(double(draws), 1.0 / double(N))));
    std::uniform_int_distribution<int> vertex(-1, r - 2);  // −1: all ones
    std::size_t added = 0;
    for (std::size_t k = 0; k < draws; ++k) {
        List v{};
        for (Index& i : v) i = static_cast<Index>(vertex(random));
        if (k == 5000) v.fill(static_cast<Index>(-1));  // the empty slot's mark, as a member
        const bool member = reference.count(v) != 0;
        ASSERT_EQ(set.contains(v), member) << k;
        const bool inserted = set.insert(v);
        ASSERT_EQ(inserted, !member) << k;
        ASSERT_FALSE(set.insert(v)) << k;
        reference.insert(v);
        added += inserted ? 1 : 0;
        ASSERT_EQ(set.size(), reference.size());
    }
    List all_ones{};
    all_ones.fill(static_cast<Index>(-1));
    EXPECT_TRUE(set.contains(all_ones));
    // the draws are a test: many members, many repeats (about 12 600 and 7 400 expected)
    EXPECT_GT(added, draws / 2);
    EXPECT_LT(added, draws * 4 / 5);
}

TEST(VertexListSet, AgreesWithAnOrderedSetGrowingFromEmpty) {
    agree_with_a_set<std::int32_t, 2>(20261201, 0);
    agree_with_a_set<std::int32_t, 3>(20261202, 0);
    agree_with_a_set<std::uint32_t, 4>(20261203, 0);
}

TEST(VertexListSet, AgreesWithAnOrderedSetAfterReserve) {
    agree_with_a_set<std::int32_t, 3>(20261204, 100000);
    agree_with_a_set<std::uint32_t, 2>(20261205, 7);
}

TEST(VertexListSet, ListsDifferingInOrderAreDistinct) {
    VertexListSet<std::int32_t, 3> set;
    EXPECT_TRUE(set.insert({1, 2, 3}));
    EXPECT_TRUE(set.insert({3, 2, 1}));  // the caller sorts when the order does not matter
    EXPECT_FALSE(set.insert({1, 2, 3}));
    EXPECT_EQ(set.size(), 2u);
    EXPECT_FALSE(set.contains({2, 1, 3}));
}

}  // namespace
