// CollisionPipeline: one detection step over a list of models (refit, broad phase, each pair's
// narrow phase, in order or in parallel); the broad phase, the candidate cache and the narrow
// phase are broad_phase.cpp, candidate_cache.cpp and narrow_phase.cpp / bvh_traversal.cpp.
#include "penalty/collision/collision_pipeline.hpp"

#include "broad_phase.hpp"
#include "candidate_cache.hpp"
#include "kernels.hpp"
#include "narrow_phase.hpp"
#include "penalty/core/error.hpp"
#include "penalty/core/first_error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <mutex>

namespace penalty {

namespace {
constexpr std::size_t kChunksPerThread = 4;  // detect() in parallel: chunks of pairs per thread
}  // namespace

CollisionPipeline::CollisionPipeline(IntersectionParams params, CollisionPipelineOptions opt,
                                     ContactDetection detection)
    : params_(params),
      opt_(std::move(opt)),
      detection_(detection),
      broad_(std::make_unique<detail::BroadPhase>()),
      cache_(std::make_unique<detail::CandidateCache>()) {
    params_.validate();
    if (opt_.depth < 0) opt_.depth = 6;  // SOFA resets a negative depth to 6
    if (opt_.leaf_size == 0) throw_invalid_argument("CollisionPipeline: leaf_size must be >= 1");
    if (!(opt_.rebuild_ratio >= 1.0)) throw_invalid_argument("CollisionPipeline: rebuild_ratio must be >= 1");
    sofa_trees_ = SofaOrderTrees(opt_.depth);
}

CollisionPipeline::~CollisionPipeline() = default;
CollisionPipeline::CollisionPipeline(CollisionPipeline&&) noexcept = default;
CollisionPipeline& CollisionPipeline::operator=(CollisionPipeline&&) noexcept = default;

const std::vector<ModelPair>& CollisionPipeline::unsupported_pairs() const { return broad_->unsupported(); }

void CollisionPipeline::set_models(std::vector<CollisionModel*> models) {
    for (std::size_t i = 0; i < models.size(); ++i)
        if (models[i] == nullptr) throw_invalid_argument("CollisionPipeline::set_models(): model ", i, " is null");
    models_ = std::move(models);
    trees_.assign(models_.size(), Bvh{});
    sofa_trees_.reset(models_.size());
    cache_->reset(models_.size());
    index_models();
}

void CollisionPipeline::add_model(CollisionModel& model) {
    models_.push_back(&model);
    trees_.emplace_back();
    sofa_trees_.add_model();
    cache_->add_model();
    index_models();
}

ModelIndex CollisionPipeline::model_index(const CollisionModel& m) const {
    // binary search in (address, index) pairs: a scene with many models asks for two per pair
    const auto it =
        std::lower_bound(index_of_.begin(), index_of_.end(), std::pair<const CollisionModel*, std::size_t>(&m, 0));
    if (it == index_of_.end() || it->first != &m)
        throw_invalid_argument("CollisionPipeline: model '", m.name(), "' is not registered");
    return ModelIndex(static_cast<Index>(it->second));
}

void CollisionPipeline::index_models() {
    index_of_.clear();
    for (std::size_t i = 0; i < models_.size(); ++i) index_of_.emplace_back(models_[i], i);
    std::sort(index_of_.begin(), index_of_.end());
}

void CollisionPipeline::refit() {
    moving_elements_ = 0;
    // SOFA's computeBoundingTree, once per detection for every active model: the model's derived
    // data (CollisionModel::update: triangle normals, tetrahedron coord2bary) and its tree. A
    // kernel's writes to a model (Triangle–Triangle's normal overwrite, §14.4) therefore last
    // until the next detection, through the later pairs of this one, as in SOFA.
    for (std::size_t i = 0; i < models_.size(); ++i) {
        CollisionModel& m = *models_[i];
        if (!m.params().active) continue;
        if (detection_ == ContactDetection::exhaustive) {
            m.validate();
            m.update();
            continue;
        }
        Bvh& tree = trees_[i];
        if (m.params().moving) {
            moving_elements_ += m.size();
            m.validate_for_step();
            m.update();
            // the separation tests' size measured at each (re)build only: it decides speed, never outputs
            if (tree.refit(m, opt_.rebuild_ratio, opt_.leaf_size))
                cache_->motion(i).longest_side = detail::longest_box_side(m, tree);
            if (opt_.candidate_cache) cache_->track_motion(i, tree, m, params_.alarm_distance);
        } else if (tree.build_count() == 0 || tree.element_boxes().size() != m.size()) {
            m.validate();  // static: checked and built once (SOFA: bounding tree computed once)
            m.update();    // a static model's update() computes once
            tree.build(m, opt_.leaf_size);
            cache_->motion(i).longest_side = detail::longest_box_side(m, tree);
            if (opt_.candidate_cache) cache_->track_motion(i, tree, m, params_.alarm_distance);
        }
    }
}

void CollisionPipeline::detect_pair(CollisionModel& m1, CollisionModel& m2, DetectionOutputList& out) {
    detail::PairCounts counts;
    detect_pair_with(model_index(m1), model_index(m2), out, scratch_, counts, nullptr);
    counts.add_to(cache_stats_, candidates_evaluated_);
}

void CollisionPipeline::detect_pair_with(ModelIndex i1, ModelIndex i2, DetectionOutputList& out, PairScratch& scratch,
                                         detail::PairCounts& counts, detail::PairCandidates* kept,
                                         std::vector<std::uint64_t>* deferred_writes) {
    out.clear();
    const bool in_sofa_order = detect_pair_unordered(i1.slot(), i2.slot(), out, scratch, counts, kept, deferred_writes);
    if (!opt_.sofa_output_order || in_sofa_order || out.size() < 2) return;
    sofa_trees_.sort_outputs(models_, i1.slot(), i2.slot(), out, scratch.sofa_order);
}

detail::PairCandidates* CollisionPipeline::pair_candidates_entry(ModelIndex i1, ModelIndex i2) {
    if (detection_ != ContactDetection::bvh || !opt_.candidate_cache) return nullptr;
    return cache_->entry(i1, i2);
}

void CollisionPipeline::follow_candidate_cache() {
    if (detection_ == ContactDetection::bvh && opt_.candidate_cache) cache_->follow(broad_->near(), pair_kept_);
    else pair_kept_.assign(broad_->near().size(), nullptr);
}

bool CollisionPipeline::detect_pair_unordered(std::size_t i1, std::size_t i2, DetectionOutputList& out,
                                              PairScratch& scratch, detail::PairCounts& counts,
                                              detail::PairCandidates* kept_entry,
                                              std::vector<std::uint64_t>* deferred_writes) {
    // the models were validated and update()d by refit()
    CollisionModel& m1 = *models_[i1];
    CollisionModel& m2 = *models_[i2];
    if (detection_ == ContactDetection::exhaustive) {
        PENALTY_DEMAND(deferred_writes == nullptr);  // pairs run in parallel only with bvh
        detail::exhaustive_element_pairs(params_, m1, m2, out, boxes_);
        return false;
    }
    // the same element pairs as the exhaustive loop (bvh_narrow_phase's guarantee)
    const Bvh& t1 = trees_[i1];
    const Bvh& t2 = trees_[i2];
    if (t1.empty() || t2.empty()) return false;
    const detail::ModelMotion& a = cache_->motion(i1);
    const detail::ModelMotion& b = cache_->motion(i2);
    if (!opt_.candidate_cache || a.generation == 0 || b.generation == 0) {
        if (&m1 != &m2 && !t1.root_box().overlaps(t2.root_box(), box_margin(params_, m1, m2))) return false;
        // with SOFA's output order the outputs are sorted afterwards (detect_pair): the
        // candidates need no sort of their own
        NarrowPhaseOptions narrow = opt_.narrow;
        if (opt_.sofa_output_order) narrow.sorted_candidates = false;
        detail::narrow_phase_on_trees(params_, m1, t1, m2, t2, narrow, scratch.narrow, out, a.longest_side,
                                      b.longest_side, opt_.contact_outputs_only, deferred_writes);
        counts.candidates += scratch.narrow.buffers().keys.size();
        return false;
    }
    detail::PairCandidates& kept =
        kept_entry != nullptr ? *kept_entry : *pair_candidates_entry(ModelIndex(Index(i1)), ModelIndex(Index(i2)));
    const detail::CachedPair pair{params_, opt_, m1, t1, a, m2, t2, b, sofa_trees_, i1, i2, models_};
    return detail::CandidateCache::detect(pair, kept, scratch.narrow.buffers(), scratch.sofa_order, counts,
                                          deferred_writes, out);
}

const SceneDetection& CollisionPipeline::detect() {
    refit();
    if (opt_.sofa_output_order)
        sofa_trees_.build_all(models_);  // SOFA computes every model's bounding tree at each detection
    broad_->update(params_, models_);
    const bool exhaustive = detection_ == ContactDetection::exhaustive;
    if (exhaustive) find_exhaustive_root_boxes();
    broad_->find_near(
        params_, models_, trees_, [this](ModelIndex i1, ModelIndex i2) { return roots_within_margin(i1, i2); },
        exhaustive);
    list_near_pairs();
    if (opt_.narrow_phase_override) return opt_.narrow_phase_override->detect(result_);
    last_concurrent_ = pairs_run_concurrently();
    pair_work_.resize(result_.size());
    if (last_concurrent_) detect_pairs_concurrently();
    else detect_pairs_in_order();
    for (std::size_t p = 0; p < pair_kept_.size(); ++p)  // (none kept without the cache)
        cache_->count_kept_keys(broad_->near()[p].places, pair_kept_[p]);
    pair_work_last_.swap(pair_work_);
    return result_;
}

void CollisionPipeline::list_near_pairs() {
    // Each pair keeps its own output list from one detection to the next, so a list's capacity
    // is its pair's largest output count. (Lists kept by place grew, place by place, to the
    // largest pair that ever stood there: in a pile of 512 cubes 29 MB of capacity for the
    // outputs of 14 000 contacts.) Both lists of pairs are in order (detail::NearPair::order).
    const std::vector<detail::NearPair>& near = broad_->near();
    listed_outputs_.resize(result_.size());
    for (std::size_t p = 0; p < result_.size(); ++p) listed_outputs_[p].swap(result_[p].outputs);
    result_.resize(near.size());
    std::size_t last = 0;
    for (std::size_t p = 0; p < near.size(); ++p) {
        ModelPairDetection& d = result_[p];
        d.model1 = models_[near[p].places[0].slot()];
        d.model2 = models_[near[p].places[1].slot()];
        d.support = pair_support(params_, d.model1->type(), d.model2->type());
        d.skipped = false;
        d.narrow_phase = true;
        const ListedPair pair{near[p].order, d.model1, d.model2};
        while (last < listed_.size() && listed_[last].order < pair.order) ++last;
        if (last < listed_.size() && listed_[last] == pair) d.outputs.swap(listed_outputs_[last]);
        d.outputs.clear();
    }
    listed_.resize(near.size());
    for (std::size_t p = 0; p < near.size(); ++p) listed_[p] = {near[p].order, result_[p].model1, result_[p].model2};
    for (DetectionOutputList& unclaimed : listed_outputs_) DetectionOutputList().swap(unclaimed);
}

void CollisionPipeline::find_exhaustive_root_boxes() {
    // the root boxes the trees would give (roots_within_margin)
    root_boxes_.assign(models_.size(), Aabb{});
    for (std::size_t i = 0; i < models_.size(); ++i) {
        const CollisionModel& m = *models_[i];
        if (!m.params().active || m.size() == 0) continue;
        boxes_.resize(m.size());
        m.element_boxes(0, m.size(), boxes_.data());
        for (const Aabb& b : boxes_) root_boxes_[i].extend(b);
    }
}

bool CollisionPipeline::pairs_run_concurrently() const {
    if (detection_ != ContactDetection::bvh || opt_.pair_concurrency == PairConcurrency::never ||
        !opt_.narrow.parallel || tbb::this_task_arena::max_concurrency() < 2)
        return false;
    // a kernel's writes are read by the later pairs of its models (§14.4): pairs in order,
    // unless only writes read them (then the writes of all pairs run after the pairs, in order)
    if (broad_->any_pair_writes_models() && !detail::model_writes_read_only_by_writes(params_)) return false;
    const bool always = opt_.pair_concurrency == PairConcurrency::always;
    std::size_t worth_a_task = 0, candidates = 0;
    // each near pair's candidates at the last detection, if it was near then (both lists in order)
    auto last = pair_work_last_.begin();
    for (std::size_t p = 0; p < result_.size(); ++p) {
        if (always) {
            ++worth_a_task;
            continue;
        }
        const std::uint64_t order = broad_->near()[p].order;
        while (last != pair_work_last_.end() && last->pair.order < order) ++last;
        const bool known =
            last != pair_work_last_.end() && last->pair == ListedPair{order, result_[p].model1, result_[p].model2};
        if (!known) continue;
        candidates += last->candidates;
        worth_a_task += last->candidates >= kMinCandidatesPerConcurrentPair ? 1 : 0;
    }
    if (always) return worth_a_task >= 2;
    return worth_a_task >= 2 && candidates >= std::max(kMinCandidatesForConcurrentPairs, moving_elements_);
}

void CollisionPipeline::record_pair_work(std::size_t place, std::size_t candidates) {
    pair_work_[place] = {{broad_->near()[place].order, result_[place].model1, result_[place].model2}, candidates};
}

void CollisionPipeline::detect_pairs_in_order() {
    // A pair whose root boxes are not within the margin has no element boxes within it (each
    // element box lies in its root box, and the test is monotone in the bounds): no candidates
    // and no outputs, so the detection neither traverses its trees nor looks its candidate
    // cache up (SOFA's BruteForceBroadPhase does not hand such a pair to the narrow phase at
    // all): it runs the pairs of the broad phase's near().
    detail::PairCounts counts;
    const std::vector<detail::NearPair>& near = broad_->near();
    follow_candidate_cache();
    for (std::size_t p = 0; p < near.size(); ++p) {
        const std::size_t before = counts.candidates;
        detect_pair_with(near[p].places[0], near[p].places[1], result_[p].outputs, scratch_, counts, pair_kept_[p]);
        record_pair_work(p, counts.candidates - before);
    }
    counts.add_to(cache_stats_, candidates_evaluated_);
}

void CollisionPipeline::detect_pairs_concurrently() {
    // What the pairs would otherwise make or compute as they go, made first on this thread:
    // their candidate-cache entries (the map does not change while pairs run) and the
    // Triangle planes their separation tests read (a model's, shared by its pairs).
    // (bvh only: the pairs of the broad phase's near(), in order)
    const std::vector<detail::NearPair>& near = broad_->near();
    follow_candidate_cache();
    for (std::size_t p = 0; p < near.size(); ++p) {
        CollisionModel& m1 = *result_[p].model1;
        CollisionModel& m2 = *result_[p].model2;
        if (detail::reads_triangle_planes(detail::pair_kernel_parts(params_, m1, m2))) {
            static_cast<TriangleModel&>(m1).update_planes();
            static_cast<TriangleModel&>(m2).update_planes();
        }
    }
    // Contiguous chunks of pairs, a few per thread (the pairs' costs differ widely: TBB hands
    // the chunks out as threads come free), each with its own buffers: their number and
    // bounds depend only on the number of pairs and of threads, so in steady state each
    // chunk's buffers have the capacity its pairs need and a step allocates nothing. (A thread
    // waiting inside a pair, in a nested parallel traversal or evaluation, may start another
    // chunk: with the other chunk's buffers.) Errors: the first in pair order is rethrown.
    const std::size_t n = near.size();
    const std::size_t chunks =
        std::min(n, kChunksPerThread * std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
    if (chunk_scratch_.size() < chunks) chunk_scratch_.resize(chunks);
    // Kernels that write the models (NewProximity Triangle–Triangle's normal overwrite), read by
    // writes alone (pairs_run_concurrently): each pair keeps its writes' candidates, run below
    // in pair order, as detect_pairs_in_order would have run them.
    const bool defer_writes = broad_->any_pair_writes_models();
    if (defer_writes && deferred_writes_.size() < n) deferred_writes_.resize(n);
    std::mutex merge;
    detail::PairCounts total;
    FirstErrorInOrder failure;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, chunks, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t c = r.begin(); c != r.end(); ++c) {
                detail::PairCounts counts;
                for (std::size_t p = c * n / chunks; p < (c + 1) * n / chunks; ++p) {
                    const bool done = failure.run(p, [&] {
                        const std::size_t before = counts.candidates;
                        Keys* deferred = defer_writes ? &deferred_writes_[p] : nullptr;
                        if (deferred != nullptr) deferred->clear();
                        detect_pair_with(near[p].places[0], near[p].places[1], result_[p].outputs, chunk_scratch_[c],
                                         counts, pair_kept_[p], deferred);
                        record_pair_work(p, counts.candidates - before);
                    });
                    if (!done) break;
                }
                const std::lock_guard lock(merge);
                counts.add_to(total.cache, total.candidates);
            }
        },
        tbb::simple_partitioner());
    total.add_to(cache_stats_, candidates_evaluated_);
    if (defer_writes) {
        // the writes of the pairs before the first that failed (all of them if none did)
        for (std::size_t p = 0; p < n && p < failure.first_index(); ++p) {
            CollisionModel& m1 = *result_[p].model1;
            CollisionModel& m2 = *result_[p].model2;
            const detail::KernelParts kernel = detail::pair_kernel_parts(params_, m1, m2);
            if (kernel.writes != nullptr) detail::run_kernel_writes(params_, m1, m2, kernel, deferred_writes_[p]);
        }
    }
    failure.rethrow_if_any();
}

bool CollisionPipeline::roots_within_margin(ModelIndex place1, ModelIndex place2) const {
    const std::size_t i1 = place1.slot(), i2 = place2.slot();
    // BruteForceBroadPhase::addCollisionModel skips empty models and keeps a pair when the
    // intersector's canIntersect passes on the root cubes (BaseProximityIntersection::
    // testIntersection(Cube&, Cube&): within box_margin on every axis; a model with itself
    // always passes; DiscreteIntersection's cone-angle test of a cube with itself is not emulated)
    const CollisionModel& m1 = *models_[i1];
    const CollisionModel& m2 = *models_[i2];
    if (m1.size() == 0 || m2.size() == 0) return false;
    if (&m1 == &m2) return true;
    const bool exhaustive = detection_ == ContactDetection::exhaustive;
    if (!exhaustive && (trees_[i1].empty() || trees_[i2].empty())) return false;
    const Aabb& r1 = exhaustive ? root_boxes_[i1] : trees_[i1].root_box();
    const Aabb& r2 = exhaustive ? root_boxes_[i2] : trees_[i2].root_box();
    return r1.overlaps(r2, box_margin(params_, m1, m2));
}

}  // namespace penalty
