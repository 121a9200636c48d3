#pragma once
/// @file
/// SOFA's per-model-pair id deduplication and contact tracking (BarycentricPenalityContact's
/// setDetectionOutputs, spec §7.1): of the detection outputs sharing an id, the first one with the
/// minimal value wins (strict `<` to replace); each kept output inherits the 1-based position its id
/// had in the previous step's contact list (0 = new), which becomes the force field's old_index.

#include "penalty/collision/detection_output.hpp"
#include "penalty/core/types.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace penalty {

/// One output kept by the deduplication, in output order.
struct KeptOutput {
    std::size_t output = 0;  ///< index into the step's DetectionOutput list
    Index old_index = 0;     ///< 1-based position of its id in the previous list, 0 when new
};

/// The `contactIndex` map of one model pair, carried from step to step. Every buffer is reused:
/// once the capacities are reached (as many outputs and ids as before), update() allocates
/// nothing.
class ContactTracker {
public:
    /// Deduplicates this step's outputs and updates the id → position map. The result lists the
    /// kept outputs in output order; the k-th kept output becomes contact k of the force field.
    /// It views a buffer of the tracker, valid until the next update(); with the same ids as the
    /// step before and no more outputs, update() allocates nothing (every buffer is reused).
    [[nodiscard]] std::span<const KeptOutput> update(std::span<const DetectionOutput> outputs);

    /// 1-based position of `id` in the last list, or 0 when the id was not kept last step.
    [[nodiscard]] Index position_of(std::int64_t id) const;
    [[nodiscard]] std::size_t tracked_ids() const { return previous_.size(); }
    /// Forgets every id (a pair destroyed and recreated from scratch, as SOFA's cleanup).
    void reset() { previous_.clear(); }

    /// One entry of the map: an id and its 1-based position in the last list.
    struct IdPosition {
        std::int64_t id;
        std::int64_t position;
    };

    /// From this many outputs whose ids span fewer than kIdSlotsPerOutput ids an
    /// output, a slot per id of the range instead of a sort (update_dense); otherwise the
    /// outputs are sorted by id: the stable radix sort from kMinOutputsForRadixSort outputs, a
    /// comparison sort below.
    static constexpr std::size_t kMinOutputsForIdSlots = 32;
    static constexpr std::uint64_t kIdSlotsPerOutput = 8;
    static constexpr std::size_t kMinOutputsForRadixSort = 256;

private:
    /// update() for ids in [low, low + span], span < kIdSlotsPerOutput · outputs:
    /// the same result, from a slot per id (no sort).
    std::span<const KeptOutput> update_dense(std::span<const DetectionOutput> outputs, std::int64_t low,
                                             std::uint64_t span);
    /// by_id_ = (id, output index) of every output, sorted; `low` is their least id.
    void sort_by_id(std::span<const DetectionOutput> outputs, std::int64_t low);

    // SOFA's contactIndex map as a vector sorted by id: no allocation once its capacity is
    // reached, whichever ids come and go
    std::vector<IdPosition> previous_;
    // scratch, reused across steps
    std::vector<IdPosition> next_;  // the map being built (swapped with previous_)
    std::vector<std::pair<std::int64_t, std::size_t>>
        by_id_;  // (id, output index), sorted: compact, so the sort stays in cache
    std::vector<std::pair<std::int64_t, std::size_t>> by_id_swap_;  // the radix sort's other buffer
    std::vector<std::size_t> radix_counts_;                         // the radix sort's digit counts
    std::vector<std::int64_t> old_;           // per output: previous position, 0 new, −1 dropped
    std::vector<std::int64_t> new_position_;  // per output: 1-based position in this step's list
    std::vector<KeptOutput> kept_;            // the result of the last update()
    std::vector<std::size_t>
        winner_of_id_;  // update_dense: per id of the range, 1 + its winner's output index (0: none)
    std::vector<std::int64_t> position_of_id_;  // update_dense: per id, its previous position, then its new one
};

}  // namespace penalty
