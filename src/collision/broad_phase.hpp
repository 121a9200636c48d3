#pragma once
/// @file
/// The broad phase of a detection (private to the collision stage).
///
/// SOFA's BruteForceBroadPhase filters every model pair (broad_phase()) and hands the narrow phase
/// those whose root boxes are within the margin. Kept here: only what the filter says about all
/// pairs together (how many pass, the ones without an intersector, whether a kernel writes the
/// models), counted again only when a model or a parameter the filter reads changed (update), and
/// each detection's near pairs (find_near), found by a sweep over the models' root boxes and
/// filtered one by one: a pile of n bodies has n²/2 pairs and about 6n near ones, so the broad
/// phase's memory and time follow the near pairs, not the n² pairs. The near pairs, their order
/// and keys are those of the test of every pair.

#include "penalty/collision/bvh.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/core/index_types.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace penalty::detail {

/// The place of the pair of models j and i (i ≤ j) in broad_phase()'s order, filtered or not:
/// each model j adds (j, j) then (j, 0) … (j, j − 1), so j(j + 1)/2 pairs come before its own.
[[nodiscard]] constexpr std::uint64_t sofa_pair_order(std::size_t j, std::size_t i) {
    return std::uint64_t(j) * (std::uint64_t(j) + 1) / 2 + (i == j ? 0 : std::uint64_t(i) + 1);
}

/// Calls visit(j, i) for every pair of `n` models in broad_phase()'s order (sofa_pair_order
/// ascending): for each model j, (j, j), then (j, 0) … (j, j − 1).
template <class Visit>
void for_each_model_pair_in_order(std::size_t n, Visit&& visit) {
    for (std::size_t j = 0; j < n; ++j) {
        visit(j, j);
        for (std::size_t i = 0; i < j; ++i) visit(j, i);
    }
}

/// A model pair the broad phase kept and hands to the narrow phase.
struct NearPair {
    std::uint64_t order = 0;             ///< sofa_pair_order of its models' places
    std::array<ModelIndex, 2> places{};  ///< of its model1 and model2 (registered order)
};

/// What SOFA's filter makes of the pair (models[j], models[i]), i ≤ j, as broad_phase() keys it.
enum class PairVerdict : std::uint8_t { filtered_out, unsupported, kept };
[[nodiscard]] PairVerdict judge_model_pair(const IntersectionParams& params, const CollisionModel& later,
                                           const CollisionModel& earlier);
/// The places j and i (i ≤ j) in the intersector's registered order: (j, i) unless the types are
/// registered the other way (two models of one type stay (later, earlier)).
[[nodiscard]] std::array<ModelIndex, 2> registered_places(std::span<CollisionModel* const> models, std::size_t j,
                                                          std::size_t i);

class BroadPhase {
public:
    /// Counts the pairs again if a model or a filter's parameter changed since the last call;
    /// returns whether it did.
    bool update(const IntersectionParams& params, const std::vector<CollisionModel*>& models);
    /// This detection's near pairs, in broad_phase()'s order: the kept pairs passing
    /// `within_margin(place1, place2)`. `every_pair`: each kept pair tested in order (the
    /// exhaustive detection); else, beyond a few pairs, a sweep over the trees' root boxes.
    void find_near(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
                   const std::vector<Bvh>& trees, const std::function<bool(ModelIndex, ModelIndex)>& within_margin,
                   bool every_pair);
    [[nodiscard]] const std::vector<NearPair>& near() const { return near_; }
    [[nodiscard]] const std::vector<ModelPair>& unsupported() const { return unsupported_; }
    /// Some kept pair's kernel writes the models (pairs in order, or their writes deferred).
    [[nodiscard]] bool any_pair_writes_models() const { return any_pair_writes_models_; }

private:
    /// What the pairs of one model depend on.
    struct ModelKey {
        const CollisionModel* model = nullptr;
        ModelType type = ModelType::Point;
        bool active = false, simulated = false, self_collision = false, both_side = false;
        int node = -1;
        std::vector<int> group;
        [[nodiscard]] bool describes(const CollisionModel& m) const;
    };
    /// The pair (j, i), i ≤ j, if kept.
    [[nodiscard]] static std::optional<NearPair> kept_pair(const IntersectionParams& params,
                                                           const std::vector<CollisionModel*>& models, std::size_t j,
                                                           std::size_t i);
    /// Appends to near_ the kept pairs passing `within_margin` among the models whose root boxes
    /// a sweep finds within reach of each other, in no order (find_near sorts them).
    void sweep(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
               const std::vector<Bvh>& trees, const std::function<bool(ModelIndex, ModelIndex)>& within_margin);
    /// The sweep's models go to TBB's threads in ranges of this many, from twice as many.
    static constexpr std::size_t kModelsPerSweepTask = 64;
    std::vector<ModelKey> key_;
    std::size_t kept_pairs_ = 0;  ///< pairs passing the filter with an intersector
    std::vector<ModelPair> unsupported_;
    bool any_pair_writes_models_ = false;
    std::vector<NearPair> near_;  ///< this detection's, in order
    // the sweep's scratch
    std::vector<std::size_t> sweep_;
    std::vector<Aabb> sweep_boxes_;
    tbb::enumerable_thread_specific<std::vector<NearPair>> sweep_lists_;  ///< each thread's pairs
    std::vector<NearPair> sort_swap_;  ///< near_'s radix sort: its other buffer and counts
    std::vector<std::size_t> sort_counts_;
};

}  // namespace penalty::detail
