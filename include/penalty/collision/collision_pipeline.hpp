#pragma once
/// @file
/// Collision detection of a whole scene, the one detection driver (`penalty run`, the tests and
/// the benchmarks all go through CollisionPipeline::detect): SOFA's CollisionPipeline with
/// BruteForceBroadPhase and BVHNarrowPhase (spec §3.8, §4), re-implemented with per-model
/// bounding trees (bvh.hpp), a parallel dual-tree traversal and parallel element evaluation, or
/// with the exhaustive all-element-pairs loop (ContactDetection::exhaustive, the reference).
///
/// Guarantees (tested: BVH against exhaustive):
/// - the model pairs are those of broad_phase() that SOFA's broad phase hands to the narrow
///   phase (neither model empty, root boxes within the margin), in broad_phase()'s order, each
///   keyed (model1, model2) in the intersector's registered order, with or without outputs (a
///   kept pair whose root boxes are apart has none and is not listed);
/// - the outputs of each pair are exactly those of exhaustive_narrow_phase, in the same order:
///   element pairs by (elem1, elem2) ascending, each pair's outputs in kernel order. The output
///   is therefore bit-identical for any number of threads and either detection.
/// - in steady state (same pairs, outputs no more numerous than before) detect() allocates
///   nothing: the result and every scratch buffer keep their capacity from step to step.

#include "penalty/collision/bvh.hpp"
#include "penalty/collision/intersection.hpp"
#include "penalty/collision/sofa_traversal_order.hpp"
#include "penalty/core/fidelity.hpp"
#include "penalty/core/index_types.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace penalty {

namespace detail {
class BroadPhase;
class CandidateCache;
struct PairCandidates;
struct PairCounts;
}  // namespace detail

/// All outputs of one detection: one entry per pair the broad phase hands to the narrow phase,
/// in broad_phase()'s order (ModelPairDetection::narrow_phase set in each).
using SceneDetection = std::vector<ModelPairDetection>;

/// A model pair kept by the broad phase, in registered order.
struct ModelPair {
    CollisionModel* model1 = nullptr;
    CollisionModel* model2 = nullptr;
    friend bool operator==(const ModelPair&, const ModelPair&) = default;
};

/// SOFA's broad-phase filter over the models in order (BruteForceBroadPhase::addCollisionModel):
/// for each model j, the pair (j, j), then (j, i) for i = 0 … j−1, each kept when it passes
/// keep_model_pair (active, simulated, self_collision, groups), keyed in registered order (a
/// pair of two models of one type stays (models[j], models[i]): the later model first).
/// Pairs with an active intersector go to `pairs`; the others (the method ignores or does not
/// support them) to `unsupported` when given. Both are cleared first. Throws
/// std::invalid_argument for a null model. `indices`, when given, receives for each entry of
/// `pairs` the places of its model1 and model2 in `models`.
void broad_phase(const IntersectionParams& params, std::span<CollisionModel* const> models,
                 std::vector<ModelPair>& pairs, std::vector<ModelPair>* unsupported = nullptr,
                 std::vector<std::array<ModelIndex, 2>>* indices = nullptr);

/// Tuning of the narrow phase (none of it changes the output).
struct NarrowPhaseOptions {
    std::size_t chunk_size = 512;  ///< element pairs per evaluation task (fixed, not per thread)
    bool parallel = true;          ///< false: traverse and evaluate on the calling thread
    /// true: candidates evaluated, and outputs given, in (element 1, element 2) order. false: in
    /// the traversal's order (which depends on the threads), for a caller that sorts the outputs
    /// itself (SOFA's output order); a kernel that writes the models (NewProximity Triangle–
    /// Triangle's normal overwrite) still makes its writes in (element 1, element 2) order.
    bool sorted_candidates = true;
};

