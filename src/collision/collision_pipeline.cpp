#include "penalty/collision/collision_pipeline.hpp"

#include "penalty/core/radix_sort.hpp"

#include "penalty/core/error.hpp"
#include "penalty/core/first_error.hpp"

#include "penalty/collision/box_columns.hpp"
#include "penalty/collision/separation.hpp"
#include "kernels.hpp"
#include "prefetch.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <mutex>
#include <type_traits>

namespace penalty {

namespace {

constexpr std::uint32_t kParallelTraversalMin = 4096;  // element count above which a node pair forks
constexpr std::size_t kChunksPerThread = 4;            // CollisionPipeline::detect in parallel: chunks of pairs per thread

using Keys = std::vector<std::uint64_t>;

std::uint64_t key(std::uint32_t e1, std::uint32_t e2) { return (std::uint64_t(e1) << 32) | e2; }

// Dual-tree traversal collecting the element pairs whose boxes pass the §3.8 test. Below
// kBruteForceBelow element pairs, a node pair is finished by testing all its element pairs
// (the same element box test, so the same pairs, with less recursion).
constexpr std::uint32_t kBruteForceBelow = 64;

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
            tbb::parallel_invoke([&] { split_a ? pair<Rows>(l, ib, &buffers.local()) : pair<Rows>(ia, l, &buffers.local()); },
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

// find_near_pairs tests every pair's root boxes, in pair order, up to this many pairs; beyond,
// it sweeps over the models' root boxes.
constexpr std::size_t kMaxPairsTestedOneByOne = 64;

// How collect_candidates sorts its keys (elem1 << 32 | elem2, unique): fewer than
// kMinKeysForRadixSort by comparisons (std::sort); fewer than kMinKeysForCountingSort (or fewer
// than a quarter of the first model's elements) by the radix sort of the packed indices; more by
// counting sorts on each element index, or, with threads and kMinKeysForParallelBucketSort
// keys, a counting sort on elem1 and each element's candidates sorted in parallel.
constexpr std::size_t kMinKeysForRadixSort = 256;
constexpr std::size_t kMinKeysForCountingSort = 4096;
constexpr std::size_t kMinKeysForParallelBucketSort = std::size_t(1) << 18;

// A kernel that writes the models (detail::KernelParts) needs its candidates in a fixed order.
bool kernel_writes_models(const IntersectionParams& p, const CollisionModel& m1, const CollisionModel& m2) {
    return detail::np_triangle_triangle_writes_normals(p, m1, m2);
}

}  // namespace

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

NarrowPhaseScratch::NarrowPhaseScratch() : buffers_(std::make_unique<Buffers>()) {}
NarrowPhaseScratch::~NarrowPhaseScratch() = default;
NarrowPhaseScratch::NarrowPhaseScratch(NarrowPhaseScratch&&) noexcept = default;
NarrowPhaseScratch& NarrowPhaseScratch::operator=(NarrowPhaseScratch&&) noexcept = default;

namespace {

// The candidates of bvh_candidates, left sorted in b.keys (every buffer of `b` reused).
// rows: the traversal's row mode (LongElements), or nullptr.
void collect_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin, bool parallel, bool sort,
                        NarrowPhaseScratch::Buffers& b, const LongElements* rows = nullptr) {
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
                          [low_bits](std::uint64_t k) { return (k >> 32) << low_bits | (k & 0xffffffffU); });
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
        for (const std::uint64_t k : keys) ++start[std::size_t(k & 0xffffffffU) + 1];
        for (std::size_t i = 0; i < n2; ++i) start[i + 1] += start[i];
        for (const std::uint64_t k : keys) sorted[start[std::size_t(k & 0xffffffffU)]++] = k;
        start.assign(n1 + 1, 0);
        for (const std::uint64_t k : sorted) ++start[std::size_t(k >> 32) + 1];
        for (std::size_t i = 0; i < n1; ++i) start[i + 1] += start[i];
        for (const std::uint64_t k : sorted) keys[start[std::size_t(k >> 32)]++] = k;
        return;
    }
    // very many candidates and threads: counting sort on elem1, then each (short) elem1 bucket
    // sorted by elem2, buckets in parallel
    start.assign(n1 + 1, 0);
    for (const std::uint64_t k : keys) ++start[std::size_t(k >> 32) + 1];
    for (std::size_t i = 0; i < n1; ++i) start[i + 1] += start[i];
    b.pos.assign(start.begin(), start.end() - 1);
    for (const std::uint64_t k : keys) sorted[b.pos[std::size_t(k >> 32)]++] = k;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n1, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t e = r.begin(); e < r.end(); ++e)
            if (start[e + 1] - start[e] > 1)
                std::sort(sorted.begin() + std::ptrdiff_t(start[e]), sorted.begin() + std::ptrdiff_t(start[e + 1]));
    });
    std::swap(keys, sorted);
}

}  // namespace

void broad_phase(const IntersectionParams& params, std::span<CollisionModel* const> models,
                 std::vector<ModelPair>& pairs, std::vector<ModelPair>* unsupported,
                 std::vector<std::array<std::size_t, 2>>* indices) {
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
            if (indices != nullptr) indices->push_back(keep_order ? std::array{j, i} : std::array{i, j});
        }
    }
}

std::vector<std::uint64_t> bvh_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin,
                                          bool parallel) {
    NarrowPhaseScratch scratch;
    collect_candidates(t1, t2, same_model, margin, parallel, true, scratch.buffers());
    return std::move(scratch.buffers().keys);
}

