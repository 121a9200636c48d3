#pragma once
/// @file
/// The candidate cache of the BVH detection (private to the collision stage).
///
/// Each model pair keeps its candidate element pairs from step to step, collected with its
/// models' boxes grown by a slack, and only box-tests them again while no element box has moved
/// past that slack since the collection (a "generation" of each model): the candidates are then
/// exactly the traversal's, so are the outputs. Each moving model's slack adapts to how long its
/// generations last (track_motion).

#include "broad_phase.hpp"
#include "narrow_phase.hpp"

#include "penalty/collision/bvh.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/collision/sofa_traversal_order.hpp"
#include "penalty/core/index_types.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penalty::detail {

/// What a pair's detection counted (added to the pipeline's totals by the thread that ran it).
struct PairCounts {
    CollisionPipeline::CandidateCacheStats cache;
    std::size_t candidates = 0;
    void add_to(CollisionPipeline::CandidateCacheStats& stats, std::size_t& candidates_evaluated) const;
};

/// A model's generation: the element boxes at its start and the slack they may move by.
struct ModelMotion {
    std::vector<Aabb> reference;
    double slack = 0.0;
    std::uint64_t generation = 0;     ///< 0: none (its pairs traverse the trees)
    std::size_t steps = 0;            ///< refits since the generation began
    std::size_t uncached_refits = 0;  ///< > 0: too fast for the cache for that many more refits
    /// largest side of a Triangle or Line element box at the tree's last build (separation.hpp)
    double longest_side = 0.0;
    /// the keys its pairs kept in this generation, and how many of them overlapped at their
    /// last detection (the cheap-slack rule of track_motion)
    std::size_t kept_keys = 0;
    std::size_t overlapping_keys = 0;
};

/// A pair's kept candidates. Sorted in SOFA's visiting order once the outputs sorted in this
/// generation outnumber the keys (then the outputs come out in it); the keys sure to overlap
/// until the generations end are flagged (sure) and not box-tested.
struct PairCandidates {
    std::uint64_t generation1 = 0, generation2 = 0;
    Keys keys;
    bool in_sofa_order = false;
    std::size_t outputs_sorted = 0;  ///< outputs sorted by detect_pair in this generation
    bool nearest_outputs = false;    ///< contact outputs only, for a kernel of outputs_nearest_to_element2
    std::size_t overlapped_last = 0;
    std::vector<std::uint8_t> sure;
    std::size_t sure_count = 0;  ///< the keys sure to overlap
    bool sure_current = false;
};

/// One pair's detection through the cache: its models, trees and motions, the pipeline's
/// parameters, and where its SOFA order comes from.
struct CachedPair {
    const IntersectionParams& params;
    const CollisionPipelineOptions& options;
    CollisionModel& m1;
    const Bvh& t1;
    const ModelMotion& a;
    CollisionModel& m2;
    const Bvh& t2;
    const ModelMotion& b;
    SofaOrderTrees& sofa_trees;
    std::size_t i1, i2;  ///< the models' places in the pipeline (sofa_trees)
    const std::vector<CollisionModel*>& models;
};

class CandidateCache {
public:
    /// Every model untracked and every pair forgotten.
    void reset(std::size_t models);
    void add_model() { motion_.emplace_back(); }
    [[nodiscard]] ModelMotion& motion(std::size_t i) { return motion_[i]; }
    [[nodiscard]] const ModelMotion& motion(std::size_t i) const { return motion_[i]; }
    /// After model i's tree was refitted or built: a new generation when its boxes moved past
    /// their slack (the slack adapted), or the model left untracked for a while.
    void track_motion(std::size_t i, const Bvh& tree, const CollisionModel& model, double alarm_distance);
    /// The entries of this detection's near pairs (`near`, in order): the last detection's entry
    /// of a pair carried over, a new pair's empty, the others' dropped (the cache holds the near
    /// pairs only). kept[p]: near[p]'s entry, or nullptr when one of its models is untracked.
    void follow(const std::vector<NearPair>& near, std::vector<PairCandidates*>& kept);
    /// The kept candidates of pair (i1, i2) (registered order) if it was near at the last
    /// detection, else an empty entry of one use; nullptr when a model is untracked.
    [[nodiscard]] PairCandidates* entry(ModelIndex i1, ModelIndex i2);
    /// Adds to the models at `places` the kept and overlapping keys of their pair's entry `kept`
    /// (nullptr: none) in their current generations.
    void count_kept_keys(const std::array<ModelIndex, 2>& places, const PairCandidates* kept);
    /// The outputs of `pair` from its kept candidates, collected again when a generation moved
    /// on: the traversal's candidates, so the traversal's outputs. Returns whether they are in
    /// SOFA's order.
    static bool detect(const CachedPair& pair, PairCandidates& kept, NarrowPhaseScratch::Buffers& buf,
                       SofaOrderScratch& sofa_scratch, PairCounts& counts, Keys* deferred_writes,
                       DetectionOutputList& out);

private:
    /// Collects the pair's candidates again, with the boxes grown by 2·(s1 + s2).
    static void collect(const CachedPair& pair, PairCandidates& kept, NarrowPhaseScratch::Buffers& buf,
                        SofaOrderScratch& sofa_scratch, bool writes_models);
    /// Box-tests the kept keys with the pair's margin into buf.keys (their order kept).
    static void test_kept_keys(const CachedPair& pair, PairCandidates& kept, double margin, Keys& now,
                               PairCounts& counts);
    struct Entry {
        NearPair pair;
        PairCandidates candidates;
    };
    std::vector<ModelMotion> motion_;
    std::uint64_t generations_ = 0;  ///< generations begun, all models together (each one unique)
    std::vector<Entry> entries_;     ///< the last detection's near pairs', in order
    std::vector<Entry> next_;        ///< follow()'s other buffer
    PairCandidates one_use_;         ///< entry() of a pair that was not near
};

/// The largest change of any box bound between two lists of the same size (stops above `limit`).
[[nodiscard]] double largest_bound_change(std::span<const Aabb> now, std::span<const Aabb> before, double limit);

}  // namespace penalty::detail
