#pragma once
/// @file
/// The error a sequential loop would raise, for items run in parallel: each task records the
/// exception it caught for its item index, and rethrow_if_any() raises the one of least index.
/// The items before that one ran without error whatever the schedule (a task stops at its first
/// error), so it is the error the loop over the items in order would have raised.

#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>

namespace penalty {

class FirstErrorInOrder {
public:
    /// Records the exception being handled (call in a catch block) as item `index`'s.
    void record(std::size_t index) {
        const std::lock_guard lock(mutex_);
        if (index < index_) {
            index_ = index;
            error_ = std::current_exception();
        }
    }
    /// Runs fn() as item `index`: true, or false with the exception it threw recorded (the
    /// calling task then stops: its items after this one are not run).
    template <class Fn>
    bool run(std::size_t index, Fn&& fn) {
        try {
            fn();
            return true;
        } catch (...) {
            record(index);
            return false;
        }
    }
    /// The least index recorded (the largest std::size_t if none).
    [[nodiscard]] std::size_t first_index() const { return index_; }
    /// Rethrows the recorded exception of least index, if any.
    void rethrow_if_any() const {
        if (error_) std::rethrow_exception(error_);
    }

private:
    std::mutex mutex_;
    std::size_t index_ = std::numeric_limits<std::size_t>::max();
    std::exception_ptr error_;
};

}  // namespace penalty