namespace {

// The largest side of an element box of a Triangle or Line model (0 for the other models, whose
// kernels have no separation tests).
double longest_box_side(const CollisionModel& m, const Bvh& t) {
    if (m.type() != ModelType::Triangle && m.type() != ModelType::Line) return 0.0;
    double side = 0.0;
    for (const Aabb& box : t.element_boxes()) side = std::max(side, (box.max - box.min).maxCoeff());
    return side;
}

// The row mode of a model pair (LongElements) whose Triangle or Line element boxes have sides
// up to side1 and side2 (longest_box_side), or none (model nullptr): a model with elements worth
// separating (worth_separating), of a kernel whose outputs join element points
// (outputs_join_element_points); the one with fewer elements if both are long.
LongElements long_elements(const IntersectionParams& params, const CollisionModel& m1, double side1,
                           const CollisionModel& m2, double side2) {
    const double R = box_margin(params, m1, m2);
    const bool long1 = detail::worth_separating(side1, R);
    const bool long2 = detail::worth_separating(side2, R);
    if (&m1 == &m2 || (!long1 && !long2)) return {};
    if (!detail::outputs_join_element_points(detail::pair_kernel_parts(params, m1, m2))) return {};
    const bool side_a = long1 && (!long2 || m1.size() <= m2.size());
    return {side_a ? &m1 : &m2, side_a, R, 0.0};
}

// The kernel's writes (KernelParts::writes, not null) over the candidates `keys` of m1 × m2 in
// their order; within one node, the element pairs that may not collide are skipped, as
// evaluate_candidates skips them.
void run_kernel_writes(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                       const detail::KernelParts& kernel, std::span<const std::uint64_t> keys) {
    const bool node = same_node(m1, m2);
    DetectionOutputList none;  // the writes make no output
    detail::PairCtx ctx{params, m1, m2, 0, 0, none};
    for (const std::uint64_t key : keys) {
        ctx.e1 = Index(key >> 32);
        ctx.e2 = Index(key & 0xffffffffu);
        if (node && !elements_may_collide(m1, ctx.e1, m2, ctx.e2)) continue;
        kernel.writes(ctx);
    }
}

// Intersects the candidates `all_keys` (element 1 << 32 | element 2) of m1 × m2 in their
// order: the kernel's filter first, if it has one (KernelParts::filter: drops candidates that
// give no output), then its writes to the models, over all candidates in order, then its reads,
// in parallel chunks concatenated in chunk order (the outputs of the sequential loop).
// separation_tests: the kernels run their early outs (separation.hpp) on every candidate.
// deferred_writes: if not null, the kernel's writes are not run but their candidates appended
// to it, in the order they would have run in (run_kernel_writes runs them later).
void evaluate_candidates(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                         const Keys& all_keys, const NarrowPhaseOptions& opt, NarrowPhaseScratch::Buffers& b,
                         DetectionOutputList& out, bool separation_tests, Keys* deferred_writes) {
    const bool node = same_node(m1, m2);
    // intersect_elements' lookup and checks, once for the pair; the keys come from trees of the
    // models' sizes (check_trees), so every element index is in range
    const detail::KernelParts kernel = detail::pair_kernel_parts(params, m1, m2);
    const Keys* candidates = &all_keys;
    if (kernel.filter != nullptr && !all_keys.empty()) {
        b.filtered.clear();
        kernel.filter(params, m1, m2, all_keys, b.filtered);
        candidates = &b.filtered;
    }
    const Keys& keys = *candidates;
    // the planes its separation tests read, for the current positions, before the parallel part
    if (!keys.empty() && detail::reads_triangle_planes(kernel)) {
        static_cast<TriangleModel&>(m1).update_planes();
        static_cast<TriangleModel&>(m2).update_planes();
    }
    const CollisionModel::ElementRow row1 = m1.element_row();
    const CollisionModel::ElementRow row2 = m2.element_row();
    const bool prefetch =
        row1.base != nullptr && row2.base != nullptr && detail::prefetch::worth_it(m1.size() + m2.size());
    auto for_each_candidate = [&](std::size_t begin, std::size_t end, DetectionOutputList& to, auto&& fn) {
        detail::PairCtx ctx{params, m1, m2, 0, 0, to, separation_tests};
        for (std::size_t k = begin; k < end; ++k) {
            if (prefetch && k + detail::prefetch::kAhead < end) {
                const std::uint64_t ahead = keys[k + detail::prefetch::kAhead];
                detail::prefetch::object(row1.base + row1.stride * (ahead >> 32), row1.stride);
                detail::prefetch::object(row2.base + row2.stride * (ahead & 0xffffffffu), row2.stride);
            }
            ctx.e1 = Index(keys[k] >> 32);
            ctx.e2 = Index(keys[k] & 0xffffffffu);
            if (node && !elements_may_collide(m1, ctx.e1, m2, ctx.e2)) continue;
            fn(ctx);
        }
    };
    if (kernel.writes != nullptr) {
        if (deferred_writes != nullptr) deferred_writes->insert(deferred_writes->end(), keys.begin(), keys.end());
        else run_kernel_writes(params, m1, m2, kernel, keys);
    }
    auto run = [&](std::size_t begin, std::size_t end, DetectionOutputList& to) {
        if (kernel.reads_all != nullptr && !node) {
            detail::PairCtx ctx{params, m1, m2, 0, 0, to, separation_tests};
            kernel.reads_all(ctx, std::span<const std::uint64_t>(keys).subspan(begin, end - begin));
            return;
        }
        for_each_candidate(begin, end, to, kernel.reads);
    };
    // one thread (the arena's, e.g. a benchmark's or a user's task_arena of 1): the chunks would
    // be run one after the other and then copied into `out` in order, the same outputs
    if (!opt.parallel || keys.size() <= opt.chunk_size || tbb::this_task_arena::max_concurrency() < 2) {
        run(0, keys.size(), out);
        return;
    }
    const std::size_t chunk = std::max<std::size_t>(1, opt.chunk_size);
    const std::size_t nchunks = (keys.size() + chunk - 1) / chunk;
    std::vector<DetectionOutputList>& parts = b.parts;
    if (parts.size() < nchunks) parts.resize(nchunks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nchunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
            parts[c].clear();
            run(c * chunk, std::min(keys.size(), (c + 1) * chunk), parts[c]);
        }
    });
    std::size_t total = out.size();
    for (std::size_t c = 0; c < nchunks; ++c) total += parts[c].size();
    out.reserve(total);
    for (std::size_t c = 0; c < nchunks; ++c) out.insert(out.end(), parts[c].begin(), parts[c].end());
}

