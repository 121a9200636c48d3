#pragma once
/// @file
/// The BVH narrow phase's parts (private to the collision stage): the dual-tree traversal that
/// collects a pair's candidate element pairs (bvh_traversal.cpp) and their evaluation by the
/// pair's kernel (narrow_phase.cpp), which CollisionPipeline and its candidate cache share.

#include "kernels.hpp"
#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/collision/detection_output.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <span>
#include <vector>

namespace penalty {

/// Candidate element pairs, each a key PairKey(element 1, element 2).bits().
using Keys = std::vector<std::uint64_t>;

struct NarrowPhaseScratch::Buffers {
    tbb::enumerable_thread_specific<Keys> per_thread;  // traversal output of each thread
    Keys keys;                                         // the sorted candidates
    Keys sorted;                                       // counting sort: its output
    std::vector<std::size_t> start, pos;               // counting sort: bucket starts, cursors
    std::vector<std::size_t> radix_counts;             // radix sort: digit counts
    std::vector<DetectionOutputList> parts;            // parallel evaluation: one list per chunk
    // keep_nearest_candidates: per candidate, the squared distance from element 2's point to
    // element 1's box; per element 2, its nearest candidate and the bound on that distance
    // (keep_least_outputs: the least output value of each element 2)
    std::vector<double> reach;
    std::vector<double> bound;
    std::vector<std::uint32_t> nearest;
    Keys nearest_keys;
    DetectionOutputList nearest_outputs;
    Keys filtered;  // evaluate_candidates: the candidates its kernel's filter keeps
};

namespace detail {

// The traversal's row mode (detail::ElementPlanes): the model on one side of a model pair whose
// Triangle or Line elements are long against the margin R, for a kernel whose outputs join its
// elements' planes or lines to the other elements' boxes (outputs_join_element_points). Once a
// node of that side holds at most kRowNodeMax elements, and the other node more (a single leaf
// is cheaper to test pair by pair), each of its elements descends the other tree alone, and a
// node or element box that its planes clear (every point farther than R) is dropped with all
// it holds: such a pair has no output, so the outputs are the same. The boxes are grown by
// `pad` (the candidate cache's collection: how far they may move while kept).
struct LongElements {
    const CollisionModel* model = nullptr;  // of tree a (side_a) or of tree b
    bool side_a = true;
    double R = 0.0;
    double pad = 0.0;
};

/// The candidates of bvh_candidates, left in b.keys, sorted when `sort` (every buffer of `b`
/// reused). rows: the traversal's row mode (LongElements), or nullptr.
void collect_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin, bool parallel, bool sort,
                        NarrowPhaseScratch::Buffers& b, const LongElements* rows = nullptr);

/// A kernel that writes the models (detail::KernelParts) needs its candidates in a fixed order.
[[nodiscard]] bool kernel_writes_models(const IntersectionParams& p, const CollisionModel& m1,
                                        const CollisionModel& m2);

/// The largest side of an element box of a Triangle or Line model (0 for the other models, whose
/// kernels have no separation tests).
[[nodiscard]] double longest_box_side(const CollisionModel& m, const Bvh& t);

/// The row mode of a model pair (LongElements) whose Triangle or Line element boxes have sides
/// up to side1 and side2 (longest_box_side), or none (model nullptr): a model with elements worth
/// separating (worth_separating), of a kernel whose outputs join element points
/// (outputs_join_element_points); the one with fewer elements if both are long.
[[nodiscard]] LongElements long_elements(const IntersectionParams& params, const CollisionModel& m1, double side1,
                                         const CollisionModel& m2, double side2);

/// The kernel's writes (KernelParts::writes, not null) over the candidates `keys` of m1 × m2 in
/// their order; within one node, the element pairs that may not collide are skipped, as
/// evaluate_candidates skips them.
void run_kernel_writes(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                       const KernelParts& kernel, std::span<const std::uint64_t> keys);

/// Intersects the candidates `all_keys` of m1 × m2 in their order: the kernel's filter first, if
/// it has one (KernelParts::filter: drops candidates that give no output), then its writes to the
/// models, over all candidates in order, then its reads, in parallel chunks concatenated in chunk
/// order (the outputs of the sequential loop). separation_tests: the kernels run their early outs
/// (separation.hpp) on every candidate. deferred_writes: if not null, the kernel's writes are not
/// run but their candidates appended to it, in the order they would have run in
/// (run_kernel_writes runs them later).
void evaluate_candidates(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2, const Keys& all_keys,
                         const NarrowPhaseOptions& opt, NarrowPhaseScratch::Buffers& b, DetectionOutputList& out,
                         bool separation_tests, Keys* deferred_writes);

/// CollisionPipelineOptions::contact_outputs_only for a kernel of outputs_nearest_to_element2
/// is worth its cost: at least 8 candidates per element of m2 (narrow_phase.cpp).
[[nodiscard]] bool worth_keeping_nearest(std::size_t candidates, const CollisionModel& m2);

/// Drops from `keys` (the rest kept in order) the candidates none of whose outputs a contact can
/// be made of (narrow_phase.cpp says why that is exact).
void keep_nearest_candidates(const IntersectionParams& params, CollisionModel& m1, const Aabb* boxes1,
                             CollisionModel& m2, Keys& keys, NarrowPhaseScratch::Buffers& b, bool separation_tests,
                             Keys* deferred_writes);

/// After keep_nearest_candidates and the evaluation of the candidates left: drops from
/// out[from, end) every output whose value is above the least value of its element 2.
void keep_least_outputs(DetectionOutputList& out, std::size_t from, std::size_t n2, NarrowPhaseScratch::Buffers& b);

/// std::invalid_argument when a tree's element count is not its model's size.
void check_trees(const CollisionModel& m1, const Bvh& t1, const CollisionModel& m2, const Bvh& t2);

/// bvh_narrow_phase with the sizes of the models' longest element boxes (longest_box_side) given
/// by the caller: they decide the pair's separation tests and the traversal's row mode.
/// contact_outputs_only: keep_nearest_candidates for a kernel of outputs_nearest_to_element2.
void narrow_phase_on_trees(const IntersectionParams& params, CollisionModel& m1, const Bvh& t1, CollisionModel& m2,
                           const Bvh& t2, const NarrowPhaseOptions& opt, NarrowPhaseScratch& scratch,
                           DetectionOutputList& out, double side1, double side2, bool contact_outputs_only = false,
                           Keys* deferred_writes = nullptr);

}  // namespace detail
}  // namespace penalty
