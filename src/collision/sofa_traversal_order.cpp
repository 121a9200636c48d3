#include "penalty/collision/sofa_traversal_order.hpp"
#include "penalty/core/pair_key.hpp"

#include "penalty/core/radix_sort.hpp"

#include "kernels/prefetch.hpp"
#include "penalty/core/error.hpp"

#include <algorithm>
#include <bit>

namespace penalty {

namespace {
struct Cell {
    std::uint32_t first = 0, last = 0;  // element range (positions in the sorted leaf order)
    std::int32_t child = -1;            // first of its two child cells at the next level, or −1
    Aabb box;
};

Aabb union_box(std::span<const Aabb> boxes, std::span<const Index> order, std::uint32_t first, std::uint32_t last) {
    Aabb b;
    for (std::uint32_t i = first; i < last; ++i) {
        b.min = b.min.cwiseMin(boxes[order[i]].min);
        b.max = b.max.cwiseMax(boxes[order[i]].max);
    }
    return b;
}
}  // namespace

namespace {

// The digits of sofa_visits_before packed into one integer, most significant level first. At
// level t an element pair's loop position is loop = s.index·r.size + r.index < D_t = (largest
// range of tree 1 at t)·(largest range of tree 2 at t); its digit is loop when both paths end
// there (intersected in the loop, first) and 2·D_t − 1 − loop otherwise (pushed, visited last
// pushed first); the levels after a pair's last are 0. Returns false when the digits need more
// than 64 bits.
struct PackedLevels {
    std::vector<std::uint64_t>& span;  // D_t
    std::vector<int>& shift;           // bit position of level t's digit
};

// levels: the deeper tree's; range(t): the product of the two trees' largest ranges at t
template <class RangeProduct>
bool pack_levels(std::size_t levels, RangeProduct range, PackedLevels p) {
    p.span.resize(levels);
    p.shift.resize(levels);
    int bits = 0;
    for (std::size_t t = 0; t < levels; ++t) {
        p.span[t] = range(t);
        bits += std::bit_width(2 * p.span[t] - 1);
        if (bits > 64) return false;
    }
    int below = bits;
    for (std::size_t t = 0; t < levels; ++t) {
        below -= std::bit_width(2 * p.span[t] - 1);
        p.shift[t] = below;
    }
    return true;
}

bool pack_levels(const SofaCubeTree& t1, const SofaCubeTree& t2, PackedLevels p) {
    return pack_levels(
        std::max(t1.levels(), t2.levels()),
        [&](std::size_t t) { return std::uint64_t(t1.max_range(t)) * std::uint64_t(t2.max_range(t)); }, p);
}

std::uint64_t packed_key(const PackedLevels& p, const SofaCubeTree::Path& a, const SofaCubeTree::Path& b) {
    std::uint64_t key = 0;
    for (std::size_t t = 0; t < p.span.size(); ++t) {
        const SofaTreeStep s = t < a.size() ? a[t] : SofaTreeStep{};
        const SofaTreeStep r = t < b.size() ? b[t] : SofaTreeStep{};
        const std::uint64_t loop = std::uint64_t(s.index) * r.size + r.index;
        const bool leaf_pair = t + 1 >= a.size() && t + 1 >= b.size();
        key |= (leaf_pair ? loop : 2 * p.span[t] - 1 - loop) << p.shift[t];
        if (leaf_pair) break;
    }
    return key;
}

}  // namespace

void SofaCubeTree::build(const CollisionModel& model, int depth) {
    const std::size_t n = model.size();
    places_.clear();
    key_as_first_.clear();
    key_as_second_.clear();
    if (n == 0) return;
    if (n >= (std::size_t(1) << 31)) throw_invalid_argument("SofaCubeTree: model '", model.name(), "' is too large");
    std::vector<Aabb> boxes(n);
    for (std::size_t e = 0; e < n; ++e) boxes[e] = model.element_box(Index(e));
    std::vector<Index> order(n);  // leaf cube k holds element order[k]
    for (std::size_t e = 0; e < n; ++e) order[e] = Index(e);
    // levels[0] = {root}; each level's cells are made in the order of their parents
    std::vector<std::vector<Cell>> levels(1);
    levels[0].push_back({0, std::uint32_t(n), -1, union_box(boxes, order, 0, std::uint32_t(n))});
    for (int lvl = 0; lvl < depth; ++lvl) {
        std::vector<Cell> next;
        for (Cell& c : levels[std::size_t(lvl)]) {
            const std::uint32_t count = c.last - c.first;
            if (count <= 4) continue;  // only cells with more than 4 children are split
            const Vec3 l = c.box.max - c.box.min;
            const int axis = l[0] > l[1] ? (l[0] > l[2] ? 0 : 2) : (l[1] > l[2] ? 1 : 2);
            const std::uint32_t middle = c.first + (count + 1) / 2;
            std::stable_sort(order.begin() + c.first, order.begin() + c.last, [&](Index a, Index b) {
                return boxes[a].min[axis] + boxes[a].max[axis] < boxes[b].min[axis] + boxes[b].max[axis];
            });
            c.child = std::int32_t(next.size());
            next.push_back({c.first, middle, -1, union_box(boxes, order, c.first, middle)});
            next.push_back({middle, c.last, -1, union_box(boxes, order, middle, c.last)});
        }
        if (next.empty()) break;
        levels.push_back(std::move(next));
    }
    // each leaf cell's path from the root's children down to the cell (the split steps {s, 2}),
    // and each element's place in its leaf cell; an element's path is its cell's path followed
    // by {place, cell size}
    places_.assign(n, Place{});
    cell_offsets_.assign(1, 0);
    cell_steps_.clear();
    cell_sizes_.clear();
    std::vector<SofaTreeStep> prefix;
    const auto walk = [&](const auto& self, std::size_t lvl, const Cell& c) -> void {
        if (c.child < 0) {
            const auto cell = std::uint32_t(cell_sizes_.size());
            cell_steps_.insert(cell_steps_.end(), prefix.begin(), prefix.end());
            cell_offsets_.push_back(std::uint32_t(cell_steps_.size()));
            cell_sizes_.push_back(c.last - c.first);
            for (std::uint32_t k = c.first; k < c.last; ++k) places_[order[k]] = {cell, k - c.first};
            return;
        }
        const std::vector<Cell>& below = levels[lvl + 1];
        for (std::uint32_t s = 0; s < 2; ++s) {
            prefix.push_back({s, 2});
            self(self, lvl + 1, below[std::size_t(c.child) + s]);
            prefix.pop_back();
        }
    };
    walk(walk, 0, levels[0][0]);
    level_max_size_.clear();
    for (std::size_t c = 0; c < cell_sizes_.size(); ++c) {
        // a cell's path: split steps of size 2, then its elements' last step of the cell's size
        const std::size_t depth_of_cell = cell_offsets_[c + 1] - cell_offsets_[c];
        if (depth_of_cell + 1 > level_max_size_.size()) level_max_size_.resize(depth_of_cell + 1, 1);
        for (std::size_t t = 0; t < depth_of_cell; ++t)
            level_max_size_[t] = std::max<std::uint32_t>(level_max_size_[t], 2);
        level_max_size_[depth_of_cell] = std::max(level_max_size_[depth_of_cell], cell_sizes_[c]);
    }
    compute_keys_against_one_element();
}

void SofaCubeTree::compute_keys_against_one_element() {
    key_as_first_.clear();
    key_as_second_.clear();
    // a one-element tree: one path [{0, 1}], one level, largest range 1 at every level
    const Path other{{}, SofaTreeStep{0, 1}};
    std::vector<std::uint64_t> span;
    std::vector<int> shift;
    const PackedLevels levels{span, shift};
    if (!pack_levels(
            std::max<std::size_t>(this->levels(), 1), [&](std::size_t t) { return std::uint64_t(max_range(t)); },
            levels))
        return;
    const std::size_t n = size();
    key_as_first_.resize(n);
    key_as_second_.resize(n);
    for (std::size_t e = 0; e < n; ++e) {
        key_as_first_[e] = packed_key(levels, path(Index(e)), other);
        key_as_second_[e] = packed_key(levels, other, path(Index(e)));
    }
}

bool sofa_visits_before(const SofaCubeTree& t1, const SofaCubeTree& t2, Index a1, Index b1, Index a2, Index b2) {
    const auto pa1 = t1.path(a1), pb1 = t2.path(b1), pa2 = t1.path(a2), pb2 = t2.path(b2);
    // At each level both pairs are in the same two ranges (their earlier steps agree). A pair
    // of two elements is intersected during the loop (key 0, loop position); any other pair is
    // pushed and visited after the loop, last pushed first (key 1, −loop position).
    const auto key = [](const SofaCubeTree::Path& p, const SofaCubeTree::Path& q, std::size_t t, bool& leaf_pair) {
        const SofaTreeStep s = t < p.size() ? p[t] : SofaTreeStep{};
        const SofaTreeStep r = t < q.size() ? q[t] : SofaTreeStep{};
        leaf_pair = t + 1 >= p.size() && t + 1 >= q.size();
        const std::int64_t loop = std::int64_t(s.index) * std::int64_t(r.size) + std::int64_t(r.index);
        return leaf_pair ? loop : -loop;
    };
    for (std::size_t t = 0;; ++t) {
        bool leaf1 = false, leaf2 = false;
        const std::int64_t k1 = key(pa1, pb1, t, leaf1);
        const std::int64_t k2 = key(pa2, pb2, t, leaf2);
        if (leaf1 != leaf2) return leaf1;  // intersected in the loop, before anything pushed
        if (k1 != k2) return k1 < k2;
        if (leaf1) return false;  // the same element pair
    }
}

namespace {

// Sorts v by key; equal keys keep their order in v: the stable radix sort (core/radix_sort.hpp),
// or std::sort with the position as the tie-break for short lists.
void sort_by_key_stable(std::vector<SofaOrderScratch::Keyed>& v, std::vector<SofaOrderScratch::Keyed>& swap,
                        std::vector<std::size_t>& counts) {
    using Keyed = SofaOrderScratch::Keyed;
    if (v.size() < 512) {
        // v is in index order (the caller's), so the index is the position
        std::sort(v.begin(), v.end(),
                  [](const Keyed& x, const Keyed& y) { return x.key != y.key ? x.key < y.key : x.index < y.index; });
        return;
    }
    stable_radix_sort(v, swap, counts, [](const Keyed& k) { return k.key; });
}

// The permutation that puts the element pairs elements(i), i < n, into SOFA's visiting order
// (sofa_visits_before), left in scratch.permutation; pairs of the same two elements keep their
// index order.
template <class ElementPair>
void sofa_order_permutation(const SofaCubeTree& t1, const SofaCubeTree& t2, std::size_t n, ElementPair elements,
                            SofaOrderScratch& scratch) {
    std::vector<std::uint32_t>& perm = scratch.permutation;
    perm.clear();
    const PackedLevels levels{scratch.level_span, scratch.level_shift};
    // against a one-element model the key is a function of the other element, computed once
    // when its tree was built (SofaCubeTree::keys_against_one_element)
    const bool one2 = t2.size() == 1 && !t1.keys_against_one_element(true).empty();
    const bool one1 = !one2 && t1.size() == 1 && !t2.keys_against_one_element(false).empty();
    if (one1 || one2 || pack_levels(t1, t2, levels)) {
        // clear + push_back, not resize: the scratch serves pairs of every size, and growing
        // with resize would value-initialise (zero) the new elements at every call
        std::vector<SofaOrderScratch::Keyed>& keyed = scratch.keyed;
        keyed.clear();
        if (one2) {
            const std::span<const std::uint64_t> k = t1.keys_against_one_element(true);
            for (std::size_t i = 0; i < n; ++i) keyed.push_back({k[std::size_t(elements(i).first)], std::uint32_t(i)});
        } else if (one1) {
            const std::span<const std::uint64_t> k = t2.keys_against_one_element(false);
            for (std::size_t i = 0; i < n; ++i) keyed.push_back({k[std::size_t(elements(i).second)], std::uint32_t(i)});
        } else {
            // the pairs come in no memory order of their elements: each element's place in
            // its leaf cell is fetched ahead (the cells' paths are few and stay in cache)
            const std::size_t kAhead = detail::prefetch::kAhead;
            const bool prefetch = detail::prefetch::worth_it(t1.size() + t2.size());
            for (std::size_t i = 0; i < n; ++i) {
                if (prefetch && i + kAhead < n) {
                    const auto [a, b] = elements(i + kAhead);
                    detail::prefetch::first_word(t1.place_address(a));
                    detail::prefetch::first_word(t2.place_address(b));
                }
                const auto [a, b] = elements(i);
                keyed.push_back({packed_key(levels, t1.path(a), t2.path(b)), std::uint32_t(i)});
            }
        }
        // the index breaks ties: the outputs of one element pair keep their order
        sort_by_key_stable(keyed, scratch.keyed_swap, scratch.radix_counts);
        for (std::size_t i = 0; i < n; ++i) perm.push_back(keyed[i].index);
        return;
    }
    // std::sort on indices with the index as the tie-break: stable, and without std::stable_sort's
    // temporary buffer
    for (std::size_t i = 0; i < n; ++i) perm.push_back(std::uint32_t(i));
    std::sort(perm.begin(), perm.end(), [&](std::uint32_t i, std::uint32_t j) {
        const auto [a1, b1] = elements(i);
        const auto [a2, b2] = elements(j);
        if (a1 == a2 && b1 == b2) return i < j;
        return sofa_visits_before(t1, t2, a1, b1, a2, b2);
    });
}

}  // namespace

void sort_in_sofa_order(const SofaCubeTree& t1, const SofaCubeTree& t2, DetectionOutputList& outputs,
                        SofaOrderScratch& scratch) {
    const std::size_t n = outputs.size();
    if (n < 2) return;
    sofa_order_permutation(
        t1, t2, n,
        [&](std::size_t i) { return std::pair<Index, Index>(outputs[i].elem1.value(), outputs[i].elem2.value()); },
        scratch);
    scratch.sorted.clear();
    const std::vector<std::uint32_t>& perm = scratch.permutation;
    // the outputs are read in no memory order
    const std::size_t ahead = detail::prefetch::kAhead;
    const bool prefetch = detail::prefetch::worth_it(t1.size() + t2.size());
    for (std::size_t j = 0; j < n; ++j) {
        if (prefetch && j + ahead < n) detail::prefetch::object(&outputs[perm[j + ahead]], sizeof(DetectionOutput));
        scratch.sorted.push_back(outputs[perm[j]]);
    }
    std::copy(scratch.sorted.begin(), scratch.sorted.end(), outputs.begin());  // the buffers stay with their owners
}

void sort_keys_in_sofa_order(const SofaCubeTree& t1, const SofaCubeTree& t2, std::span<std::uint64_t> keys,
                             SofaOrderScratch& scratch) {
    const std::size_t n = keys.size();
    if (n < 2) return;
    sofa_order_permutation(
        t1, t2, n,
        [&](std::size_t i) {
            return std::pair<Index, Index>(Index(pair_key::first(keys[i])), Index(pair_key::second(keys[i])));
        },
        scratch);
    scratch.sorted_keys.clear();
    for (const std::uint32_t i : scratch.permutation) scratch.sorted_keys.push_back(keys[i]);
    std::copy(scratch.sorted_keys.begin(), scratch.sorted_keys.end(), keys.begin());
}

void SofaOrderTrees::ensure(const std::vector<CollisionModel*>& models, std::size_t i1, std::size_t i2) {
    for (const std::size_t i : {i1, i2}) {
        // SOFA builds a model's tree at its first detection and then only refits it
        // (CubeCollisionModel::computeBoundingTree); rebuilt here only if the model's size changed
        if (trees_[i].empty() || trees_[i].size() != models[i]->size()) trees_[i].build(*models[i], depth_);
    }
}

void SofaOrderTrees::build_all(const std::vector<CollisionModel*>& models) {
    for (std::size_t i = 0; i < models.size(); ++i) {
        CollisionModel& m = *models[i];
        if (!m.params().active || m.size() == 0) continue;
        if (trees_[i].empty() || trees_[i].size() != m.size()) trees_[i].build(m, depth_);
    }
}

void SofaOrderTrees::sort_outputs(const std::vector<CollisionModel*>& models, std::size_t i1, std::size_t i2,
                                  DetectionOutputList& outputs, SofaOrderScratch& scratch) {
    ensure(models, i1, i2);
    sort_in_sofa_order(trees_[i1], trees_[i2], outputs, scratch);
}

void SofaOrderTrees::sort_keys(const std::vector<CollisionModel*>& models, std::size_t i1, std::size_t i2,
                               std::span<std::uint64_t> keys, SofaOrderScratch& scratch) {
    ensure(models, i1, i2);
    sort_keys_in_sofa_order(trees_[i1], trees_[i2], keys, scratch);
}

}  // namespace penalty