// CollisionPipelineOptions::contact_outputs_only: drops from `keys` (the rest kept in order)
// the candidates none of whose outputs a contact can be made of, for a kernel of
// outputs_nearest_to_element2. There the outputs of element 2 all have id e2 and value
// |q − P| − c, with |q − P| ≥ D, the distance from q, e2's point (with_element_points), to the candidate's
// element-1 box (which holds P), and ContactTracker keeps, per id, the first output of least
// value. Each element 2's candidate of least D is evaluated first: given an output of length
// L, a candidate with D > L + tol gives no output of value ≤ that output's, so neither the
// least value nor a tie with it, and is dropped. tol = 1e-10 of the magnitudes involved
// covers the rounding of the kernels' lengths and of the subtraction of c (≈ 1e-15 of them).
// An element 2 whose nearest candidate gives no output keeps all its candidates. Run only for
// at least 8 candidates per element of m2 on average (worth_keeping_nearest): with fewer, the
// distances, the per-element arrays and the kernels run twice cost more than the kernels saved
// (callgrind: ModelizationTriangleBased and MultipleObjectsTwoCubes, a cube's 8 points against
// a floor, 0.6–2.6 % more instructions at 2 per element; AdvancedSolversMultipleGroupsSolver 6 % fewer
// at 8 than the 3 % at 2).
bool worth_keeping_nearest(std::size_t candidates, const CollisionModel& m2) {
    return candidates >= 8 && candidates >= 8 * m2.size();
}

void keep_nearest_candidates(const IntersectionParams& params, CollisionModel& m1, const Aabb* boxes1,
                             CollisionModel& m2, Keys& keys, NarrowPhaseScratch::Buffers& b, bool separation_tests,
                             Keys* deferred_writes) {
    const std::size_t n = keys.size();
    const std::size_t n2 = m2.size();
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    b.reach.resize(n);
    b.nearest.assign(n2, kNone);
    b.bound.assign(n2, kInf);  // first the least reach of each element 2, then its bound
    // the squared distance from q to the box
    const auto reach_of = [](const Aabb& box, const Vec3& q) {
        return (box.min - q).cwiseMax(q - box.max).cwiseMax(0.0).squaredNorm();
    };
    detail::with_element_points(m2, [&](auto&& point_of) {
        if (n2 == 1) {
            // one element 2 (a sphere): its least reach kept in a register, not read back from
            // memory at every key
            const Vec3& q = point_of(0);
            double least = kInf;
            std::uint32_t at = kNone;
            for (std::size_t k = 0; k < n; ++k) {
                const double d2 = reach_of(boxes1[keys[k] >> 32], q);
                b.reach[k] = d2;
                if (d2 < least) {
                    least = d2;
                    at = std::uint32_t(k);
                }
            }
            b.bound[0] = least;
            b.nearest[0] = at;
        } else {
            for (std::size_t k = 0; k < n; ++k) {
                const std::uint64_t key = keys[k];
                const std::size_t e2 = key & 0xffffffffu;
                const double d2 = reach_of(boxes1[key >> 32], point_of(Index(e2)));
                b.reach[k] = d2;
                if (d2 < b.bound[e2]) {
                    b.bound[e2] = d2;
                    b.nearest[e2] = std::uint32_t(k);
                }
            }
        }
        // (as the per-element arrays: the capacity of every element 2, not of this step's ones)
        b.nearest_keys.clear();
        b.nearest_keys.reserve(n2);
        b.nearest_outputs.reserve(n2);
        for (std::size_t e2 = 0; e2 < n2; ++e2) {
            if (b.nearest[e2] != kNone) b.nearest_keys.push_back(keys[b.nearest[e2]]);
            b.bound[e2] = kInf;
        }
        b.nearest_outputs.clear();
        NarrowPhaseOptions serial;
        serial.parallel = false;
        evaluate_candidates(params, m1, m2, b.nearest_keys, serial, b, b.nearest_outputs, separation_tests, deferred_writes);
        for (const DetectionOutput& o : b.nearest_outputs) {
            const Vec3& q = point_of(o.elem2);
            const double length = (q - o.point[0]).norm();
            const double scale =
                1.0 + q.cwiseAbs().maxCoeff() + o.point[0].cwiseAbs().maxCoeff() + length + std::abs(o.value);
            const double reach = length + 1e-10 * scale;
            b.bound[std::size_t(o.elem2)] = std::min(b.bound[std::size_t(o.elem2)], reach * reach);
        }
    });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < n; ++k)
        if (b.reach[k] <= b.bound[keys[k] & 0xffffffffu]) keys[kept++] = keys[k];
    keys.resize(kept);
}

// After keep_nearest_candidates and the evaluation of the candidates left: drops from
// out[from, end) (the rest kept in order) every output whose value is above the least value of
// its element 2 (its id), which ContactTracker would not keep; the outputs of least value, ties
// included, stay, so the tracker keeps the same one. Their number is then that of the contacts
// (but for exact ties), which does not change from step to step as the candidates' outputs do.
// `out` was given the capacity of one output per candidate (these kernels give at most one),
// which is that of the kept candidates in steady state: the evaluation allocates nothing.
// The values are finite (validate() rejects non-finite positions); a NaN would make the
// tracker's choice depend on every output (a later NaN replaces its winner), so an output list
// with one is left whole.
void keep_least_outputs(DetectionOutputList& out, std::size_t from, std::size_t n2, NarrowPhaseScratch::Buffers& b) {
    if (out.size() - from < 2) return;
    b.bound.assign(n2, std::numeric_limits<double>::infinity());
    for (std::size_t i = from; i < out.size(); ++i) {
        if (std::isnan(out[i].value)) return;
        b.bound[std::size_t(out[i].elem2)] = std::min(b.bound[std::size_t(out[i].elem2)], out[i].value);
    }
    std::size_t kept = from;
    for (std::size_t i = from; i < out.size(); ++i)
        if (out[i].value <= b.bound[std::size_t(out[i].elem2)]) {
            if (kept != i) out[kept] = out[i];
            ++kept;
        }
    out.resize(kept);
}

void check_trees(const CollisionModel& m1, const Bvh& t1, const CollisionModel& m2, const Bvh& t2) {
    if (t1.element_boxes().size() != m1.size() || t2.element_boxes().size() != m2.size()) {
        throw_invalid_argument("bvh_narrow_phase(): the trees of '", m1.name(), "' and '", m2.name(),
                               "' are out of date (model sizes changed)");
    }
}