/// Buffers of the BVH narrow phase, kept from call to call so that a steady state allocates
/// nothing (opaque; one per driver, not shared between threads).
class NarrowPhaseScratch {
public:
    NarrowPhaseScratch();
    ~NarrowPhaseScratch();
    NarrowPhaseScratch(const NarrowPhaseScratch&) = delete;
    NarrowPhaseScratch& operator=(const NarrowPhaseScratch&) = delete;
    NarrowPhaseScratch(NarrowPhaseScratch&&) noexcept;
    NarrowPhaseScratch& operator=(NarrowPhaseScratch&&) noexcept;
    struct Buffers;
    [[nodiscard]] Buffers& buffers() { return *buffers_; }

private:
    std::unique_ptr<Buffers> buffers_;
};

/// Candidate element pairs of (m1, m2) (registered order) found by the dual-tree traversal with
/// the §3.8 margin, as keys (PairKey(elem1, elem2).bits()), sorted ascending. For m1 == m2 (same model,
/// same tree) only elem1 > elem2. Does not apply the self-collision element filters.
[[nodiscard]] std::vector<std::uint64_t> bvh_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin,
                                                        bool parallel = true);

/// SOFA's BVHNarrowPhase for one model pair in registered order with up-to-date trees: traverses
/// the trees, applies the self-collision element filters for models of the same node, and calls
/// the pair's intersector, appending to `out`. Does not call update()/validate(). Evaluates in
/// parallel over fixed chunks of the candidates; a kernel's writes to the models (NewProximity
/// Triangle–Triangle's normal overwrite, §14.4) run first, on one thread, in candidate order.
/// Throws std::invalid_argument, as intersect_elements does, for models not in
/// registered order or a pair with no active intersector (checked once, even with no candidate).
void bvh_narrow_phase(const IntersectionParams& params, CollisionModel& m1, const Bvh& t1, CollisionModel& m2,
                      const Bvh& t2, const NarrowPhaseOptions& opt, NarrowPhaseScratch& scratch,
                      DetectionOutputList& out);

/// How the narrow phase of a model pair is done (identical outputs either way).
enum class ContactDetection : std::uint8_t {
    exhaustive,  ///< exhaustive_narrow_phase: every element pair (box-tested), O(n1·n2) per pair
    bvh,         ///< per-model Bvh + root pruning + bvh_narrow_phase (parallel, TBB)
};

/// Whether CollisionPipeline::detect runs its model pairs in parallel (the outputs and the
/// models' stored data are the same bits in every case).
enum class PairConcurrency : std::uint8_t {
    automatic,  ///< when worth it (CollisionPipeline::detect)
    always,     ///< whenever two pairs have their root boxes within the margin
    never,      ///< one pair after the other (each pair's narrow phase still parallel)
};

/// A narrow phase that replaces BVHNarrowPhase for every pair (SOFA's RayTraceNarrowPhase,
/// ray_trace_narrow_phase.hpp): CollisionPipeline::detect hands it the broad phase's pairs
/// (refitted models, outputs empty, narrow_phase set) and returns its detections.
class NarrowPhaseOverride {
public:
    virtual ~NarrowPhaseOverride() = default;
    virtual const std::vector<ModelPairDetection>& detect(const std::vector<ModelPairDetection>& broad_pairs) = 0;
    [[nodiscard]] virtual const std::vector<ModelPairDetection>& detections() const = 0;
};

/// Options of CollisionPipeline.
struct CollisionPipelineOptions {
    /// SOFA's CollisionPipeline `depth` (default 6, negative → 6): the depth of SOFA's bounding
    /// trees, which decides the order of the outputs (sofa_traversal_order.hpp); the set of
    /// outputs does not depend on it (§3.8), and penalty's own trees go down to `leaf_size`.
    int depth = 6;
    /// Each pair's outputs in SOFA's BVHNarrowPhase order (sofa_traversal_order.hpp); false:
    /// ascending (elem1, elem2), which is cheaper for large pairs and not SOFA's.
    bool sofa_output_order = true;
    std::size_t leaf_size = 8;   ///< maximum elements per leaf
    double rebuild_ratio = 2.0;  ///< moving models: rebuild when refitting degrades the tree (Bvh::refit)
    /// bvh: keep each model pair's candidates from step to step (CollisionPipeline, "candidate
    /// cache") and only box-test them again while no element box has moved past the slack they
    /// were collected with; the outputs are the same as traversing the trees at every step.
    bool candidate_cache = true;
    /// bvh: give only the outputs a penalty contact may be made of. BarycentricPenaltyContact
    /// keeps, per id, the first output of least value (ContactTracker); for the kernels whose
    /// outputs all carry element 2 as id and measure a distance from element 2's point to
    /// element 1 (Line and Triangle against Point and spheres), the candidates that cannot give
    /// an output of that least value are not evaluated (CollisionPipeline::detect). The contacts
    /// are those of all outputs; detections() lists fewer. ContactPipeline sets it unless told
    /// otherwise (ContactPipelineOptions::all_detection_outputs).
    bool contact_outputs_only = false;
    /// bvh, more than one thread: the model pairs in parallel (see CollisionPipeline::detect).
    PairConcurrency pair_concurrency = PairConcurrency::automatic;
    NarrowPhaseOptions narrow;
    /// When set, the narrow phase of every pair (NarrowPhaseOverride).
    std::shared_ptr<NarrowPhaseOverride> narrow_phase_override;
};

