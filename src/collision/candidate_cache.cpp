// CandidateCache: each model pair's candidates kept from step to step (candidate_cache.hpp).
#include "candidate_cache.hpp"
#include "penalty/core/pair_key.hpp"

#include "kernels.hpp"
#include "kernels/box_overlap.hpp"
#include "kernels/prefetch.hpp"
#include "penalty/collision/separation.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace penalty::detail {

namespace {
/// A model's slack also doubles while its generations last up to this many refits when nearly all
/// its pairs' kept keys overlapped (track_motion).
constexpr std::size_t kCheapSlackRefits = 6;
}  // namespace

void PairCounts::add_to(CollisionPipeline::CandidateCacheStats& stats, std::size_t& candidates_evaluated) const {
    stats.reused += cache.reused;
    stats.collected += cache.collected;
    stats.in_sofa_order += cache.in_sofa_order;
    stats.sofa_order_sorts += cache.sofa_order_sorts;
    stats.branch_free_tests += cache.branch_free_tests;
    stats.sure_keys_skipped += cache.sure_keys_skipped;
    candidates_evaluated += candidates;
}

double largest_bound_change(std::span<const Aabb> now, std::span<const Aabb> before, double limit) {
    double moved = 0.0;
    for (std::size_t e = 0; e < now.size(); ++e) {
        const Vec3 d = (now[e].min - before[e].min).cwiseAbs().cwiseMax((now[e].max - before[e].max).cwiseAbs());
        moved = std::max(moved, d.maxCoeff());
        if (!(moved <= limit)) return moved;  // NaN too
    }
    return moved;
}

void CandidateCache::reset(std::size_t models) {
    motion_.assign(models, ModelMotion{});
    entries_.clear();
}

void CandidateCache::track_motion(std::size_t i, const Bvh& tree, const CollisionModel& model, double alarm_distance) {
    const std::vector<Aabb>& boxes = tree.element_boxes();
    ModelMotion& mm = motion_[i];
    const bool moving = model.params().moving;
    if (mm.uncached_refits > 0) {  // moving too fast for the cache: traversed at every step
        --mm.uncached_refits;
        if (mm.uncached_refits > 0) return;
    } else if (mm.generation != 0 && mm.reference.size() == boxes.size() &&
               largest_bound_change(boxes, mm.reference, mm.slack) <= mm.slack) {
        ++mm.steps;
        return;
    }
    // A new generation. Slack of a moving model: an eighth of the mean element extent (at
    // least 1e-3 of the model's extent) to start with; doubled when a generation lasts a single
    // refit, up to a quarter of the extent (for a Point model, of the points' spacing), beyond
    // which the model is traversed at every step for 16 refits (a wider slack would only
    // collect more candidates than it saves); halved when generations last long. A static
    // model's boxes change only with a new build: slack 0.
    // When nearly all the keys its pairs kept in the generation overlapped at their detections
    // (at least 7/8), the slack added few candidates and a wider one costs little while a
    // collection costs much (CompositeCollisionPipeline's falling sphere, whose alarm box covers
    // most of a torus: a collection every 2-3 steps): the slack then also doubles while
    // generations last up to kCheapSlackRefits refits, up to half the alarm distance (finite:
    // validated) if that is more. (Up to the model's own extent, collisionMultiple's falling
    // objects, few kept keys all overlapping, grew slacks of 1.8 m for elements of 1 cm.)
    double extent = 0.0;
    double largest_extent = 0.0;  // the slack's bound: a quarter of it
    for (const Aabb& a : boxes) extent += (a.max - a.min).maxCoeff();
    extent = boxes.empty() ? 0.0 : extent / double(boxes.size());
    if (!tree.empty()) {
        const Aabb& root = tree.root_box();
        const double root_extent = (root.max - root.min).maxCoeff();
        extent = std::max(extent, 1e-3 * root_extent);
        // A Point model's elements have no extent (their boxes are the contact distance): its
        // slack may grow up to a quarter of the points' spacing on a surface, root extent / √n.
        // (With 1e-3 of the root extent, the points of AdvancedSolversMultipleGroupsSolver's
        // falling cubes were traversed at nearly every step.)
        if (model.type() == ModelType::Point)
            largest_extent = std::max(extent, root_extent / std::sqrt(double(boxes.size())));
    }
    if (!std::isfinite(extent)) extent = 0.0;
    largest_extent = std::isfinite(largest_extent) ? std::max(largest_extent, extent) : extent;
    const bool cheap_slack = mm.kept_keys > 0 && 8 * mm.overlapping_keys >= 7 * mm.kept_keys;
    double slack_bound = 0.25 * largest_extent;
    if (cheap_slack) slack_bound = std::max(slack_bound, 0.5 * alarm_distance);
    mm.kept_keys = mm.overlapping_keys = 0;
    const bool fresh = mm.generation == 0 || mm.reference.size() != boxes.size();
    if (!moving) {
        mm.slack = 0.0;
    } else if (fresh) {
        mm.slack = 0.125 * extent;
    } else if (mm.steps <= 1) {
        if (2.0 * mm.slack > slack_bound) {
            mm.generation = 0;  // pairs with this model traverse the trees
            mm.uncached_refits = 16;
            mm.reference.clear();
            return;
        }
        mm.slack *= 2.0;
    } else if (cheap_slack && mm.steps <= kCheapSlackRefits) {
        if (2.0 * mm.slack <= slack_bound) mm.slack *= 2.0;
    } else if (mm.steps > 16) {
        mm.slack = std::max(0.5 * mm.slack, extent / 64.0);
    }
    mm.reference.assign(boxes.begin(), boxes.end());
    mm.generation = ++generations_;
    mm.steps = 0;
}

