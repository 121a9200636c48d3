// broad_phase() (SOFA's BruteForceBroadPhase filter) and BroadPhase, its pairs kept from step to
// step with the near ones found by a sweep (broad_phase.hpp).
#include "broad_phase.hpp"

#include "narrow_phase.hpp"
#include "penalty/core/error.hpp"
#include "penalty/core/radix_sort.hpp"

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
    // every model added before it, the pair (new model, earlier model) swapped only when the
    // intersector is registered the other way (so two models of one type are keyed (later,
    // earlier), which decides the contact ids and the order of the contacts).
    for (std::size_t j = 0; j < models.size(); ++j) {
        for (std::size_t k = 0; k <= j; ++k) {
            const std::size_t i = k == 0 ? j : k - 1;  // j itself first, then 0 … j−1
            CollisionModel* a = models[j];
            CollisionModel* b = models[i];
            if (!keep_model_pair(*a, *b)) continue;
            if (!has_active_intersector(params, a->type(), b->type())) {
                if (unsupported != nullptr) unsupported->push_back({a, b});
                continue;
            }
            const bool keep_order = is_registered_order(a->type(), b->type());
            pairs.push_back(keep_order ? ModelPair{a, b} : ModelPair{b, a});
            const ModelIndex place_j(static_cast<Index>(j)), place_i(static_cast<Index>(i));
            if (indices != nullptr)
                indices->push_back(keep_order ? std::array{place_j, place_i} : std::array{place_i, place_j});
        }
    }
}

namespace detail {

namespace {
// find_near tests every pair's root boxes, in pair order, up to this many pairs; beyond, it
// sweeps over the models' root boxes.
constexpr std::size_t kMaxPairsTestedOneByOne = 64;
// near_'s sort: std::sort below this many pairs, the radix sort from there
constexpr std::size_t kMinNearPairsForRadixSort = 256;
// pair_of_models_'s key of the models at places a and b: (lower place, higher place)
PairKey model_pair_key(ModelIndex a, ModelIndex b) { return PairKey(std::min(a, b), std::max(a, b)); }
}  // namespace

bool BroadPhase::ModelKey::describes(const CollisionModel& m) const {
    const CollisionModelParams& p = m.params();
    return model == &m && type == m.type() && active == p.active && simulated == p.simulated &&
           self_collision == p.self_collision && both_side == p.both_side && node == p.node && group == p.group;
}

bool BroadPhase::update(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
                        SceneDetection& result) {
    bool same = key_.size() == models.size();
    for (std::size_t i = 0; same && i < models.size(); ++i) same = key_[i].describes(*models[i]);
    if (same) return false;
    broad_phase(params, models, pairs_, &unsupported_, &indices_);
    key_.resize(models.size());
    for (std::size_t i = 0; i < models.size(); ++i) {
        const CollisionModel& m = *models[i];
        const CollisionModelParams& p = m.params();
        key_[i] = {&m, m.type(), p.active, p.simulated, p.self_collision, p.both_side, p.node, p.group};
    }
    result.resize(pairs_.size());  // the remaining entries keep their output capacity
    any_pair_writes_models_ = false;
    pair_of_models_.clear();
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
        ModelPairDetection& d = result[k];
        d.model1 = pairs_[k].model1;
        d.model2 = pairs_[k].model2;
        d.support = pair_support(params, d.model1->type(), d.model2->type());
        d.skipped = false;
        d.narrow_phase = false;
        d.outputs.clear();
        any_pair_writes_models_ = any_pair_writes_models_ || kernel_writes_models(params, *d.model1, *d.model2);
        pair_of_models_.emplace(model_pair_key(indices_[k][0], indices_[k][1]), k);
    }
    near_.clear();
    near_last_.clear();
    is_near_.assign(pairs_.size(), 0);
    return true;
}

void BroadPhase::find_near(const IntersectionParams& params, const std::vector<CollisionModel*>& models,
                           const std::vector<Bvh>& trees,
                           const std::function<bool(ModelIndex, ModelIndex)>& within_margin, SceneDetection& result) {
    std::swap(near_, near_last_);
    near_.clear();
    if (pairs_.size() <= kMaxPairsTestedOneByOne) {
        // few pairs: each one's test, in pair order, costs less than a sweep
        for (std::size_t k = 0; k < pairs_.size(); ++k)
            if (within_margin(indices_[k][0], indices_[k][1])) near_.push_back(k);
        mark_near(result);
        return;
    }
    const auto consider = [&](std::size_t a, std::size_t b) {  // models a <= b
        const auto it = pair_of_models_.find(model_pair_key(ModelIndex(Index(a)), ModelIndex(Index(b))));
        if (it == pair_of_models_.end()) return;  // filtered out by the broad phase
        const std::size_t k = it->second;
        if (within_margin(indices_[k][0], indices_[k][1])) near_.push_back(k);
    };
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
    // a model with itself (roots_within_margin passes it when neither is empty)
    for (const std::size_t i : sweep_) consider(i, i);
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
    sweep_active_.clear();  // places in sweep_boxes_
    for (std::size_t s = 0; s < sweep_boxes_.size(); ++s) {
        const Aabb& box = sweep_boxes_[s];
        const double lo = box.min[axis];
        std::size_t kept = 0;
        for (const std::size_t t : sweep_active_) {
            const Aabb& other = sweep_boxes_[t];
            if (other.max[axis] + reach < lo) continue;  // apart from this box and every later one
            sweep_active_[kept++] = t;
            // apart by more than `reach` on some axis: the exact test fails too
            if (!box.overlaps(other, reach)) continue;
            const std::size_t i = sweep_[s], j = sweep_[t];
            consider(std::min(i, j), std::max(i, j));
        }
        sweep_active_.resize(kept);
        sweep_active_.push_back(s);
    }
    if (near_.size() < kMinNearPairsForRadixSort) std::sort(near_.begin(), near_.end());
    else stable_radix_sort(near_, sweep_swap_, sweep_counts_, [](std::size_t k) { return std::uint64_t(k); });
    mark_near(result);
}

void BroadPhase::mark_near(SceneDetection& result) {
    for (const std::size_t k : near_last_) {
        is_near_[k] = 0;
        result[k].narrow_phase = false;
        result[k].outputs.clear();
    }
    for (const std::size_t k : near_) {
        is_near_[k] = 1;
        result[k].narrow_phase = true;
    }
}

}  // namespace detail
}  // namespace penalty