// Largest change of any box bound between two lists of the same size (stops above `limit`).
double largest_bound_change(std::span<const Aabb> now, std::span<const Aabb> before, double limit) {
    double moved = 0.0;
    for (std::size_t e = 0; e < now.size(); ++e) {
        const Vec3 d = (now[e].min - before[e].min).cwiseAbs().cwiseMax((now[e].max - before[e].max).cwiseAbs());
        moved = std::max(moved, d.maxCoeff());
        if (!(moved <= limit)) return moved;  // NaN too
    }
    return moved;
}

// bvh_narrow_phase with the sizes of the models' longest element boxes (longest_box_side) given
// by the caller: they decide the pair's separation tests and the traversal's row mode
// contact_outputs_only: keep_nearest_candidates for a kernel of outputs_nearest_to_element2.
void narrow_phase_on_trees(const IntersectionParams& params, CollisionModel& m1, const Bvh& t1, CollisionModel& m2,
                           const Bvh& t2, const NarrowPhaseOptions& opt, NarrowPhaseScratch& scratch,
                           DetectionOutputList& out, double side1, double side2, bool contact_outputs_only = false,
                           Keys* deferred_writes = nullptr) {
    const bool same_model = &m1 == &m2;
    check_trees(m1, t1, m2, t2);
    NarrowPhaseScratch::Buffers& b = scratch.buffers();
    const bool writes_models = kernel_writes_models(params, m1, m2);
    const double margin = box_margin(params, m1, m2);
    const LongElements rows = long_elements(params, m1, side1, m2, side2);
    collect_candidates(t1, t2, same_model, margin, opt.parallel, opt.sorted_candidates || writes_models, b,
                       rows.model != nullptr ? &rows : nullptr);
    const bool separation_tests = detail::worth_separating(std::max(side1, side2), margin);
    const std::size_t candidates = b.keys.size();
    const bool nearest = contact_outputs_only && worth_keeping_nearest(candidates, m2) &&
                         detail::outputs_nearest_to_element2(params, detail::pair_kernel_parts(params, m1, m2));
    if (nearest) keep_nearest_candidates(params, m1, t1.element_boxes().data(), m2, b.keys, b, separation_tests, deferred_writes);
    const std::size_t from = out.size();
    if (nearest) out.reserve(from + candidates);
    evaluate_candidates(params, m1, m2, b.keys, opt, b, out, separation_tests, deferred_writes);
    if (nearest) keep_least_outputs(out, from, m2.size(), b);
}
}  // namespace

void bvh_narrow_phase(const IntersectionParams& params, CollisionModel& m1, const Bvh& t1, CollisionModel& m2,
                      const Bvh& t2, const NarrowPhaseOptions& opt, NarrowPhaseScratch& scratch,
                      DetectionOutputList& out) {
    narrow_phase_on_trees(params, m1, t1, m2, t2, opt, scratch, out, longest_box_side(m1, t1),
                          longest_box_side(m2, t2));
}

void CollisionPipeline::PairCounts::add_to(CandidateCacheStats& stats, std::size_t& candidates_evaluated) const {
    stats.reused += cache.reused;
    stats.collected += cache.collected;
    stats.in_sofa_order += cache.in_sofa_order;
    stats.sofa_order_sorts += cache.sofa_order_sorts;
    stats.branch_free_tests += cache.branch_free_tests;
    stats.sure_keys_skipped += cache.sure_keys_skipped;
    candidates_evaluated += candidates;
}

CollisionPipeline::CollisionPipeline(IntersectionParams params, CollisionPipelineOptions opt,
                                     ContactDetection detection)
    : params_(std::move(params)), opt_(opt), detection_(detection) {
    params_.validate();
    if (opt_.depth < 0) opt_.depth = 6;  // SOFA resets a negative depth to 6
    if (opt_.leaf_size == 0) throw_invalid_argument("CollisionPipeline: leaf_size must be >= 1");
    if (!(opt_.rebuild_ratio >= 1.0)) throw_invalid_argument("CollisionPipeline: rebuild_ratio must be >= 1");
}

void CollisionPipeline::set_models(std::vector<CollisionModel*> models) {
    for (std::size_t i = 0; i < models.size(); ++i)
        if (models[i] == nullptr) throw_invalid_argument("CollisionPipeline::set_models(): model ", i, " is null");
    models_ = std::move(models);
    trees_.assign(models_.size(), Bvh{});
    sofa_trees_.assign(models_.size(), SofaCubeTree{});
    motion_.assign(models_.size(), ModelMotion{});
    pair_candidates_.clear();
    index_models();
}

void CollisionPipeline::add_model(CollisionModel& model) {
    models_.push_back(&model);
    trees_.emplace_back();
    sofa_trees_.emplace_back();
    motion_.emplace_back();
    index_models();
}

std::size_t CollisionPipeline::model_index(const CollisionModel& m) const {
    // binary search in (address, index) pairs: a scene with many models asks for two per pair
    const auto it = std::lower_bound(index_of_.begin(), index_of_.end(), std::pair<const CollisionModel*, std::size_t>(&m, 0));
    if (it == index_of_.end() || it->first != &m)
        throw_invalid_argument("CollisionPipeline: model '", m.name(), "' is not registered");
    return it->second;
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
            if (tree.refit(m, opt_.rebuild_ratio, opt_.leaf_size)) motion_[i].longest_side = longest_box_side(m, tree);
            if (opt_.candidate_cache) track_motion(i);
        } else if (tree.build_count() == 0 || tree.element_boxes().size() != m.size()) {
            m.validate();  // static: checked and built once (SOFA: bounding tree computed once)
            m.update();    // a static model's update() computes once
            tree.build(m, opt_.leaf_size);
            motion_[i].longest_side = longest_box_side(m, tree);
            if (opt_.candidate_cache) track_motion(i);
        }
    }
}

