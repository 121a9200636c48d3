#include "penalty/response/contact_tracker.hpp"

namespace penalty {

std::vector<KeptOutput> ContactTracker::update(std::span<const DetectionOutput> outputs) {
    // Slots in the map: > 0 = 1-based position in the previous list; < 0 = −1 − i for output i
    // currently holding the id in this step. old_[i]: ≥ 0 kept (0 = new, > 0 = previous position),
    // −1 ignored (a duplicate with a value not strictly smaller).
    const std::size_t n = outputs.size();
    old_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        std::int64_t& slot = contact_index_[outputs[i].id];  // inserted as 0 (new) when absent
        const auto current = -1 - static_cast<std::int64_t>(i);
        if (slot < 0) {
            const auto j = static_cast<std::size_t>(-1 - slot);
            if (outputs[j].value <= outputs[i].value) {
                old_[i] = -1;  // the earlier output keeps the id
                continue;
            }
            old_[i] = old_[j];  // output i replaces j and inherits its previous position
            old_[j] = -1;
            slot = current;
        } else {
            old_[i] = slot;
            slot = current;
        }
    }

    // kept outputs get positions 1, 2, … in output order
    std::vector<KeptOutput> kept;
    std::vector<std::int64_t> new_position(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (old_[i] < 0) continue;
        kept.push_back({i, static_cast<Index>(old_[i])});
        new_position[i] = static_cast<std::int64_t>(kept.size());
    }

    // ids not seen this step are forgotten; the others point at their new position
    for (auto it = contact_index_.begin(); it != contact_index_.end();) {
        if (it->second >= 0) {
            it = contact_index_.erase(it);
        } else {
            it->second = new_position[static_cast<std::size_t>(-1 - it->second)];
            ++it;
        }
    }
    return kept;
}

Index ContactTracker::position_of(std::int64_t id) const {
    const auto it = contact_index_.find(id);
    return it == contact_index_.end() ? 0 : static_cast<Index>(it->second);
}

}  // namespace penalty
