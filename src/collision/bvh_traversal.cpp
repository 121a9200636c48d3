// The dual-tree traversal of a model pair's bounding trees: the candidate element pairs whose
// boxes pass the §3.8 test, sorted (collect_candidates, bvh_candidates).
#include "narrow_phase.hpp"
#include "penalty/core/pair_key.hpp"

#include "kernels/collision/box_columns.hpp"
#include "penalty/collision/models.hpp"
#include "penalty/collision/separation.hpp"
#include "penalty/core/radix_sort.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <bit>

namespace penalty {
namespace detail {

namespace {

constexpr std::uint32_t kParallelTraversalMin = 4096;  // element count above which a node pair forks

std::uint64_t key(std::uint32_t e1, std::uint32_t e2) { return pair_key::make(e1, e2); }

// Dual-tree traversal collecting the element pairs whose boxes pass the §3.8 test. Below
// kBruteForceBelow element pairs, a node pair is finished by testing all its element pairs
// (the same element box test, so the same pairs, with less recursion).
constexpr std::uint32_t kBruteForceBelow = 64;

constexpr std::uint32_t kRowNodeMax = 8;

detail::ElementPlanes element_planes(const CollisionModel& m, std::uint32_t e, double R) {
    const Index i = Index(e);
    if (m.type() == ModelType::Triangle) {
        const auto& t = static_cast<const TriangleModel&>(m);
        return detail::ElementPlanes::triangle(t.p(i, 0), t.p(i, 1), t.p(i, 2), R);
    }
    const auto& l = static_cast<const LineModel&>(m);  // long_elements keeps Triangle and Line models only
    return detail::ElementPlanes::segment(l.p1(i), l.p2(i), R);
}

struct Traversal {
    const Bvh& a;
    const Bvh& b;
    bool self;  // a and b are the same tree of the same model: keys (max, min), diagonal skipped
    double margin;
    bool parallel;
    tbb::enumerable_thread_specific<Keys>& buffers;
    const LongElements* rows = nullptr;    // the row mode, if any (never with self)
    KernelPath path = best_kernel_path();  // the leaf-level box tests (box_columns.hpp)

    void emit(Keys& out, std::uint32_t ea, std::uint32_t eb) const {
        if (self) out.push_back(ea > eb ? key(ea, eb) : key(eb, ea));
        else out.push_back(key(ea, eb));
    }

    // Every element pair of two nodes whose boxes overlap, emitted by slot of a, then of b.
    void all_pairs(const BvhNode& na, const BvhNode& nb, Keys& out) const {
        const std::uint32_t* oa = a.order().data();
        const std::uint32_t* ob = b.order().data();
        const Aabb* ba = a.ordered_boxes().data();
        const Aabb* bb = b.ordered_boxes().data();
        // One element on a side (a sphere against a mesh): its box against the other node's
        // element boxes, in slot order. The same pairs in the same order as the columns below:
        // an element's box lies in its node's box, so a box overlapping the element's overlaps
        // the node's (the tests are monotone in the bounds), and the columns' pre-test adds nothing.
        if (na.count == 1) {
            const Aabb& boxa = ba[na.first];
            if (!boxa.overlaps(nb.box, margin)) return;
            for (std::uint32_t t = nb.first; t < nb.first + nb.count; ++t)
                if (boxa.overlaps(bb[t], margin)) emit(out, oa[na.first], ob[t]);
            return;
        }
        if (nb.count == 1) {
            const Aabb& boxb = bb[nb.first];
            if (!boxb.overlaps(na.box, margin)) return;
            for (std::uint32_t s = na.first; s < na.first + na.count; ++s)
                if (ba[s].overlaps(boxb, margin)) emit(out, oa[s], ob[nb.first]);
            return;
        }
        if (nb.count > detail::BoxColumns::kCapacity) {
            for (std::uint32_t s = na.first; s < na.first + na.count; ++s) {
                const Aabb& boxa = ba[s];
                if (!boxa.overlaps(nb.box, margin)) continue;  // prunes only: nb.box contains bb[t]
                for (std::uint32_t t = nb.first; t < nb.first + nb.count; ++t)
                    if (boxa.overlaps(bb[t], margin)) emit(out, oa[s], ob[t]);
            }
            return;
        }
        // The columns: the elements of nb whose box overlaps na's box. The others overlap no
        // box of na (na.box contains them: a.min >= na.min, a.max <= na.max, exactly), and the
        // rows likewise need to overlap nb's box. Same pairs, same order as testing every pair.
        detail::BoxColumns columns;
        for (std::uint32_t t = nb.first; t < nb.first + nb.count; ++t)
            if (bb[t].overlaps(na.box, margin)) columns.push(bb[t], margin, t);
        if (columns.size == 0) return;
        columns.pad();
        for (std::uint32_t s = na.first; s < na.first + na.count; ++s) {
            const Aabb& boxa = ba[s];
            if (!boxa.overlaps(nb.box, margin)) continue;
            for (std::uint64_t m = detail::overlap_mask(boxa, margin, columns, path); m != 0; m &= m - 1)
                emit(out, oa[s], ob[columns.slot[std::countr_zero(m)]]);
        }
    }

