#include "penalty/response/contact_tracker.hpp"

#include "penalty/core/radix_sort.hpp"

#include <algorithm>

namespace penalty {

namespace {
bool id_less(const ContactTracker::IdPosition& a, std::int64_t id) { return a.id < id; }
}  // namespace

std::span<const KeptOutput> ContactTracker::update(std::span<const DetectionOutput> outputs) {
    // Outputs grouped by id (sorted by (id, output index), so each group is in output order).
    // Per group the winner is the first output with the minimal value: a later output replaces
    // the current winner only if the winner's value is not <= its value (strict `<`, and a NaN
    // winner is replaced, as SOFA's comparison). The winner inherits the id's previous position.
    const std::size_t n = outputs.size();
    sort_by_id(outputs);
    // old_[i]: ≥ 0 kept (0 = new, > 0 = previous 1-based position), −1 not kept
    // The groups come in increasing id order and previous_ is sorted by id: one merge finds each
    // id's previous position.
    old_.assign(n, -1);
    auto previous = previous_.begin();
    for (std::size_t g = 0; g < n;) {
        const std::int64_t id = by_id_[g].first;
        std::size_t winner = by_id_[g].second;
        std::size_t end = g + 1;
        for (; end < n && by_id_[end].first == id; ++end)
            if (!(outputs[winner].value <= outputs[by_id_[end].second].value)) winner = by_id_[end].second;
        while (previous != previous_.end() && previous->id < id) ++previous;
        old_[winner] = (previous != previous_.end() && previous->id == id) ? previous->position : 0;
        g = end;
    }

    // kept outputs get positions 1, 2, … in output order
    kept_.clear();
    new_position_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (old_[i] < 0) continue;
        kept_.push_back({i, static_cast<Index>(old_[i])});
        new_position_[i] = static_cast<std::int64_t>(kept_.size());
    }

    // the id → position map of this step (ids not kept are forgotten), sorted by id
    next_.clear();
    for (const auto& [id, i] : by_id_)
        if (old_[i] >= 0) next_.push_back({id, new_position_[i]});
    std::swap(previous_, next_);
    return kept_;
}

void ContactTracker::sort_by_id(std::span<const DetectionOutput> outputs) {
    // by id, then output index (all pairs distinct); outputs often come in id order already
    const std::size_t n = outputs.size();
    by_id_.resize(n);
    bool sorted = true;
    std::int64_t low = n > 0 ? outputs[0].id : 0, high = low;
    for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t id = outputs[i].id;
        by_id_[i] = {id, i};
        sorted = sorted && (i == 0 || outputs[i - 1].id <= id);
        low = std::min(low, id);
        high = std::max(high, id);
    }
    if (sorted) return;
    // Ids within a few times the output count (element indices of one model, the usual case):
    // a counting sort, which places the outputs of an id in output order, so the order is the
    // comparison sort's. Otherwise the radix sort by id − low (stable, and by_id_ is in output
    // order: the comparison sort's order too), or for few outputs the comparison sort. (The span
    // is high − low computed without overflow, whatever the int64 ids.)
    const auto span = static_cast<std::uint64_t>(high) - static_cast<std::uint64_t>(low);
    if (n < kMinOutputsForCountingSort || span >= kCountingSortRangePerOutput * n) {
        if (n < kMinOutputsForRadixSort) {
            std::sort(by_id_.begin(), by_id_.end());
            return;
        }
        const auto offset = static_cast<std::uint64_t>(low);
        stable_radix_sort(by_id_, by_id_swap_, radix_counts_, [offset](const std::pair<std::int64_t, std::size_t>& e) {
            return static_cast<std::uint64_t>(e.first) - offset;
        });
        return;
    }
    id_counts_.assign(span + 2, 0);
    for (std::size_t i = 0; i < n; ++i) ++id_counts_[static_cast<std::size_t>(outputs[i].id - low) + 1];
    for (std::size_t k = 1; k < id_counts_.size(); ++k) id_counts_[k] += id_counts_[k - 1];  // first slot of each id
    for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t id = outputs[i].id;
        by_id_[id_counts_[static_cast<std::size_t>(id - low)]++] = {id, i};
    }
}

Index ContactTracker::position_of(std::int64_t id) const {
    const auto it = std::lower_bound(previous_.begin(), previous_.end(), id, id_less);
    return (it != previous_.end() && it->id == id) ? static_cast<Index>(it->position) : 0;
}

}  // namespace penalty