void CandidateCache::follow(const std::vector<NearPair>& near, std::vector<PairCandidates*>& kept) {
    // both lists in order: one merge
    next_.clear();
    auto last = entries_.begin();
    for (const NearPair& p : near) {
        while (last != entries_.end() && last->pair.order < p.order) ++last;
        if (last != entries_.end() && last->pair.order == p.order && last->pair.places == p.places)
            next_.push_back(std::move(*last));
        else next_.push_back({p, PairCandidates{}});
    }
    entries_.swap(next_);
    kept.assign(near.size(), nullptr);
    for (std::size_t k = 0; k < near.size(); ++k) {
        const NearPair& p = near[k];
        if (motion_[p.places[0].slot()].generation != 0 && motion_[p.places[1].slot()].generation != 0)
            kept[k] = &entries_[k].candidates;
    }
}

PairCandidates* CandidateCache::entry(ModelIndex i1, ModelIndex i2) {
    if (motion_[i1.slot()].generation == 0 || motion_[i2.slot()].generation == 0) return nullptr;
    const std::uint64_t order = sofa_pair_order(std::max(i1, i2).slot(), std::min(i1, i2).slot());
    const auto it = std::lower_bound(entries_.begin(), entries_.end(), order,
                                     [](const Entry& e, std::uint64_t o) { return e.pair.order < o; });
    if (it != entries_.end() && it->pair.order == order) return &it->candidates;
    one_use_ = PairCandidates{};
    return &one_use_;
}

void CandidateCache::count_kept_keys(const std::array<ModelIndex, 2>& places, const PairCandidates* kept) {
    if (kept == nullptr) return;
    ModelMotion& a = motion_[places[0].slot()];
    ModelMotion& b = motion_[places[1].slot()];
    if (kept->generation1 != a.generation || kept->generation2 != b.generation) return;
    for (ModelMotion* m : {&a, &b}) {
        m->kept_keys += kept->keys.size();
        m->overlapping_keys += kept->overlapped_last;
    }
}

void CandidateCache::collect(const CachedPair& p, PairCandidates& kept, NarrowPhaseScratch::Buffers& buf,
                             SofaOrderScratch& sofa_scratch, bool writes_models) {
    const ModelMotion& a = p.a;
    const ModelMotion& b = p.b;
    const double wide = box_margin(p.params, p.m1, p.m2) + 2.0 * (a.slack + b.slack);
    // the row mode with the boxes grown by how far they may move while the keys are kept
    // (2 · slack each); only for a static long model, whose elements (planes) stay put
    LongElements rows = long_elements(p.params, p.m1, a.longest_side, p.m2, b.longest_side);
    if (rows.model != nullptr && rows.model->params().moving) rows.model = nullptr;
    rows.pad = 2.0 * (a.slack + b.slack);
    kept.keys.clear();
    const bool sorted_candidates = p.options.narrow.sorted_candidates && !p.options.sofa_output_order;
    if (&p.m1 == &p.m2 || p.t1.root_box().overlaps(p.t2.root_box(), wide)) {
        collect_candidates(p.t1, p.t2, &p.m1 == &p.m2, wide, p.options.narrow.parallel,
                           sorted_candidates || writes_models, buf, rows.model != nullptr ? &rows : nullptr);
        kept.keys.assign(buf.keys.begin(), buf.keys.end());
    }
    kept.in_sofa_order = false;
    kept.outputs_sorted = 0;
    kept.sure_current = false;
    if (p.options.sofa_output_order && !writes_models) {
        // sort_keys' buffers, grown here (a collection allocates anyway) and not at the later
        // step that sorts the keys
        const std::size_t n = kept.keys.size();
        sofa_scratch.keyed.reserve(n);
        sofa_scratch.permutation.reserve(n);
        sofa_scratch.sorted_keys.reserve(n);
    }
    kept.generation1 = a.generation;
    kept.generation2 = b.generation;
    kept.nearest_outputs = p.options.contact_outputs_only &&
                           outputs_nearest_to_element2(p.params, pair_kernel_parts(p.params, p.m1, p.m2));
}