    // Rows: rows != nullptr (a template argument: the test costs the other pairs nothing)
    template <bool Rows = false>
    void pair(std::uint32_t ia, std::uint32_t ib, Keys* out) const {
        const BvhNode& na = a.nodes()[ia];
        const BvhNode& nb = b.nodes()[ib];
        if (!na.box.overlaps(nb.box, margin)) return;
        if (Rows && (rows->side_a ? na.count : nb.count) <= kRowNodeMax &&
            (rows->side_a ? nb.count : na.count) > kRowNodeMax) {
            if (rows->side_a) row_pairs<true>(na, ib, out);
            else row_pairs<false>(nb, ia, out);
            return;
        }
        if ((na.leaf() && nb.leaf()) || std::uint64_t(na.count) * nb.count <= kBruteForceBelow) {
            all_pairs(na, nb, *out);
            return;
        }
        const bool fork = parallel && std::uint64_t(na.count) + nb.count >= kParallelTraversalMin;
        const bool split_a = !na.leaf() && (nb.leaf() || na.count >= nb.count);
        const std::uint32_t l = split_a ? ia + 1 : ib + 1;
        const std::uint32_t r = split_a ? na.right : nb.right;
        if (fork) {
            tbb::parallel_invoke(
                [&] { split_a ? pair<Rows>(l, ib, &buffers.local()) : pair<Rows>(ia, l, &buffers.local()); },
                [&] { split_a ? pair<Rows>(r, ib, &buffers.local()) : pair<Rows>(ia, r, &buffers.local()); });
        } else if (split_a) {
            pair<Rows>(l, ib, out);
            pair<Rows>(r, ib, out);
        } else {
            pair<Rows>(ia, l, out);
            pair<Rows>(ia, r, out);
        }
    }

    // Row mode: each element of node n (of tree a if RowsOfA, else of b) against the subtree
    // `other` of the other tree.
    template <bool RowsOfA>
    void row_pairs(const BvhNode& n, std::uint32_t other, Keys* out) const {
        const Bvh& own = RowsOfA ? a : b;
        for (std::uint32_t s = n.first; s < n.first + n.count; ++s) {
            const std::uint32_t e = own.order()[s];
            descend<RowsOfA>(own.ordered_boxes()[s], element_planes(*rows->model, e, rows->R), e, other, out);
        }
    }

    // The elements below node i of the other tree whose boxes overlap `box` (the same test as
    // all_pairs: Aabb::overlaps is symmetric) and that `planes` do not clear. A node box holds its
    // elements' boxes exactly, so a node it misses or they clear holds no pair to keep.
    template <bool RowsOfA>
    void descend(const Aabb& box, const detail::ElementPlanes& planes, std::uint32_t e, std::uint32_t i,
                 Keys* out) const {
        const Bvh& other = RowsOfA ? b : a;
        const BvhNode& n = other.nodes()[i];
        if (!box.overlaps(n.box, margin) || planes.clears(n.box, rows->pad)) return;
        if (n.leaf()) {
            const std::uint32_t* o = other.order().data();
            const Aabb* boxes = other.ordered_boxes().data();
            for (std::uint32_t t = n.first; t < n.first + n.count; ++t) {
                if (!box.overlaps(boxes[t], margin) || planes.clears(boxes[t], rows->pad)) continue;
                if constexpr (RowsOfA) emit(*out, e, o[t]);
                else emit(*out, o[t], e);
            }
            return;
        }
        if (parallel && n.count >= kParallelTraversalMin) {
            tbb::parallel_invoke([&] { descend<RowsOfA>(box, planes, e, i + 1, &buffers.local()); },
                                 [&] { descend<RowsOfA>(box, planes, e, n.right, &buffers.local()); });
        } else {
            descend<RowsOfA>(box, planes, e, i + 1, out);
            descend<RowsOfA>(box, planes, e, n.right, out);
        }
    }

