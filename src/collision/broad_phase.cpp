// broad_phase() (SOFA's BruteForceBroadPhase filter) and BroadPhase, each detection's near pairs
// found by a sweep and filtered one by one (broad_phase.hpp).
#include "broad_phase.hpp"

#include "narrow_phase.hpp"
#include "penalty/core/error.hpp"
#include "penalty/core/radix_sort.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <limits>

namespace penalty {

void broad_phase(const IntersectionParams& params, std::span<CollisionModel* const> models,
                 std::vector<ModelPair>& pairs, std::vector<ModelPair>* unsupported,
                 std::vector<std::array<ModelIndex, 2>>* indices) {
    pairs.clear();
    if (unsupported != nullptr) unsupported->clear();
    if (indices != nullptr) indices->clear();
    for (std::size_t i = 0; i < models.size(); ++i)
        if (models[i] == nullptr) throw_invalid_argument("broad_phase(): model ", i, " is null");
    // BruteForceBroadPhase::addCollisionModel: each model in turn, first with itself, then with
    // every model added before it (detail::sofa_pair_order)
    detail::for_each_model_pair_in_order(models.size(), [&](std::size_t j, std::size_t i) {
        const detail::PairVerdict verdict = detail::judge_model_pair(params, *models[j], *models[i]);
        if (verdict == detail::PairVerdict::unsupported && unsupported != nullptr)
            unsupported->push_back({models[j], models[i]});
        if (verdict != detail::PairVerdict::kept) return;
        const std::array<ModelIndex, 2> places = detail::registered_places(models, j, i);
        pairs.push_back({models[places[0].slot()], models[places[1].slot()]});
        if (indices != nullptr) indices->push_back(places);
    });
}

namespace detail {

namespace {
// find_near tests every kept pair's root boxes, in pair order, up to this many pairs; beyond,
// it sweeps over the models' root boxes.
constexpr std::size_t kMaxPairsTestedOneByOne = 64;
// near_'s sort: std::sort below this many pairs, the radix sort from there
constexpr std::size_t kMinNearPairsForRadixSort = 256;
}  // namespace

PairVerdict judge_model_pair(const IntersectionParams& params, const CollisionModel& later,
                             const CollisionModel& earlier) {
    if (!keep_model_pair(later, earlier)) return PairVerdict::filtered_out;
    if (!has_active_intersector(params, later.type(), earlier.type())) return PairVerdict::unsupported;
    return PairVerdict::kept;
}

bool BroadPhase::ModelKey::describes(const CollisionModel& m) const {
    const CollisionModelParams& p = m.params();
    return model == &m && type == m.type() && active == p.active && simulated == p.simulated &&
           self_collision == p.self_collision && both_side == p.both_side && node == p.node && group == p.group;
}

std::array<ModelIndex, 2> registered_places(std::span<CollisionModel* const> models, std::size_t j, std::size_t i) {
    // the pair (new model, earlier model) is swapped only when the intersector is registered the
    // other way (so two models of one type are keyed (later, earlier)), which decides the
    // contact ids and the order of the contacts
    const ModelIndex place_j(static_cast<Index>(j)), place_i(static_cast<Index>(i));
    return is_registered_order(models[j]->type(), models[i]->type()) ? std::array{place_j, place_i}
                                                                     : std::array{place_i, place_j};
}

std::optional<NearPair> BroadPhase::kept_pair(const IntersectionParams& params,
                                              const std::vector<CollisionModel*>& models, std::size_t j,
                                              std::size_t i) {
    if (judge_model_pair(params, *models[j], *models[i]) != PairVerdict::kept) return std::nullopt;
    return NearPair{sofa_pair_order(j, i), registered_places(models, j, i)};
}

bool BroadPhase::update(const IntersectionParams& params, const std::vector<CollisionModel*>& models) {
    bool same = key_.size() == models.size();
    for (std::size_t i = 0; same && i < models.size(); ++i) same = key_[i].describes(*models[i]);
    if (same) return false;
    key_.resize(models.size());
    for (std::size_t i = 0; i < models.size(); ++i) {
        const CollisionModel& m = *models[i];
        const CollisionModelParams& p = m.params();
        key_[i] = {&m, m.type(), p.active, p.simulated, p.self_collision, p.both_side, p.node, p.group};
    }
    // one pass over every pair in broad_phase()'s order, nothing kept per pair
    kept_pairs_ = 0;
    unsupported_.clear();
    any_pair_writes_models_ = false;
    for_each_model_pair_in_order(models.size(), [&](std::size_t j, std::size_t i) {
        const PairVerdict verdict = judge_model_pair(params, *models[j], *models[i]);
        if (verdict == PairVerdict::unsupported) unsupported_.push_back({models[j], models[i]});
        if (verdict != PairVerdict::kept) return;
        ++kept_pairs_;
        const std::array<ModelIndex, 2> places = registered_places(models, j, i);
        any_pair_writes_models_ = any_pair_writes_models_ ||
                                  kernel_writes_models(params, *models[places[0].slot()], *models[places[1].slot()]);
    });
    near_.clear();
    return true;
}

void BroadPhase::find_near(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
                           const std::vector<Bvh>& trees,
                           const std::function<bool(ModelIndex, ModelIndex)>& within_margin, bool every_pair) {
    near_.clear();
    if (every_pair || kept_pairs_ <= kMaxPairsTestedOneByOne) {
        // each pair's test, in pair order (few pairs: it costs less than a sweep)
        for_each_model_pair_in_order(models.size(), [&](std::size_t j, std::size_t i) {
            const std::optional<NearPair> p = kept_pair(params, models, j, i);
            if (p && within_margin(p->places[0], p->places[1])) near_.push_back(*p);
        });
        return;
    }
    sweep(params, models, trees, within_margin);
    const auto order_of = [](const NearPair& p) { return p.order; };
    if (near_.size() < kMinNearPairsForRadixSort)
        std::sort(near_.begin(), near_.end(), [](const NearPair& x, const NearPair& y) { return x.order < y.order; });
    else stable_radix_sort(near_, sort_swap_, sort_counts_, order_of);
}

void BroadPhase::sweep(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
                       const std::vector<Bvh>& trees,
                       const std::function<bool(ModelIndex, ModelIndex)>& within_margin) {
    // The models roots_within_margin may pass: neither empty nor without a tree. The margin of
    // a pair is at most `reach` (box_margin's largest terms), so a pair whose root boxes are
    // apart by more than `reach` on the sweep's axis fails it (max + m <= max + reach, the sums
    // rounded alike). The root boxes are finite: a tree refuses an element box that is not.
    sweep_.clear();
    double largest_contact_distance = 0.0;
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (std::size_t i = 0; i < models.size(); ++i) {
        const CollisionModel& m = *models[i];
        if (m.size() == 0 || trees[i].empty()) continue;
        largest_contact_distance = std::max(largest_contact_distance, m.params().contact_distance);
        const Aabb& r = trees[i].root_box();
        PENALTY_DEMAND(r.min.allFinite() && r.max.allFinite());
        sweep_.push_back(i);
        const Vec3 centre = 0.5 * (r.min + r.max);
        low = low.cwiseMin(centre);
        high = high.cwiseMax(centre);
    }
    const double reach = params.method == IntersectionMethod::Discrete
                             ? params.alarm_distance
                             : params.alarm_distance + largest_contact_distance + largest_contact_distance;
    // sweep and prune on the axis where the boxes' centres spread most
    int axis = 0;
    (high - low).maxCoeff(&axis);
    const auto lower_bound_of = [&](std::size_t i) { return trees[i].root_box().min[axis]; };
    std::sort(sweep_.begin(), sweep_.end(), [&](std::size_t a, std::size_t b) {
        return lower_bound_of(a) != lower_bound_of(b) ? lower_bound_of(a) < lower_bound_of(b) : a < b;
    });
    // the root boxes of the sweep's models in sweep order (compact: the inner loop reads them)
    sweep_boxes_.clear();
    for (const std::size_t i : sweep_) sweep_boxes_.push_back(trees[i].root_box());
    // Each model with itself (roots_within_margin passes it when neither is empty), then with
    // the later models of the sweep whose lower bound lies within `reach` of its upper bound
    // (the boxes apart by more on some axis fail the exact test too): each pair once, pure
    // tests, so the models go in ranges on TBB's threads, their pairs sorted by order after.
    const std::size_t n = sweep_.size();
    const auto scan = [&](std::size_t begin, std::size_t end, std::vector<NearPair>& out) {
        const auto keep = [&](std::size_t i, std::size_t j) {  // models i <= j
            const std::optional<NearPair> p = kept_pair(params, models, j, i);
            if (p && within_margin(p->places[0], p->places[1])) out.push_back(*p);
        };
        for (std::size_t s = begin; s < end; ++s) {
            const std::size_t i = sweep_[s];
            keep(i, i);
            const Aabb& box = sweep_boxes_[s];
            const double upper = box.max[axis] + reach;
            for (std::size_t t = s + 1; t < n && !(upper < sweep_boxes_[t].min[axis]); ++t)
                if (box.overlaps(sweep_boxes_[t], reach)) keep(std::min(i, sweep_[t]), std::max(i, sweep_[t]));
        }
    };
    if (n < 2 * kModelsPerSweepTask || tbb::this_task_arena::max_concurrency() < 2) {
        scan(0, n, near_);
        return;
    }
    for (std::vector<NearPair>& list : sweep_lists_) list.clear();
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, kModelsPerSweepTask),
        [&](const tbb::blocked_range<std::size_t>& r) { scan(r.begin(), r.end(), sweep_lists_.local()); });
    for (const std::vector<NearPair>& list : sweep_lists_) near_.insert(near_.end(), list.begin(), list.end());
}

}  // namespace detail
}  // namespace penalty