void CandidateCache::test_kept_keys(const CachedPair& p, PairCandidates& kept, double margin, Keys& now,
                                    PairCounts& counts) {
    now.clear();
    const Aabb* boxes1 = p.t1.element_boxes().data();
    const Aabb* boxes2 = p.t2.element_boxes().data();
    const std::size_t n_kept = kept.keys.size();
    const std::uint64_t* keys = kept.keys.data();
    const bool fetch = prefetch::worth_it(p.m1.size() + p.m2.size());
    const auto prefetch_ahead = [&](std::size_t j) {
        if (fetch && j + prefetch::kAhead < n_kept) {
            const std::uint64_t ahead = keys[j + prefetch::kAhead];
            prefetch::object(boxes1 + pair_key::first(ahead), sizeof(Aabb));
            prefetch::object(boxes2 + pair_key::second(ahead), sizeof(Aabb));
        }
    };
    // Nearly all or nearly none of the keys overlapped last time: a branch per key, predicted.
    // Otherwise (AdvancedSolversMultipleGroupsSolver: detection 4-8 % faster, same keys) no
    // branch: each key is written to a block whose end advances by the test's result, and the
    // blocks are appended. The same keys in the same order either way.
    // Either way the keys kept are gathered in blocks of 64 and appended a block at a time (a
    // push_back per key was a call when the compiler did not inline it).
    // When nearly all overlapped, most keys are usually sure to overlap until the generations
    // end (PairCandidates::sure): every box bound stays within its model's slack s of the bound
    // at its generation's start, so it moves by at most 2·s between two detections of one
    // generation, and a pair whose boxes overlap now with m − 2·(s1 + s2) − tol overlaps with m
    // at every detection left in both generations. tol covers the rounding of the sums max + m
    // and of the bounds' changes (a few ulps of the magnitudes; 1e-12 of them here; a NaN
    // bound makes no key sure). The marks are made in the first such test after a collection
    // or a reordering, and the sure keys' box tests are skipped from then on.
    const std::size_t share_eighths = n_kept == 0 ? 0 : 8 * kept.overlapped_last / n_kept;
    const bool mostly_overlapping = share_eighths >= 7;
    double sure_margin = 0.0;
    if (mostly_overlapping && !kept.sure_current) {
        const double reach = 2.0 * (p.a.slack + p.b.slack);
        const auto magnitude = [](const Aabb& box) {
            return std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
        };
        const double scale =
            1.0 + std::abs(margin) + reach + std::max(magnitude(p.t1.root_box()), magnitude(p.t2.root_box()));
        sure_margin = margin - reach - 1e-12 * scale;
        kept.sure.resize(n_kept);
    }
    std::uint8_t* sure = kept.sure.data();
    // what the test does with the per-key "sure" marks
    enum class SureMarks : std::uint8_t {
        unused,   ///< not read, not written
        current,  ///< current: a marked key is kept without its test
        made,     ///< made in this test
    };
    const SureMarks marks = !mostly_overlapping ? SureMarks::unused
                            : kept.sure_current ? SureMarks::current
                                                : SureMarks::made;
    std::size_t sure_count = 0;
    const auto test_keys = [&](auto branch_free) {
        constexpr std::size_t kBlock = 64;
        std::uint64_t block[kBlock];
        for (std::size_t first = 0; first < n_kept; first += kBlock) {
            const std::size_t last = std::min(n_kept, first + kBlock);
            std::size_t count = 0;
            for (std::size_t j = first; j < last; ++j) {
                prefetch_ahead(j);
                const std::uint64_t k = keys[j];
                if constexpr (decltype(branch_free)::value) {
                    block[count] = k;
                    count += boxes_overlap_branch_free(boxes1[pair_key::first(k)], boxes2[pair_key::second(k)], margin)
                                 ? 1
                                 : 0;
                } else if (marks == SureMarks::current) {
                    if (sure[j] != 0 || boxes1[pair_key::first(k)].overlaps(boxes2[pair_key::second(k)], margin))
                        block[count++] = k;
                } else if (marks == SureMarks::made) {
                    const Aabb& box1 = boxes1[pair_key::first(k)];
                    const Aabb& box2 = boxes2[pair_key::second(k)];
                    sure[j] = boxes_overlap_branch_free(box1, box2, sure_margin) ? 1 : 0;
                    sure_count += sure[j];
                    if (sure[j] != 0 || box1.overlaps(box2, margin)) block[count++] = k;
                } else if (boxes1[pair_key::first(k)].overlaps(boxes2[pair_key::second(k)], margin)) {
                    block[count++] = k;
                }
            }
            now.insert(now.end(), block, block + count);
        }
    };
    if (share_eighths == 0 || mostly_overlapping) {
        test_keys(std::false_type{});
        if (marks == SureMarks::current) counts.cache.sure_keys_skipped += kept.sure_count;
        if (marks == SureMarks::made) {
            kept.sure_current = true;
            kept.sure_count = sure_count;
        }
    } else {
        ++counts.cache.branch_free_tests;
        test_keys(std::true_type{});
    }
    kept.overlapped_last = now.size();
}