/// SOFA's CollisionPipeline + BruteForceBroadPhase + BVHNarrowPhase over a list of models.
/// Models are not owned and must outlive the pipeline; their order is SOFA's model order.
class CollisionPipeline {
public:
    /// Throws std::invalid_argument for invalid `params`, leaf_size 0 or rebuild_ratio < 1.
    explicit CollisionPipeline(IntersectionParams params, CollisionPipelineOptions opt = {},
                               ContactDetection detection = kFidelityDefaults.exhaustive_detection
                                                                ? ContactDetection::exhaustive
                                                                : ContactDetection::bvh);

    /// Sets the models (and forgets the trees).
    void set_models(std::vector<CollisionModel*> models);
    /// Appends one model (its tree is built at the next refit).
    void add_model(CollisionModel& model);
    [[nodiscard]] const std::vector<CollisionModel*>& models() const { return models_; }
    [[nodiscard]] const IntersectionParams& params() const { return params_; }
    [[nodiscard]] const CollisionPipelineOptions& options() const { return opt_; }
    [[nodiscard]] ContactDetection detection() const { return detection_; }

    /// One detection step: refit(), broad_phase(), then for each kept pair (registered order)
    /// its narrow phase: exhaustive_narrow_phase's element loop, or (bvh), unless the root boxes
    /// are apart by more than the §3.8 margin, bvh_narrow_phase. Returns every
    /// kept pair (outputs possibly empty; narrow_phase false when SOFA's broad phase would drop
    /// it: root boxes apart or a model empty); the reference is valid until the next detect().
    /// bvh, with NarrowPhaseOptions::parallel and more than one thread in the calling arena:
    /// the pairs are detected in parallel, in contiguous chunks of pairs, each chunk on one
    /// thread with its own buffers (their capacity kept from step to step), when a pair's
    /// kernel that writes the models has its writes read by writes alone
    /// (detail::model_writes_read_only_by_writes: NewProximity Triangle–Triangle's normal
    /// overwrite; then the pairs' writes run after the pairs, in pair order, on this thread) and
    /// - PairConcurrency::always: two pairs have their root boxes within the margin;
    /// - automatic: at the last detection two of these pairs evaluated at least
    ///   kMinCandidatesPerConcurrentPair candidates each, and all pairs together at least
    ///   kMinCandidatesForConcurrentPairs and at least as many as the elements of the moving
    ///   models refitted. (The tasks pull the pairs' models and trees into the other core's
    ///   caches, and the next refit of large moving models pays for it: Gravity's refit took
    ///   0.149 → 0.183 ms for pairs 0.067 → 0.053 ms; docs/performance.md.)
    /// A pair's outputs do not depend on the others', so they are the same bits either way; a
    /// failing pair's exception is the first in pair order. last_detection_concurrent() says
    /// which way the last detection went.
    const SceneDetection& detect();
    /// PairConcurrency::automatic: the candidates a pair, and all pairs together, evaluated at
    /// the last detection for the next one to run pairs in parallel.
    static constexpr std::size_t kMinCandidatesPerConcurrentPair = 32;
    static constexpr std::size_t kMinCandidatesForConcurrentPairs = 256;
    /// Whether the last detect() ran its model pairs in parallel.
    [[nodiscard]] bool last_detection_concurrent() const { return last_concurrent_; }
    /// The result of the last detect().
    [[nodiscard]] const SceneDetection& detections() const {
        return opt_.narrow_phase_override ? opt_.narrow_phase_override->detections() : result_;
    }
    /// Pairs of the last detect() that passed the model-pair filter but have no active
    /// intersector (the method ignores or does not support them): not detected.
    [[nodiscard]] const std::vector<ModelPair>& unsupported_pairs() const;