void CollisionPipeline::track_motion(std::size_t i) {
    const std::vector<Aabb>& boxes = trees_[i].element_boxes();
    ModelMotion& mm = motion_[i];
    const bool moving = models_[i]->params().moving;
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
    if (!trees_[i].empty()) {
        const Aabb& root = trees_[i].root_box();
        const double root_extent = (root.max - root.min).maxCoeff();
        extent = std::max(extent, 1e-3 * root_extent);
        // A Point model's elements have no extent (their boxes are the contact distance): its
        // slack may grow up to a quarter of the points' spacing on a surface, root extent / √n.
        // (With 1e-3 of the root extent, the points of AdvancedSolversMultipleGroupsSolver's
        // falling cubes were traversed at nearly every step.)
        if (models_[i]->type() == ModelType::Point)
            largest_extent = std::max(extent, root_extent / std::sqrt(double(boxes.size())));
    }
    if (!std::isfinite(extent)) extent = 0.0;
    largest_extent = std::isfinite(largest_extent) ? std::max(largest_extent, extent) : extent;
    const bool cheap_slack = mm.kept_keys > 0 && 8 * mm.overlapping_keys >= 7 * mm.kept_keys;
    double slack_bound = 0.25 * largest_extent;
    if (cheap_slack) slack_bound = std::max(slack_bound, 0.5 * params_.alarm_distance);
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

void CollisionPipeline::detect_pair(CollisionModel& m1, CollisionModel& m2, DetectionOutputList& out) {
    PairCounts counts;
    detect_pair_with(model_index(m1), model_index(m2), out, scratch_, counts, nullptr);
    counts.add_to(cache_stats_, candidates_evaluated_);
}

void CollisionPipeline::detect_pair_with(std::size_t i1, std::size_t i2, DetectionOutputList& out,
                                         PairScratch& scratch, PairCounts& counts, PairCandidates* kept,
                                         std::vector<std::uint64_t>* deferred_writes) {
    out.clear();
    const bool in_sofa_order = detect_pair_unordered(i1, i2, out, scratch, counts, kept, deferred_writes);
    if (!opt_.sofa_output_order || in_sofa_order || out.size() < 2) return;
    ensure_sofa_trees(i1, i2);
    sort_in_sofa_order(sofa_trees_[i1], sofa_trees_[i2], out, scratch.sofa_order);
}

void CollisionPipeline::ensure_sofa_trees(std::size_t i1, std::size_t i2) {
    for (const std::size_t i : {i1, i2}) {
        // SOFA builds a model's tree at its first detection and then only refits it
        // (CubeCollisionModel::computeBoundingTree); rebuilt here only if the model's size changed
        if (sofa_trees_[i].empty() || sofa_trees_[i].size() != models_[i]->size())
            sofa_trees_[i].build(*models_[i], opt_.depth);
    }
}

void CollisionPipeline::sort_keys_in_sofa_order(std::size_t i1, std::size_t i2, std::vector<std::uint64_t>& keys,
                                                SofaOrderScratch& scratch) {
    ensure_sofa_trees(i1, i2);
    penalty::sort_keys_in_sofa_order(sofa_trees_[i1], sofa_trees_[i2], keys, scratch);
}

void CollisionPipeline::build_sofa_trees() {
    if (!opt_.sofa_output_order) return;
    for (std::size_t i = 0; i < models_.size(); ++i) {
        CollisionModel& m = *models_[i];
        if (!m.params().active || m.size() == 0) continue;
        if (sofa_trees_[i].empty() || sofa_trees_[i].size() != m.size()) sofa_trees_[i].build(m, opt_.depth);
    }
}

CollisionPipeline::PairCandidates* CollisionPipeline::pair_candidates_entry(std::size_t i1, std::size_t i2) {
    if (detection_ != ContactDetection::bvh || !opt_.candidate_cache) return nullptr;
    if (motion_[i1].generation == 0 || motion_[i2].generation == 0) return nullptr;
    return &pair_candidates_[(std::uint64_t(i1) << 32) | std::uint64_t(i2)];
}

bool CollisionPipeline::detect_pair_unordered(std::size_t i1, std::size_t i2, DetectionOutputList& out,
                                              PairScratch& scratch, PairCounts& counts, PairCandidates* kept_entry,
                                              Keys* deferred_writes) {
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
    const double margin = box_margin(params_, m1, m2);
    // with SOFA's output order the outputs are sorted afterwards (detect_pair): the candidates
    // need no sort of their own
    NarrowPhaseOptions narrow = opt_.narrow;
    if (opt_.sofa_output_order) narrow.sorted_candidates = false;
    const ModelMotion& a = motion_[i1];
    const ModelMotion& b = motion_[i2];
    if (!opt_.candidate_cache || a.generation == 0 || b.generation == 0) {
        if (&m1 != &m2 && !t1.root_box().overlaps(t2.root_box(), margin)) return false;
        narrow_phase_on_trees(params_, m1, t1, m2, t2, narrow, scratch.narrow, out, a.longest_side, b.longest_side,
                              opt_.contact_outputs_only, deferred_writes);
        counts.candidates += scratch.narrow.buffers().keys.size();
        return false;
    }
    const bool separation_tests = detail::worth_separating(std::max(a.longest_side, b.longest_side), margin);
    // Candidate cache. Since a generation began every box bound moved by at most its model's
    // slack s, so between the collection and now by at most 2·s: a pair overlapping now with
    // margin m overlapped at the collection with m + 2·(s1 + s2). The kept pairs are box-tested
    // again with m, exactly as the traversal tests them, so the candidates are the traversal's.
    check_trees(m1, t1, m2, t2);
    const bool writes_models = kernel_writes_models(params_, m1, m2);
    NarrowPhaseScratch::Buffers& buf = scratch.narrow.buffers();
    PairCandidates& kept = kept_entry != nullptr ? *kept_entry : *pair_candidates_entry(i1, i2);
    if (kept.generation1 != a.generation || kept.generation2 != b.generation) {
        ++counts.cache.collected;
        const double wide = margin + 2.0 * (a.slack + b.slack);
        // the row mode with the boxes grown by how far they may move while the keys are kept
        // (2 · slack each); only for a static long model, whose elements (planes) stay put
        LongElements rows = long_elements(params_, m1, a.longest_side, m2, b.longest_side);
        if (rows.model != nullptr && rows.model->params().moving) rows.model = nullptr;
        rows.pad = 2.0 * (a.slack + b.slack);
        kept.keys.clear();
        if (&m1 == &m2 || t1.root_box().overlaps(t2.root_box(), wide)) {
            collect_candidates(t1, t2, &m1 == &m2, wide, narrow.parallel, narrow.sorted_candidates || writes_models, buf,
                               rows.model != nullptr ? &rows : nullptr);
            kept.keys.assign(buf.keys.begin(), buf.keys.end());
        }
        kept.in_sofa_order = false;
        kept.outputs_sorted = 0;
        kept.sure_current = false;
        if (opt_.sofa_output_order && !writes_models) {
            // sort_keys_in_sofa_order's buffers, grown here (a collection allocates anyway) and not
            // at the later step that sorts the keys
            const std::size_t n = kept.keys.size();
            scratch.sofa_order.keyed.reserve(n);
            scratch.sofa_order.permutation.reserve(n);
            scratch.sofa_order.sorted_keys.reserve(n);
        }
        kept.generation1 = a.generation;
        kept.generation2 = b.generation;
        kept.nearest_outputs = opt_.contact_outputs_only &&
                               detail::outputs_nearest_to_element2(params_, detail::pair_kernel_parts(params_, m1, m2));
    } else {
        ++counts.cache.reused;
    }
    // Kept in SOFA's visiting order, the outputs come out in it (evaluate_candidates keeps the
    // candidates' order). Sorted when the outputs sorted in this generation outnumber the kept
    // keys (PairCandidates). Not for a kernel that writes the models: its writes run over the
    // candidates sorted by element.
    if (opt_.sofa_output_order && !writes_models && !kept.in_sofa_order && kept.outputs_sorted >= kept.keys.size()) {
        if (kept.keys.size() >= 2) sort_keys_in_sofa_order(i1, i2, kept.keys, scratch.sofa_order);
        kept.in_sofa_order = true;
        kept.sure_current = false;
        ++counts.cache.sofa_order_sorts;
    }
    Keys& now = buf.keys;
    now.clear();
    const Aabb* boxes1 = t1.element_boxes().data();
    const Aabb* boxes2 = t2.element_boxes().data();
    const std::size_t n_kept = kept.keys.size();
    const std::uint64_t* keys = kept.keys.data();
    const bool prefetch = detail::prefetch::worth_it(m1.size() + m2.size());
    const auto prefetch_ahead = [&](std::size_t j) {
        if (prefetch && j + detail::prefetch::kAhead < n_kept) {
            const std::uint64_t ahead = keys[j + detail::prefetch::kAhead];
            detail::prefetch::object(boxes1 + (ahead >> 32), sizeof(Aabb));
            detail::prefetch::object(boxes2 + (ahead & 0xffffffffu), sizeof(Aabb));
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
    // bound makes no key sure). The flags are made in the first such test after a collection
    // or a reordering, and the sure keys' box tests are skipped from then on.
    const std::size_t share_eighths = n_kept == 0 ? 0 : 8 * kept.overlapped_last / n_kept;
    const bool mostly_overlapping = share_eighths >= 7;
    double sure_margin = 0.0;
    if (mostly_overlapping && !kept.sure_current) {
        const double reach = 2.0 * (a.slack + b.slack);
        const auto magnitude = [](const Aabb& box) {
            return std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
        };
        const double scale = 1.0 + std::abs(margin) + reach + std::max(magnitude(t1.root_box()), magnitude(t2.root_box()));
        sure_margin = margin - reach - 1e-12 * scale;
        kept.sure.resize(n_kept);
    }
    std::uint8_t* sure = kept.sure.data();
    // 0: no flags; 1: the flags are current; 2: made in this test
    const int flags = !mostly_overlapping ? 0 : kept.sure_current ? 1 : 2;
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
                    count += boxes1[k >> 32].overlaps_branch_free(boxes2[k & 0xffffffffu], margin) ? 1 : 0;
                } else if (flags == 1) {
                    if (sure[j] != 0 || boxes1[k >> 32].overlaps(boxes2[k & 0xffffffffu], margin)) block[count++] = k;
                } else if (flags == 2) {
                    const Aabb& box1 = boxes1[k >> 32];
                    const Aabb& box2 = boxes2[k & 0xffffffffu];
                    sure[j] = box1.overlaps_branch_free(box2, sure_margin) ? 1 : 0;
                    sure_count += sure[j];
                    if (sure[j] != 0 || box1.overlaps(box2, margin)) block[count++] = k;
                } else if (boxes1[k >> 32].overlaps(boxes2[k & 0xffffffffu], margin)) {
                    block[count++] = k;
                }
            }
            now.insert(now.end(), block, block + count);
        }
    };
    if (share_eighths == 0 || mostly_overlapping) {
        test_keys(std::false_type{});
        if (flags == 1) counts.cache.sure_keys_skipped += kept.sure_count;
        if (flags == 2) {
            kept.sure_current = true;
            kept.sure_count = sure_count;
        }
    } else {
        ++counts.cache.branch_free_tests;
        test_keys(std::true_type{});
    }
    kept.overlapped_last = now.size();
    const bool nearest = kept.nearest_outputs && worth_keeping_nearest(now.size(), m2);
    if (nearest) keep_nearest_candidates(params_, m1, boxes1, m2, now, buf, separation_tests, deferred_writes);
    const std::size_t from = out.size();
    if (nearest) out.reserve(from + kept.keys.size());
    evaluate_candidates(params_, m1, m2, now, narrow, buf, out, separation_tests, deferred_writes);
    if (nearest) keep_least_outputs(out, from, m2.size(), buf);
    counts.candidates += now.size();
    if (kept.in_sofa_order) ++counts.cache.in_sofa_order;
    else kept.outputs_sorted += out.size();
    return kept.in_sofa_order;
}