bool CandidateCache::detect(const CachedPair& p, PairCandidates& kept, NarrowPhaseScratch::Buffers& buf,
                            SofaOrderScratch& sofa_scratch, PairCounts& counts, Keys* deferred_writes,
                            DetectionOutputList& out) {
    // Since a generation began every box bound moved by at most its model's slack s, so between
    // the collection and now by at most 2·s: a pair overlapping now with margin m overlapped at
    // the collection with m + 2·(s1 + s2). The kept pairs are box-tested again with m, exactly
    // as the traversal tests them, so the candidates are the traversal's.
    check_trees(p.m1, p.t1, p.m2, p.t2);
    const double margin = box_margin(p.params, p.m1, p.m2);
    const bool separation_tests = worth_separating(std::max(p.a.longest_side, p.b.longest_side), margin);
    const bool writes_models = kernel_writes_models(p.params, p.m1, p.m2);
    if (kept.generation1 != p.a.generation || kept.generation2 != p.b.generation) {
        ++counts.cache.collected;
        collect(p, kept, buf, sofa_scratch, writes_models);
    } else {
        ++counts.cache.reused;
    }
    // Kept in SOFA's visiting order, the outputs come out in it (evaluate_candidates keeps the
    // candidates' order). Sorted when the outputs sorted in this generation outnumber the kept
    // keys (PairCandidates). Not for a kernel that writes the models: its writes run over the
    // candidates sorted by element.
    if (p.options.sofa_output_order && !writes_models && !kept.in_sofa_order &&
        kept.outputs_sorted >= kept.keys.size()) {
        if (kept.keys.size() >= 2) p.sofa_trees.sort_keys(p.models, p.i1, p.i2, kept.keys, sofa_scratch);
        kept.in_sofa_order = true;
        kept.sure_current = false;
        ++counts.cache.sofa_order_sorts;
    }
    Keys& now = buf.keys;
    test_kept_keys(p, kept, margin, now, counts);
    // with SOFA's output order the outputs are sorted afterwards (detect_pair): the candidates
    // need no sort of their own
    NarrowPhaseOptions narrow = p.options.narrow;
    if (p.options.sofa_output_order) narrow.sorted_candidates = false;
    const bool nearest = kept.nearest_outputs && worth_keeping_nearest(now.size(), p.m2);
    if (nearest)
        keep_nearest_candidates(p.params, p.m1, p.t1.element_boxes().data(), p.m2, now, buf, separation_tests,
                                deferred_writes);
    const std::size_t from = out.size();
    if (nearest) out.reserve(from + kept.keys.size());
    evaluate_candidates(p.params, p.m1, p.m2, now, narrow, buf, out, separation_tests, deferred_writes);
    if (nearest) keep_least_outputs(out, from, p.m2.size(), buf);
    counts.candidates += now.size();
    if (kept.in_sofa_order) ++counts.cache.in_sofa_order;
    else kept.outputs_sorted += out.size();
    return kept.in_sofa_order;
}

}  // namespace penalty::detail