    /// For every active model, once per detection (SOFA's computeBoundingTree): validate()
    /// (std::invalid_argument naming the model and the element for NaN/inf positions), update()
    /// (triangle normals, tetrahedron coord2bary; a static model's only once) and, bvh, its tree
    /// refitted (moving) or built once (moving = false; rebuilt if its size changed). A moving
    /// model of the bvh detection is checked by validate_for_step(), the same outcome.
    void refit();
    /// The narrow phase of one pair (m1, m2 registered here, in registered order, with an active
    /// intersector) at the current positions, as detect() does it; trees as left by refit().
    /// `out` is cleared first.
    void detect_pair(CollisionModel& m1, CollisionModel& m2, DetectionOutputList& out);

    /// The tree of models()[i] (empty before the first detect() or for an inactive model, and
    /// always for the exhaustive detection).
    [[nodiscard]] const Bvh& tree(std::size_t i) const { return trees_[i]; }

    /// Candidate cache statistics since construction: pair detections answered from a pair's
    /// kept candidates (`reused`) and pair detections that traversed the trees (`collected`);
    /// of both, those whose outputs came in SOFA's order without a sort (`in_sofa_order`: the
    /// kept candidates were in that order, PairCandidates) and the times kept candidates were
    /// sorted into it (`sofa_order_sorts`).
    struct CandidateCacheStats {
        std::size_t reused = 0;
        std::size_t collected = 0;
        std::size_t in_sofa_order = 0;
        std::size_t sofa_order_sorts = 0;
        /// pair detections from kept keys (reused or just collected) whose keys were box-tested
        /// without a branch per key (between 1/8 and 7/8 of them overlapped at the last one)
        std::size_t branch_free_tests = 0;
        /// kept keys whose box test was skipped: sure to overlap until their models'
        /// generations end (PairCandidates::sure)
        std::size_t sure_keys_skipped = 0;
    };
    [[nodiscard]] const CandidateCacheStats& candidate_cache_stats() const { return cache_stats_; }
    /// Element pairs handed to the kernels by the bvh detection since construction (the
    /// candidates left by the box tests and the traversal's plane tests; 0 for exhaustive).
    [[nodiscard]] std::size_t candidates_evaluated() const { return candidates_evaluated_; }

