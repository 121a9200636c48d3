// The BVH narrow phase of a model pair: its candidates evaluated by the pair's kernel, the
// filters that evaluate fewer (contact outputs only), bvh_narrow_phase.
#include "narrow_phase.hpp"
#include "penalty/core/pair_key.hpp"

#include "kernels.hpp"
#include "kernels/prefetch.hpp"
#include "penalty/collision/separation.hpp"
#include "penalty/core/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty {

NarrowPhaseScratch::NarrowPhaseScratch() : buffers_(std::make_unique<Buffers>()) {}
NarrowPhaseScratch::~NarrowPhaseScratch() = default;
NarrowPhaseScratch::NarrowPhaseScratch(NarrowPhaseScratch&&) noexcept = default;
NarrowPhaseScratch& NarrowPhaseScratch::operator=(NarrowPhaseScratch&&) noexcept = default;

namespace detail {

bool kernel_writes_models(const IntersectionParams& p, const CollisionModel& m1, const CollisionModel& m2) {
    return np_triangle_triangle_writes_normals(p, m1, m2);
}

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
        ctx.e1 = Index(pair_key::first(key));
        ctx.e2 = Index(pair_key::second(key));
        if (node && !elements_may_collide(m1, ctx.e1, m2, ctx.e2)) continue;
        kernel.writes(ctx);
    }
}

// Intersects the candidates `all_keys` (PairKey(element 1, element 2).bits()) of m1 × m2 in their
// order: the kernel's filter first, if it has one (KernelParts::filter: drops candidates that
// give no output), then its writes to the models, over all candidates in order, then its reads,
// in parallel chunks concatenated in chunk order (the outputs of the sequential loop).
// separation_tests: the kernels run their early outs (separation.hpp) on every candidate.
// deferred_writes: if not null, the kernel's writes are not run but their candidates appended
// to it, in the order they would have run in (run_kernel_writes runs them later).
void evaluate_candidates(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2, const Keys& all_keys,
                         const NarrowPhaseOptions& opt, NarrowPhaseScratch::Buffers& b, DetectionOutputList& out,
                         bool separation_tests, Keys* deferred_writes) {
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
                detail::prefetch::object(row1.base + row1.stride * pair_key::first(ahead), row1.stride);
                detail::prefetch::object(row2.base + row2.stride * pair_key::second(ahead), row2.stride);
            }
            ctx.e1 = Index(pair_key::first(keys[k]));
            ctx.e2 = Index(pair_key::second(keys[k]));
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
                const double d2 = reach_of(boxes1[pair_key::first(keys[k])], q);
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
                const std::size_t e2 = pair_key::second(key);
                const double d2 = reach_of(boxes1[pair_key::first(key)], point_of(Index(e2)));
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
        evaluate_candidates(params, m1, m2, b.nearest_keys, serial, b, b.nearest_outputs, separation_tests,
                            deferred_writes);
        for (const DetectionOutput& o : b.nearest_outputs) {
            const Vec3& q = point_of(o.elem2.value());
            const double length = (q - o.point[0]).norm();
            const double scale =
                1.0 + q.cwiseAbs().maxCoeff() + o.point[0].cwiseAbs().maxCoeff() + length + std::abs(o.value);
            const double reach = length + 1e-10 * scale;
            b.bound[o.elem2.slot()] = std::min(b.bound[o.elem2.slot()], reach * reach);
        }
    });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < n; ++k)
        if (b.reach[k] <= b.bound[pair_key::second(keys[k])]) keys[kept++] = keys[k];
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
        b.bound[out[i].elem2.slot()] = std::min(b.bound[out[i].elem2.slot()], out[i].value);
    }
    std::size_t kept = from;
    for (std::size_t i = from; i < out.size(); ++i)
        if (out[i].value <= b.bound[out[i].elem2.slot()]) {
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
// bvh_narrow_phase with the sizes of the models' longest element boxes (longest_box_side) given
// by the caller: they decide the pair's separation tests and the traversal's row mode
// contact_outputs_only: keep_nearest_candidates for a kernel of outputs_nearest_to_element2.
void narrow_phase_on_trees(const IntersectionParams& params, CollisionModel& m1, const Bvh& t1, CollisionModel& m2,
                           const Bvh& t2, const NarrowPhaseOptions& opt, NarrowPhaseScratch& scratch,
                           DetectionOutputList& out, double side1, double side2, bool contact_outputs_only,
                           Keys* deferred_writes) {
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
    if (nearest)
        keep_nearest_candidates(params, m1, t1.element_boxes().data(), m2, b.keys, b, separation_tests,
                                deferred_writes);
    const std::size_t from = out.size();
    if (nearest) out.reserve(from + candidates);
    evaluate_candidates(params, m1, m2, b.keys, opt, b, out, separation_tests, deferred_writes);
    if (nearest) keep_least_outputs(out, from, m2.size(), b);
}

}  // namespace detail

void bvh_narrow_phase(const IntersectionParams& params, CollisionModel& m1, const Bvh& t1, CollisionModel& m2,
                      const Bvh& t2, const NarrowPhaseOptions& opt, NarrowPhaseScratch& scratch,
                      DetectionOutputList& out) {
    detail::narrow_phase_on_trees(params, m1, t1, m2, t2, opt, scratch, out, detail::longest_box_side(m1, t1),
                                  detail::longest_box_side(m2, t2));
}

}  // namespace penalty
