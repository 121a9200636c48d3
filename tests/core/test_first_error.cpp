// FirstErrorInOrder: items run out of order (here on threads in reverse chunk order) raise the
// error the loop over the items in order would raise, that of the least failing index; run()
// reports and records a failure so that the calling task stops.

#include "penalty/core/first_error.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

using penalty::FirstErrorInOrder;

TEST(FirstErrorInOrder, RunReturnsFalseAndRecordsTheItemsError) {
    FirstErrorInOrder failure;
    EXPECT_TRUE(failure.run(4, [] {}));
    EXPECT_EQ(failure.first_index(), std::numeric_limits<std::size_t>::max());
    EXPECT_NO_THROW(failure.rethrow_if_any());
    EXPECT_FALSE(failure.run(7, [] { throw std::runtime_error("item 7"); }));
    EXPECT_EQ(failure.first_index(), 7U);
    EXPECT_FALSE(failure.run(9, [] { throw std::runtime_error("item 9"); }));
    EXPECT_FALSE(failure.run(3, [] { throw std::invalid_argument("item 3"); }));
    EXPECT_EQ(failure.first_index(), 3U);
    EXPECT_THROW(failure.rethrow_if_any(), std::invalid_argument);  // the least index's, its type kept
}

// 8 threads over 800 items in chunks, each chunk stopping at its first failure; items 650, 420 and
// 421 fail. Whatever the schedule, the error raised is item 420's and every item before it ran.
TEST(FirstErrorInOrder, ChunksOnThreadsRaiseTheFirstItemsError) {
    for (int round = 0; round < 20; ++round) {
        FirstErrorInOrder failure;
        std::vector<std::atomic<int>> ran(800);
        std::vector<std::thread> threads;
        for (int t = 7; t >= 0; --t)
            threads.emplace_back([&, t] {
                for (std::size_t i = 100 * std::size_t(t); i < 100 * std::size_t(t + 1); ++i) {
                    const bool done = failure.run(i, [&] {
                        ++ran[i];
                        if (i == 650 || i == 420 || i == 421) throw std::runtime_error("item " + std::to_string(i));
                    });
                    if (!done) break;
                }
            });
        for (std::thread& t : threads) t.join();
        EXPECT_EQ(failure.first_index(), 420U);
        try {
            failure.rethrow_if_any();
            ADD_FAILURE() << "no error raised";
        } catch (const std::runtime_error& e) {
            EXPECT_STREQ(e.what(), "item 420");
        }
        for (std::size_t i = 0; i <= 420; ++i) EXPECT_EQ(ran[i].load(), 1) << i;
        EXPECT_EQ(ran[421].load(), 0);  // its chunk stopped at 420
    }
}

}  // namespace
