#pragma once
/// @file
/// The broad phase kept from step to step (private to the collision stage).
///
/// broad_phase()'s pairs depend only on the models and the parameters its filters read
/// (keep_model_pair, the intersectors, kernel_writes_models): they are made again only when one
/// of those changed (update). Of those pairs, the BVH detection finds the ones whose root boxes
/// are within the margin (find_near) by a sweep over the models' root boxes instead of testing
/// every pair: a pile of n bodies has n²/2 pairs and about 6n near ones. The pairs, their order,
/// their flags and outputs are those of the test of every pair.

#include "penalty/collision/bvh.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/core/index_types.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

namespace penalty::detail {

class BroadPhase {
public:
    /// Makes the pairs again if a model or a filter's parameter changed since the last call;
    /// returns whether it did (then `result` has one entry per pair, flags and outputs reset).
    bool update(const IntersectionParams& params, const std::vector<CollisionModel*>& models, SceneDetection& result);
    /// The pairs whose root boxes are within the margin (`within_margin(i1, i2)` on the models'
    /// places), ascending, into near(); near_last() keeps the previous ones; `result`'s
    /// narrow_phase flags and the outputs of pairs that left are updated.
    void find_near(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
                   const std::vector<Bvh>& trees, const std::function<bool(ModelIndex, ModelIndex)>& within_margin,
                   SceneDetection& result);
    [[nodiscard]] const std::vector<ModelPair>& pairs() const { return pairs_; }
    /// Per pair: the places of its model1 and model2 in the models.
    [[nodiscard]] const std::vector<std::array<ModelIndex, 2>>& indices() const { return indices_; }
    [[nodiscard]] const std::vector<ModelPair>& unsupported() const { return unsupported_; }
    [[nodiscard]] const std::vector<std::size_t>& near() const { return near_; }
    [[nodiscard]] const std::vector<std::size_t>& near_last() const { return near_last_; }
    [[nodiscard]] bool is_near(std::size_t k) const { return is_near_[k] != 0; }
    /// Some pair's kernel writes the models (pairs in order, or their writes deferred).
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
    void mark_near(SceneDetection& result);
    std::vector<ModelPair> pairs_;
    std::vector<std::array<ModelIndex, 2>> indices_;
    std::vector<ModelPair> unsupported_;
    std::vector<ModelKey> key_;
    bool any_pair_writes_models_ = false;
    std::unordered_map<PairKey, std::size_t> pair_of_models_;  ///< (lower place, higher place) → pair
    std::vector<std::size_t> near_;       ///< this detection's pairs with a narrow phase, ascending
    std::vector<std::size_t> near_last_;  ///< the last detection's
    std::vector<std::uint8_t> is_near_;   ///< per pair: in near_
    // the sweep's scratch
    std::vector<std::size_t> sweep_;
    std::vector<std::size_t> sweep_active_;
    std::vector<Aabb> sweep_boxes_;
    std::vector<std::size_t> sweep_swap_;  ///< near_'s radix sort: its other buffer and counts
    std::vector<std::size_t> sweep_counts_;
};

}  // namespace penalty::detail