const SceneDetection& CollisionPipeline::detect() {
    refit();
    build_sofa_trees();  // SOFA computes every model's bounding tree at each detection
    const bool rebuilt = update_broad_phase();
    if (detection_ == ContactDetection::exhaustive) {
        // the root boxes the trees would give (roots_within_margin)
        root_boxes_.assign(models_.size(), Aabb{});
        for (std::size_t i = 0; i < models_.size(); ++i) {
            const CollisionModel& m = *models_[i];
            if (!m.params().active || m.size() == 0) continue;
            boxes_.resize(m.size());
            m.element_boxes(0, m.size(), boxes_.data());
            for (const Aabb& b : boxes_) root_boxes_[i].extend(b);
        }
        for (std::size_t k = 0; k < pairs_.size(); ++k)
            result_[k].narrow_phase = roots_within_margin(pair_indices_[k][0], pair_indices_[k][1]);
    } else {
        find_near_pairs();
    }
    last_concurrent_ = pairs_run_concurrently();
    pair_work_.resize(pairs_.size());
    if (last_concurrent_) detect_pairs_concurrently();
    else detect_pairs_in_order();
    if (detection_ == ContactDetection::bvh) {
        count_kept_keys();
        // the pairs without narrow phase evaluated nothing (every one after a new broad phase,
        // else those that just left near_)
        if (rebuilt) {
            for (std::size_t k = 0; k < pairs_.size(); ++k)
                if (is_near_[k] == 0) record_pair_work(k, 0);
        } else {
            for (const std::size_t k : near_last_)
                if (is_near_[k] == 0) record_pair_work(k, 0);
        }
    }
    return result_;
}