    ~CollisionPipeline();
    CollisionPipeline(CollisionPipeline&&) noexcept;
    CollisionPipeline& operator=(CollisionPipeline&&) noexcept;

private:
    [[nodiscard]] ModelIndex model_index(const CollisionModel& m) const;
    void index_models();  // index_of_ from models_
    /// ModelPairDetection::narrow_phase of models_[i1], models_[i2]: neither empty, root boxes
    /// within box_margin.
    [[nodiscard]] bool roots_within_margin(ModelIndex i1, ModelIndex i2) const;
    /// The buffers of pair detections that run one after the other (detect() in parallel gives
    /// each chunk of pairs its own).
    struct PairScratch {
        NarrowPhaseScratch narrow;
        SofaOrderScratch sofa_order;
    };
    /// detect_pair with the given buffers. `kept`: the pair's entry of the candidate cache, made
    /// beforehand (the cache is not changed while pairs run in parallel), or nullptr: traverse
    /// the trees. The models are models_[i1] and models_[i2]. `deferred_writes`: if not null,
    /// the kernel's writes to the models are not run but their candidates appended to it, in
    /// their order.
    void detect_pair_with(ModelIndex i1, ModelIndex i2, DetectionOutputList& out, PairScratch& scratch,
                          detail::PairCounts& counts, detail::PairCandidates* kept,
                          std::vector<std::uint64_t>* deferred_writes = nullptr);
    /// detect_pair without sorting into SOFA's output order. Returns true when `out` is in that
    /// order already (the candidate cache's kept pairs are kept in it, PairCandidates).
    [[nodiscard]] bool detect_pair_unordered(std::size_t i1, std::size_t i2, DetectionOutputList& out,
                                             PairScratch& scratch, detail::PairCounts& counts,
                                             detail::PairCandidates* kept, std::vector<std::uint64_t>* deferred_writes);
    /// The pair's entry of the candidate cache when it applies to the pair (bvh, the cache on,
    /// both models tracked), made if new; nullptr otherwise.
    [[nodiscard]] detail::PairCandidates* pair_candidates_entry(ModelIndex i1, ModelIndex i2);
    /// pair_kept_: the candidate cache's entries of the broad phase's near() (all nullptr when
    /// the cache does not apply).
    void follow_candidate_cache();
    /// Work of the near pair at `place` in the broad phase's near() (this detection's).
    void record_pair_work(std::size_t place, std::size_t candidates);
    /// result_: one entry per near pair, outputs empty; a pair near at the last detection too
    /// gets its own output list back (its capacity), the lists of the pairs no longer near are
    /// freed.
    void list_near_pairs();
    /// Whether detect() runs this detection's pairs in parallel (see detect()).
    [[nodiscard]] bool pairs_run_concurrently() const;
    void detect_pairs_in_order();
    void detect_pairs_concurrently();
    /// The exhaustive detection's root boxes (those the trees would give).
    void find_exhaustive_root_boxes();

    IntersectionParams params_;
    CollisionPipelineOptions opt_;
    ContactDetection detection_;
    std::vector<CollisionModel*> models_;
    std::vector<Bvh> trees_;
    std::vector<std::pair<const CollisionModel*, std::size_t>> index_of_;  // sorted by address
    std::unique_ptr<detail::BroadPhase> broad_;      ///< the pairs, kept while the models' keys hold
    std::unique_ptr<detail::CandidateCache> cache_;  ///< bvh: each pair's candidates kept (candidate_cache.hpp)
    SofaOrderTrees sofa_trees_;                      ///< per model: SOFA's tree, built at its first detection
    CandidateCacheStats cache_stats_;
    std::size_t candidates_evaluated_ = 0;
    PairScratch scratch_;                     // detect_pair's, and detect()'s when the pairs run in order
    std::vector<PairScratch> chunk_scratch_;  // detect()'s in parallel: one per chunk of pairs (kChunksPerThread)
    std::vector<detail::PairCandidates*> pair_kept_;  // scratch: per pair of near(), its cache entry or nullptr
    /// A near pair as the next detection finds it again: its order and models.
    struct ListedPair {
        std::uint64_t order = 0;  ///< detail::NearPair::order
        const CollisionModel* model1 = nullptr;
        const CollisionModel* model2 = nullptr;
        [[nodiscard]] bool operator==(const ListedPair&) const = default;
    };
    /// What a near pair evaluated (pairs_run_concurrently's automatic rule).
    struct PairWork {
        ListedPair pair;
        std::size_t candidates = 0;
    };
    std::vector<PairWork> pair_work_;                  // this detection's, per pair of near()
    std::vector<PairWork> pair_work_last_;             // the last detection's, by order
    std::vector<ListedPair> listed_;                   // result_'s pairs, by order
    std::vector<DetectionOutputList> listed_outputs_;  // list_near_pairs' scratch: the last pairs' lists
    std::size_t moving_elements_ = 0;                  // elements of the moving models the last refit() refitted
    bool last_concurrent_ = false;
    std::vector<std::vector<std::uint64_t>>
        deferred_writes_;           // per pair of near(): its writes' candidates (detect_pairs_concurrently)
    SceneDetection result_;         // entries kept; each near pair's output list kept with it
    std::vector<Aabb> boxes_;       // exhaustive: element boxes of model 2
    std::vector<Aabb> root_boxes_;  // exhaustive: each model's root box (union of its element boxes)
};

}  // namespace penalty
