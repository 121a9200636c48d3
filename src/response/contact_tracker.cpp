#include "penalty/response/contact_tracker.hpp"

#include "penalty/core/radix_sort.hpp"

#include <algorithm>

namespace penalty {

namespace {
bool id_less(const ContactTracker::IdPosition& a, std::int64_t id) { return a.id < id; }
}  // namespace

std::span<const KeptOutput> ContactTracker::update(std::span<const DetectionOutput> outputs) {
    const std::size_t n = outputs.size();
    std::int64_t low = n > 0 ? outputs[0].id : 0, high = low;
    for (const DetectionOutput& o : outputs) {
        low = std::min(low, o.id);
        high = std::max(high, o.id);
    }
    // (high − low without overflow, whatever the int64 ids)
    const auto span = static_cast<std::uint64_t>(high) - static_cast<std::uint64_t>(low);
    if (n >= kMinOutputsForIdSlots && span < kIdSlotsPerOutput * n) return update_dense(outputs, low, span);
    // Outputs grouped by id (sorted by (id, output index), so each group is in output order).
    // Per group the winner is the first output with the minimal value: a later output replaces
    // the current winner only if the winner's value is not <= its value (strict `<`, and a NaN
    // winner is replaced, as SOFA's comparison). The winner inherits the id's previous position.
    sort_by_id(outputs, low);
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

std::span<const KeptOutput> ContactTracker::update_dense(std::span<const DetectionOutput> outputs, std::int64_t low,
                                                         std::uint64_t span) {
    // The same choices as update()'s groups, with a slot per id of [low, low + span] instead of
    // a sort: the outputs are visited in order, so each slot sees its id's outputs in output order.
    const std::size_t n = outputs.size();
    const auto slot_of = [low](std::int64_t id) {
        return static_cast<std::size_t>(static_cast<std::uint64_t>(id) - static_cast<std::uint64_t>(low));
    };
    winner_of_id_.assign(span + 1, 0);  // 1 + the winner's output index, 0: no output
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t& w = winner_of_id_[slot_of(outputs[i].id)];
        if (w == 0 || !(outputs[w - 1].value <= outputs[i].value)) w = i + 1;
    }
    // the previous positions of the ids in range (previous_ is sorted by id)
    position_of_id_.assign(span + 1, 0);
    const std::int64_t high = static_cast<std::int64_t>(static_cast<std::uint64_t>(low) + span);
    for (auto p = std::lower_bound(previous_.begin(), previous_.end(), low, id_less);
         p != previous_.end() && p->id <= high; ++p)
        position_of_id_[slot_of(p->id)] = p->position;
    // kept outputs get positions 1, 2, … in output order; a slot's previous position is read
    // once (by its winner), then replaced by the new one
    kept_.clear();
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t slot = slot_of(outputs[i].id);
        if (winner_of_id_[slot] != i + 1) continue;
        kept_.push_back({i, static_cast<Index>(position_of_id_[slot])});
        position_of_id_[slot] = static_cast<std::int64_t>(kept_.size());
    }
    // the id → position map of this step, sorted by id
    next_.clear();
    for (std::size_t slot = 0; slot <= span; ++slot)
        if (winner_of_id_[slot] != 0)
            next_.push_back({static_cast<std::int64_t>(static_cast<std::uint64_t>(low) + slot), position_of_id_[slot]});
    std::swap(previous_, next_);
    return kept_;
}

void ContactTracker::sort_by_id(std::span<const DetectionOutput> outputs, std::int64_t low) {
    // by id, then output index (all pairs distinct); outputs often come in id order already.
    // (update() takes ids in a narrow range, from kMinOutputsForIdSlots outputs, without a
    // sort: update_dense.)
    const std::size_t n = outputs.size();
    by_id_.resize(n);
    bool sorted = true;
    for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t id = outputs[i].id;
        by_id_[i] = {id, i};
        sorted = sorted && (i == 0 || outputs[i - 1].id <= id);
    }
    if (sorted) return;
    // For few outputs the comparison sort; otherwise the radix sort by id − low (stable, and
    // by_id_ is in output order: the comparison sort's order too)
    if (n < kMinOutputsForRadixSort) {
        std::sort(by_id_.begin(), by_id_.end());
        return;
    }
    const auto offset = static_cast<std::uint64_t>(low);
    stable_radix_sort(by_id_, by_id_swap_, radix_counts_, [offset](const std::pair<std::int64_t, std::size_t>& e) {
        return static_cast<std::uint64_t>(e.first) - offset;
    });
}

Index ContactTracker::position_of(std::int64_t id) const {
    const auto it = std::lower_bound(previous_.begin(), previous_.end(), id, id_less);
    return (it != previous_.end() && it->id == id) ? static_cast<Index>(it->position) : 0;
}

}  // namespace penalty