bool CollisionPipeline::ModelKey::describes(const CollisionModel& m) const {
    const CollisionModelParams& p = m.params();
    return model == &m && type == m.type() && active == p.active && simulated == p.simulated &&
           self_collision == p.self_collision && both_side == p.both_side && node == p.node && group == p.group;
}

bool CollisionPipeline::update_broad_phase() {
    bool same = broad_phase_key_.size() == models_.size();
    for (std::size_t i = 0; same && i < models_.size(); ++i) same = broad_phase_key_[i].describes(*models_[i]);
    if (same) return false;
    broad_phase(params_, models_, pairs_, &unsupported_, &pair_indices_);
    broad_phase_key_.resize(models_.size());
    for (std::size_t i = 0; i < models_.size(); ++i) {
        const CollisionModel& m = *models_[i];
        const CollisionModelParams& p = m.params();
        broad_phase_key_[i] = {&m, m.type(), p.active, p.simulated, p.self_collision, p.both_side, p.node, p.group};
    }
    result_.resize(pairs_.size());  // the remaining entries keep their output capacity
    any_pair_writes_models_ = false;
    pair_of_models_.clear();
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
        ModelPairDetection& d = result_[k];
        d.model1 = pairs_[k].model1;
        d.model2 = pairs_[k].model2;
        d.support = pair_support(params_, d.model1->type(), d.model2->type());
        d.skipped = false;
        d.narrow_phase = false;
        d.outputs.clear();
        any_pair_writes_models_ = any_pair_writes_models_ || kernel_writes_models(params_, *d.model1, *d.model2);
        const std::uint64_t lower = std::min(pair_indices_[k][0], pair_indices_[k][1]);
        const std::uint64_t higher = std::max(pair_indices_[k][0], pair_indices_[k][1]);
        pair_of_models_.emplace(lower << 32 | higher, k);
    }
    near_.clear();
    near_last_.clear();
    is_near_.assign(pairs_.size(), 0);
    return true;
}

void CollisionPipeline::find_near_pairs() {
    std::swap(near_, near_last_);
    near_.clear();
    if (pairs_.size() <= kMaxPairsTestedOneByOne) {
        // few pairs: each one's test, in pair order, costs less than a sweep
        for (std::size_t k = 0; k < pairs_.size(); ++k)
            if (roots_within_margin(pair_indices_[k][0], pair_indices_[k][1])) near_.push_back(k);
        mark_near_pairs();
        return;
    }
    const auto consider = [&](std::size_t a, std::size_t b) {  // models a <= b
        const auto it = pair_of_models_.find(std::uint64_t(a) << 32 | b);
        if (it == pair_of_models_.end()) return;  // filtered out by the broad phase
        const std::size_t k = it->second;
        if (roots_within_margin(pair_indices_[k][0], pair_indices_[k][1])) near_.push_back(k);
    };
    // The models roots_within_margin may pass: neither empty nor without a tree. The margin of
    // a pair is at most `reach` (box_margin's largest terms), so a pair whose root boxes are
    // apart by more than `reach` on the sweep's axis fails it (max + m <= max + reach, the sums
    // rounded alike). The root boxes are finite: a tree refuses an element box that is not.
    sweep_.clear();
    double largest_contact_distance = 0.0;
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (std::size_t i = 0; i < models_.size(); ++i) {
        const CollisionModel& m = *models_[i];
        if (m.size() == 0 || trees_[i].empty()) continue;
        largest_contact_distance = std::max(largest_contact_distance, m.params().contact_distance);
        const Aabb& r = trees_[i].root_box();
        PENALTY_DEMAND(r.min.allFinite() && r.max.allFinite());
        sweep_.push_back(i);
        const Vec3 centre = 0.5 * (r.min + r.max);
        low = low.cwiseMin(centre);
        high = high.cwiseMax(centre);
    }
    const double reach = params_.method == IntersectionMethod::Discrete
                             ? params_.alarm_distance
                             : params_.alarm_distance + largest_contact_distance + largest_contact_distance;
    // a model with itself (roots_within_margin passes it when neither is empty)
    for (const std::size_t i : sweep_) consider(i, i);
    // sweep and prune on the axis where the boxes' centres spread most
    int axis = 0;
    (high - low).maxCoeff(&axis);
    const auto lower_bound_of = [&](std::size_t i) { return trees_[i].root_box().min[axis]; };
    std::sort(sweep_.begin(), sweep_.end(), [&](std::size_t a, std::size_t b) {
        return lower_bound_of(a) != lower_bound_of(b) ? lower_bound_of(a) < lower_bound_of(b) : a < b;
    });
    // the root boxes of the sweep's models in sweep order (compact: the inner loop reads them)
    sweep_boxes_.clear();
    for (const std::size_t i : sweep_) sweep_boxes_.push_back(trees_[i].root_box());
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
    if (near_.size() < kMinKeysForRadixSort) std::sort(near_.begin(), near_.end());
    else stable_radix_sort(near_, sweep_swap_, sweep_counts_, [](std::size_t k) { return std::uint64_t(k); });
    mark_near_pairs();
}

void CollisionPipeline::mark_near_pairs() {
    for (const std::size_t k : near_last_) {
        is_near_[k] = 0;
        result_[k].narrow_phase = false;
        result_[k].outputs.clear();
    }
    for (const std::size_t k : near_) {
        is_near_[k] = 1;
        result_[k].narrow_phase = true;
    }
}

