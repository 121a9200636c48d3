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
#include <unordered_map>
#include <vector>

namespace penalty {

/// One output kept by the deduplication, in output order.
struct KeptOutput {
    std::size_t output = 0;  ///< index into the step's DetectionOutput list
    Index old_index = 0;     ///< 1-based position of its id in the previous list, 0 when new
};

/// The `contactIndex` map of one model pair, carried from step to step.
class ContactTracker {
public:
    /// Deduplicates this step's outputs and updates the id → position map. The result lists the
    /// kept outputs in output order; the k-th kept output becomes contact k of the force field.
    [[nodiscard]] std::vector<KeptOutput> update(std::span<const DetectionOutput> outputs);

    /// 1-based position of `id` in the last list, or 0 when the id was not kept last step.
    [[nodiscard]] Index position_of(std::int64_t id) const;
    [[nodiscard]] std::size_t tracked_ids() const { return contact_index_.size(); }
    /// Forgets every id (a pair destroyed and recreated from scratch, as SOFA's cleanup).
    void reset() { contact_index_.clear(); }

private:
    std::unordered_map<std::int64_t, std::int64_t> contact_index_;
    std::vector<std::int64_t> old_;  // scratch, reused across steps
};

}  // namespace penalty
