// PointerIndex: the open-addressing pointer → index table of the solvers' system builds,
// checked against std::unordered_map on seeded random sequences of insertions, lookups and clears.

#include "penalty/core/pointer_index.hpp"

#include <gtest/gtest.h>

#include <random>
#include <unordered_map>
#include <vector>

namespace {

using penalty::PointerIndex;

struct Object {
    double payload = 0.0;  // 8-byte objects: consecutive addresses differ in their low bits only
};

TEST(PointerIndex, AgreesWithAnUnorderedMapOverInsertionsLookupsAndClears) {
    std::vector<Object> objects(5000);
    std::mt19937 random(20261128);
    std::uniform_int_distribution<std::size_t> pick(0, objects.size() - 1);
    PointerIndex<Object> table;
    std::unordered_map<const Object*, std::size_t> reference;
    std::size_t inserts = 0, repeats = 0, found = 0, lookups = 0;
    for (int round = 0; round < 6; ++round) {
        // rounds of growing size, so the table grows several times and is then refilled
        const std::size_t operations = 500u << round;
        for (std::size_t op = 0; op < operations; ++op) {
            const Object* p = &objects[pick(random)];
            if (random() % 3 != 0) {
                const std::size_t index = op;  // a fresh value: a repeated pointer must keep its first one
                const auto [stored, added] = table.emplace(p, index);
                const auto [it, reference_added] = reference.emplace(p, index);
                ASSERT_EQ(added, reference_added);
                ASSERT_EQ(stored, it->second);
                ++inserts;
                repeats += added ? 0 : 1;
            } else {
                const auto it = reference.find(p);
                const std::size_t expected = it == reference.end() ? PointerIndex<Object>::npos : it->second;
                ASSERT_EQ(table.find(p), expected);
                ASSERT_EQ(table.contains(p), it != reference.end());
                ++lookups;
                found += it != reference.end() ? 1 : 0;
            }
        }
        ASSERT_EQ(table.size(), reference.size());
        for (const auto& [p, index] : reference) ASSERT_EQ(table.find(p), index);
        table.clear();
        reference.clear();
        EXPECT_EQ(table.size(), 0u);
        EXPECT_FALSE(table.contains(&objects[0]));
    }
    // the sequences exercised both outcomes of each operation
    EXPECT_GT(repeats, inserts / 5);
    EXPECT_LT(repeats, inserts * 9 / 10);
    EXPECT_GT(found, lookups / 5);
    EXPECT_LT(found, lookups * 9 / 10);
}

TEST(PointerIndex, KeepsTheNullPointerApartAndTheFirstIndexOfEachPointer) {
    Object a, b;
    PointerIndex<Object> table;
    EXPECT_EQ(table.find(nullptr), PointerIndex<Object>::npos);
    EXPECT_EQ(table.find(&a), PointerIndex<Object>::npos);  // empty table: no slots yet
    EXPECT_EQ(table.emplace(nullptr, 7), std::make_pair(std::size_t{7}, true));
    EXPECT_EQ(table.emplace(nullptr, 8), std::make_pair(std::size_t{7}, false));
    EXPECT_EQ(table.emplace(&a, 1), std::make_pair(std::size_t{1}, true));
    EXPECT_EQ(table.emplace(&a, 2), std::make_pair(std::size_t{1}, false));
    EXPECT_EQ(table.find(nullptr), 7u);
    EXPECT_EQ(table.find(&a), 1u);
    EXPECT_FALSE(table.contains(&b));
    EXPECT_EQ(table.size(), 2u);
    table.clear();
    EXPECT_EQ(table.size(), 0u);
    EXPECT_FALSE(table.contains(nullptr));
    EXPECT_EQ(table.emplace(&a, 3), std::make_pair(std::size_t{3}, true));  // a cleared entry takes a new index
}

}  // namespace