    // all pairs inside the subtree of node i (self traversal only)
    void inside(std::uint32_t i, Keys* out) const {
        const BvhNode& n = a.nodes()[i];
        if (n.leaf() || std::uint64_t(n.count) * n.count <= 2 * kBruteForceBelow) {
            const std::uint32_t* o = a.order().data();
            const Aabb* boxes = a.ordered_boxes().data();
            for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
                for (std::uint32_t t = s + 1; t < n.first + n.count; ++t)
                    if (boxes[s].overlaps(boxes[t], margin)) emit(*out, o[s], o[t]);
            return;
        }
        const std::uint32_t l = i + 1, r = n.right;
        if (parallel && n.count >= kParallelTraversalMin) {
            tbb::parallel_invoke([&] { inside(l, &buffers.local()); }, [&] { inside(r, &buffers.local()); },
                                 [&] { pair(l, r, &buffers.local()); });
        } else {
            inside(l, out);
            inside(r, out);
            pair(l, r, out);
        }
    }
};

// How collect_candidates sorts its keys (PairKey(elem1, elem2).bits(), unique): fewer than
// kMinKeysForRadixSort by comparisons (std::sort); fewer than kMinKeysForCountingSort (or fewer
// than a quarter of the first model's elements) by the radix sort of the packed indices; more by
// counting sorts on each element index, or, with threads and kMinKeysForParallelBucketSort
// keys, a counting sort on elem1 and each element's candidates sorted in parallel.
constexpr std::size_t kMinKeysForRadixSort = 256;
constexpr std::size_t kMinKeysForCountingSort = 4096;
constexpr std::size_t kMinKeysForParallelBucketSort = std::size_t(1) << 18;

}  // namespace

// The candidates of bvh_candidates, left sorted in b.keys (every buffer of `b` reused).
// rows: the traversal's row mode (LongElements), or nullptr.
void collect_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin, bool parallel, bool sort,
                        NarrowPhaseScratch::Buffers& b, const LongElements* rows) {
    Keys& keys = b.keys;
    keys.clear();
    if (t1.empty() || t2.empty()) return;
    for (Keys& k : b.per_thread) k.clear();
    const Traversal tr{t1, t2, same_model, margin, parallel, b.per_thread, same_model ? nullptr : rows};
    if (same_model) tr.inside(0, &b.per_thread.local());
    else if (tr.rows != nullptr) tr.pair<true>(0, 0, &b.per_thread.local());
    else tr.pair<false>(0, 0, &b.per_thread.local());
    std::size_t total = 0;
    for (const Keys& k : b.per_thread) total += k.size();
    keys.reserve(total);
    for (const Keys& k : b.per_thread) keys.insert(keys.end(), k.begin(), k.end());
    if (!sort) return;
    // keys are unique, so the sorted sequence does not depend on how the buffers were filled
    const std::size_t n1 = t1.element_boxes().size();
    if (keys.size() < kMinKeysForRadixSort) {
        std::sort(keys.begin(), keys.end());
        return;
    }
    if (keys.size() < kMinKeysForCountingSort || keys.size() < n1 / 4) {
        // radix sort by (elem1, elem2) packed into bit_width(n2) + bit_width(n1) bits (two
        // 11-bit passes for two models of 2 048 elements): the order of the keys, which are
        // unique, so std::sort's, without a comparison
        const int low_bits = std::bit_width(t2.element_boxes().size());
        stable_radix_sort(keys, b.sorted, b.radix_counts,
                          [low_bits](std::uint64_t k) { return pair_key::first(k) << low_bits | pair_key::second(k); });
        return;
    }
    std::vector<std::size_t>& start = b.start;
    Keys& sorted = b.sorted;
    sorted.resize(keys.size());
    if (!parallel || keys.size() < kMinKeysForParallelBucketSort) {
        // many candidates: a counting sort on elem2, then a stable one on elem1 (least
        // significant digit first over the two element indices; no comparison)
        const std::size_t n2 = t2.element_boxes().size();
        start.assign(n2 + 1, 0);
        for (const std::uint64_t k : keys) ++start[pair_key::second(k) + 1];
        for (std::size_t i = 0; i < n2; ++i) start[i + 1] += start[i];
        for (const std::uint64_t k : keys) sorted[start[pair_key::second(k)]++] = k;
        start.assign(n1 + 1, 0);
        for (const std::uint64_t k : sorted) ++start[pair_key::first(k) + 1];
        for (std::size_t i = 0; i < n1; ++i) start[i + 1] += start[i];
        for (const std::uint64_t k : sorted) keys[start[pair_key::first(k)]++] = k;
        return;
    }
    // very many candidates and threads: counting sort on elem1, then each (short) elem1 bucket
    // sorted by elem2, buckets in parallel
    start.assign(n1 + 1, 0);
    for (const std::uint64_t k : keys) ++start[pair_key::first(k) + 1];
    for (std::size_t i = 0; i < n1; ++i) start[i + 1] += start[i];
    b.pos.assign(start.begin(), start.end() - 1);
    for (const std::uint64_t k : keys) sorted[b.pos[pair_key::first(k)]++] = k;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n1, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t e = r.begin(); e < r.end(); ++e)
            if (start[e + 1] - start[e] > 1)
                std::sort(sorted.begin() + std::ptrdiff_t(start[e]), sorted.begin() + std::ptrdiff_t(start[e + 1]));
    });
    std::swap(keys, sorted);
}

}  // namespace detail

std::vector<std::uint64_t> bvh_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin, bool parallel) {
    NarrowPhaseScratch scratch;
    detail::collect_candidates(t1, t2, same_model, margin, parallel, true, scratch.buffers());
    return std::move(scratch.buffers().keys);
}

}  // namespace penalty
