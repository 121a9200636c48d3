#pragma once
/// @file
/// Collision detection of a whole scene: SOFA's CollisionPipeline with BruteForceBroadPhase and
/// BVHNarrowPhase (spec §3.8, §4), re-implemented with per-model bounding trees (bvh.hpp), a
/// parallel dual-tree traversal and parallel element evaluation.
///
/// Guarantees (tested against the exhaustive loop, detect_scene_exhaustive):
/// - the model pairs, their keys (model1, model2 in the intersector's registered order) and
///   their order are those of BruteForceBroadPhase; pairs without outputs are dropped;
/// - the outputs of each pair are exactly those of detect_model_pair, in the same order:
///   element pairs by (elem1, elem2) ascending, each pair's outputs in kernel order. The output
///   is therefore bit-identical for any number of threads.

#include "penalty/collision/bvh.hpp"
#include "penalty/collision/intersection.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace penalty {

/// The outputs of one model pair (SOFA's map entry (model1, model2) → DetectionOutputVector).
struct ModelPairOutputs {
    CollisionModel* model1 = nullptr;  ///< first in the intersector's registered order
    CollisionModel* model2 = nullptr;
    DetectionOutputList outputs;
};

/// All outputs of one detection, model pairs in broad-phase order.
using SceneDetection = std::vector<ModelPairOutputs>;

/// A model pair kept by the broad phase, in registered order.
struct ModelPair {
    CollisionModel* model1 = nullptr;
    CollisionModel* model2 = nullptr;
};

/// True when `params` has an active intersector for the pair of types (Supported and its use*
/// switch on, or BeyondSofa with enable_beyond_sofa_pairs).
[[nodiscard]] bool has_active_intersector(const IntersectionParams& params, ModelType a, ModelType b);

/// SOFA's BruteForceBroadPhase: for each model in order (inactive or empty models are skipped),
/// first the model with itself if keep_model_pair(m, m) (active, simulated, self_collision),
/// then the model against every previously added model (earliest first) if
/// keep_model_pair and the method has an active intersector for the pair. Pairs are returned in
/// registered order. If `roots` is given (root box per model, same indexing), pairs whose root
/// boxes do not overlap with the §3.8 margin are also dropped (pruning only).
[[nodiscard]] std::vector<ModelPair> brute_force_broad_phase(const IntersectionParams& params,
                                                             const std::vector<CollisionModel*>& models,
                                                             const std::vector<Aabb>* roots = nullptr);

/// SOFA's cube-test margin for a model pair (§3.8): Discrete → alarm_distance, otherwise
/// alarm_distance + contact_distance(m1) + contact_distance(m2).
[[nodiscard]] double box_margin(const IntersectionParams& params, const CollisionModel& m1,
                                const CollisionModel& m2);

/// Tuning of the narrow phase (none of it changes the output).
struct NarrowPhaseOptions {
    std::size_t chunk_size = 512;  ///< element pairs per evaluation task (fixed, not per thread)
    bool parallel = true;          ///< false: traverse and evaluate on the calling thread
};

/// Candidate element pairs of (m1, m2) (registered order) found by the dual-tree traversal with
/// the §3.8 margin, as keys (elem1 << 32 | elem2), sorted ascending. For m1 == m2 (same model,
/// same tree) only elem1 > elem2. Does not apply the self-collision element filters.
[[nodiscard]] std::vector<std::uint64_t> bvh_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin,
                                                        bool parallel = true);

/// SOFA's BVHNarrowPhase for one model pair in registered order with up-to-date trees: traverses
/// the trees, applies the self-collision element filters for models of the same node, and calls
/// the pair's intersector. Does not call update()/validate(). Evaluates in parallel over fixed
/// chunks of the sorted candidates, except for NewProximity Triangle–Triangle with SOFA's normal
/// overwrite (§14.4), whose kernel writes the models and runs sequentially.
[[nodiscard]] DetectionOutputList bvh_narrow_phase(const IntersectionParams& params, CollisionModel& m1,
                                                   const Bvh& t1, CollisionModel& m2, const Bvh& t2,
                                                   const NarrowPhaseOptions& opt = {});

/// Options of CollisionPipeline.
struct CollisionPipelineOptions {
    /// SOFA's CollisionPipeline `depth` (default 6, negative → 6). Accepted for scene
    /// compatibility; the trees here always go down to `leaf_size` elements (the output does not
    /// depend on the depth in SOFA either, §3.8).
    int depth = 6;
    std::size_t leaf_size = 8;      ///< maximum elements per leaf
    double rebuild_ratio = 2.0;    ///< moving models: rebuild when refitting degrades the tree (Bvh::refit)
    NarrowPhaseOptions narrow;
};

/// SOFA's CollisionPipeline + BruteForceBroadPhase + BVHNarrowPhase over a fixed list of models.
/// Models are not owned and must outlive the pipeline; their order is SOFA's model order.
class CollisionPipeline {
public:
    explicit CollisionPipeline(IntersectionParams params, CollisionPipelineOptions opt = {});

    /// Sets the models (and forgets the trees).
    void set_models(std::vector<CollisionModel*> models);
    [[nodiscard]] const std::vector<CollisionModel*>& models() const { return models_; }
    [[nodiscard]] const IntersectionParams& params() const { return params_; }
    [[nodiscard]] const CollisionPipelineOptions& options() const { return opt_; }

    /// One detection step. For every active model: validate() (std::invalid_argument naming the
    /// model and the element for NaN/inf positions), then its tree is refitted (moving) or built
    /// once (moving = false). Then the broad phase and, per pair, update() of both models (as
    /// detect_model_pair does) and the narrow phase. Pairs with no output are dropped.
    [[nodiscard]] SceneDetection detect();

    /// The tree of models()[i] (empty before the first detect() or for an inactive model).
    [[nodiscard]] const Bvh& tree(std::size_t i) const { return trees_[i]; }

private:
    IntersectionParams params_;
    CollisionPipelineOptions opt_;
    std::vector<CollisionModel*> models_;
    std::vector<Bvh> trees_;
};

/// Reference: the broad phase of brute_force_broad_phase (without root pruning) followed by
/// detect_model_pair (the exhaustive all-element-pairs loop) for every pair; empty pairs dropped.
[[nodiscard]] SceneDetection detect_scene_exhaustive(const IntersectionParams& params,
                                                     const std::vector<CollisionModel*>& models);

}  // namespace penalty