bool CollisionPipeline::pairs_run_concurrently() const {
    if (detection_ != ContactDetection::bvh || opt_.pair_concurrency == PairConcurrency::never ||
        !opt_.narrow.parallel || tbb::this_task_arena::max_concurrency() < 2)
        return false;
    // a kernel's writes are read by the later pairs of its models (§14.4): pairs in order,
    // unless only writes read them (then the writes of all pairs run after the pairs, in order)
    if (any_pair_writes_models_ && !detail::model_writes_read_only_by_writes(params_)) return false;
    const bool always = opt_.pair_concurrency == PairConcurrency::always;
    std::size_t worth_a_task = 0, candidates = 0;
    for (const std::size_t k : near_) {
        if (always) {
            ++worth_a_task;
            continue;
        }
        const bool known = k < pair_work_.size() && pair_work_[k].model1 == pairs_[k].model1 &&
                           pair_work_[k].model2 == pairs_[k].model2;
        if (!known) continue;
        candidates += pair_work_[k].candidates;
        worth_a_task += pair_work_[k].candidates >= kMinCandidatesPerConcurrentPair ? 1 : 0;
    }
    if (always) return worth_a_task >= 2;
    return worth_a_task >= 2 && candidates >= std::max(kMinCandidatesForConcurrentPairs, moving_elements_);
}

void CollisionPipeline::record_pair_work(std::size_t k, std::size_t candidates) {
    pair_work_[k] = {pairs_[k].model1, pairs_[k].model2, candidates};
}

void CollisionPipeline::detect_pairs_in_order() {
    // A pair whose root boxes are not within the margin has no element boxes within it (each
    // element box lies in its root box, and the test is monotone in the bounds): no candidates
    // and no outputs, so the BVH detection neither traverses its trees nor looks its candidate
    // cache up (SOFA's BruteForceBroadPhase does not hand such a pair to the narrow phase at
    // all): it runs the pairs of near_. Exhaustive detection runs every pair.
    PairCounts counts;
    const auto run = [&](std::size_t k, PairCandidates* kept) {
        const std::size_t before = counts.candidates;
        detect_pair_with(pair_indices_[k][0], pair_indices_[k][1], result_[k].outputs, scratch_, counts, kept);
        record_pair_work(k, counts.candidates - before);
    };
    if (detection_ == ContactDetection::bvh) {
        pair_kept_.resize(pairs_.size());
        for (const std::size_t k : near_) {
            pair_kept_[k] = pair_candidates_entry(pair_indices_[k][0], pair_indices_[k][1]);
            run(k, pair_kept_[k]);
        }
    } else {
        for (std::size_t k = 0; k < pairs_.size(); ++k) run(k, nullptr);
    }
    counts.add_to(cache_stats_, candidates_evaluated_);
}

void CollisionPipeline::count_kept_keys() {
    for (const std::size_t k : near_) {
        const PairCandidates* kept = pair_kept_[k];
        if (kept == nullptr) continue;
        ModelMotion& a = motion_[pair_indices_[k][0]];
        ModelMotion& b = motion_[pair_indices_[k][1]];
        if (kept->generation1 != a.generation || kept->generation2 != b.generation) continue;
        for (ModelMotion* m : {&a, &b}) {
            m->kept_keys += kept->keys.size();
            m->overlapping_keys += kept->overlapped_last;
        }
    }
}

void CollisionPipeline::detect_pairs_concurrently() {
    // What the pairs would otherwise make or compute as they go, made first on this thread:
    // their candidate-cache entries (the map does not change while pairs run) and the
    // Triangle planes their separation tests read (a model's, shared by its pairs).
    // (bvh only: the pairs of near_, ascending)
    pair_kept_.resize(pairs_.size());
    for (const std::size_t k : near_) {
        CollisionModel& m1 = *pairs_[k].model1;
        CollisionModel& m2 = *pairs_[k].model2;
        pair_kept_[k] = pair_candidates_entry(pair_indices_[k][0], pair_indices_[k][1]);
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
    const std::size_t n = near_.size();
    const std::size_t chunks =
        std::min(n, kChunksPerThread * std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
    if (chunk_scratch_.size() < chunks) chunk_scratch_.resize(chunks);
    // Kernels that write the models (NewProximity Triangle–Triangle's normal overwrite), read by
    // writes alone (pairs_run_concurrently): each pair keeps its writes' candidates, run below
    // in pair order, as detect_pairs_in_order would have run them.
    const bool defer_writes = any_pair_writes_models_;
    if (defer_writes && deferred_writes_.size() < pairs_.size()) deferred_writes_.resize(pairs_.size());
    std::mutex merge;
    PairCounts total;
    FirstErrorInOrder failure;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, chunks, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t c = r.begin(); c != r.end(); ++c) {
                PairCounts counts;
                for (std::size_t p = c * n / chunks; p < (c + 1) * n / chunks; ++p) {
                    const std::size_t k = near_[p];
                    ModelPairDetection& d = result_[k];
                    try {
                        const std::size_t before = counts.candidates;
                        Keys* deferred = defer_writes ? &deferred_writes_[k] : nullptr;
                        if (deferred != nullptr) deferred->clear();
                        detect_pair_with(pair_indices_[k][0], pair_indices_[k][1], d.outputs, chunk_scratch_[c],
                                         counts, pair_kept_[k], deferred);
                        record_pair_work(k, counts.candidates - before);
                    } catch (...) {
                        failure.record(k);
                        break;
                    }
                }
                const std::lock_guard lock(merge);
                counts.add_to(total.cache, total.candidates);
            }
        },
        tbb::simple_partitioner());
    total.add_to(cache_stats_, candidates_evaluated_);
    if (defer_writes) {
        // the writes of the pairs before the first that failed (all of them if none did)
        for (const std::size_t k : near_) {
            if (k >= failure.first_index()) break;
            CollisionModel& m1 = *pairs_[k].model1;
            CollisionModel& m2 = *pairs_[k].model2;
            const detail::KernelParts kernel = detail::pair_kernel_parts(params_, m1, m2);
            if (kernel.writes != nullptr) run_kernel_writes(params_, m1, m2, kernel, deferred_writes_[k]);
        }
    }
    failure.rethrow_if_any();
}

bool CollisionPipeline::roots_within_margin(std::size_t i1, std::size_t i2) const {
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
