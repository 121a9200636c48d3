#include "penalty/collision/collision_pipeline.hpp"

#include "penalty/core/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include <algorithm>

namespace penalty {

namespace {

constexpr std::uint32_t kParallelTraversalMin = 4096;  // element count above which a node pair forks

using Keys = std::vector<std::uint64_t>;

std::uint64_t key(std::uint32_t e1, std::uint32_t e2) { return (std::uint64_t(e1) << 32) | e2; }

// Dual-tree traversal collecting the element pairs whose boxes pass the §3.8 test. Below
// kBruteForceBelow element pairs, a node pair is finished by testing all its element pairs
// (the same element box test, so the same pairs, with less recursion).
constexpr std::uint32_t kBruteForceBelow = 64;

struct Traversal {
    const Bvh& a;
    const Bvh& b;
    bool self;  // a and b are the same tree of the same model: keys (max, min), diagonal skipped
    double margin;
    bool parallel;
    tbb::enumerable_thread_specific<Keys>& buffers;

    void emit(Keys& out, std::uint32_t ea, std::uint32_t eb) const {
        if (self) out.push_back(ea > eb ? key(ea, eb) : key(eb, ea));
        else out.push_back(key(ea, eb));
    }

    void all_pairs(const BvhNode& na, const BvhNode& nb, Keys& out) const {
        const std::uint32_t* oa = a.order().data();
        const std::uint32_t* ob = b.order().data();
        const Aabb* ba = a.ordered_boxes().data();
        const Aabb* bb = b.ordered_boxes().data();
        for (std::uint32_t s = na.first; s < na.first + na.count; ++s) {
            const Aabb& boxa = ba[s];
            if (!boxa.overlaps(nb.box, margin)) continue;  // prunes only: nb.box contains bb[t]
            for (std::uint32_t t = nb.first; t < nb.first + nb.count; ++t)
                if (boxa.overlaps(bb[t], margin)) emit(out, oa[s], ob[t]);
        }
    }

    void pair(std::uint32_t ia, std::uint32_t ib, Keys* out) const {
        const BvhNode& na = a.nodes()[ia];
        const BvhNode& nb = b.nodes()[ib];
        if (!na.box.overlaps(nb.box, margin)) return;
        if ((na.leaf() && nb.leaf()) || std::uint64_t(na.count) * nb.count <= kBruteForceBelow) {
            all_pairs(na, nb, *out);
            return;
        }
        const bool fork = parallel && std::uint64_t(na.count) + nb.count >= kParallelTraversalMin;
        const bool split_a = !na.leaf() && (nb.leaf() || na.count >= nb.count);
        const std::uint32_t l = split_a ? ia + 1 : ib + 1;
        const std::uint32_t r = split_a ? na.right : nb.right;
        if (fork) {
            tbb::parallel_invoke([&] { split_a ? pair(l, ib, &buffers.local()) : pair(ia, l, &buffers.local()); },
                                 [&] { split_a ? pair(r, ib, &buffers.local()) : pair(ia, r, &buffers.local()); });
        } else if (split_a) {
            pair(l, ib, out);
            pair(r, ib, out);
        } else {
            pair(ia, l, out);
            pair(ia, r, out);
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

// NewProximity Triangle–Triangle with SOFA's normal overwrite writes the models (§14.4)
bool kernel_writes_models(const IntersectionParams& p, const CollisionModel& m1, const CollisionModel& m2) {
    return p.method == IntersectionMethod::NewProximity && m1.type() == ModelType::Triangle &&
           m2.type() == ModelType::Triangle && !p.quirks.fix_newproximity_triangle_triangle_normal_overwrite &&
           !(m1.params().both_side && m2.params().both_side);
}

}  // namespace

bool has_active_intersector(const IntersectionParams& params, ModelType a, ModelType b) {
    const PairSupport s = pair_support(params, a, b);
    return s == PairSupport::Supported || (s == PairSupport::BeyondSofa && params.enable_beyond_sofa_pairs);
}

double box_margin(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2) {
    return params.method == IntersectionMethod::Discrete
               ? params.alarm_distance
               : params.alarm_distance + m1.params().contact_distance + m2.params().contact_distance;
}

std::vector<ModelPair> brute_force_broad_phase(const IntersectionParams& params,
                                               const std::vector<CollisionModel*>& models,
                                               const std::vector<Aabb>* roots) {
    if (roots != nullptr && roots->size() != models.size()) {
        throw_invalid_argument("brute_force_broad_phase(): ", roots->size(), " root boxes for ", models.size(),
                               " models");
    }
    std::vector<ModelPair> pairs;
    std::vector<std::size_t> added;
    for (std::size_t i = 0; i < models.size(); ++i) {
        CollisionModel* m = models[i];
        if (m == nullptr) throw_invalid_argument("brute_force_broad_phase(): model ", i, " is null");
        if (!m->params().active || m->size() == 0) continue;
        if (keep_model_pair(*m, *m) && has_active_intersector(params, m->type(), m->type())) pairs.push_back({m, m});
        for (const std::size_t j : added) {
            CollisionModel* prev = models[j];
            if (!keep_model_pair(*m, *prev) || !has_active_intersector(params, m->type(), prev->type())) continue;
            const bool keep = is_registered_order(m->type(), prev->type());
            CollisionModel* m1 = keep ? m : prev;
            CollisionModel* m2 = keep ? prev : m;
            if (roots != nullptr && !(*roots)[i].overlaps((*roots)[j], box_margin(params, *m1, *m2))) continue;
            pairs.push_back({m1, m2});
        }
        added.push_back(i);
    }
    return pairs;
}

std::vector<std::uint64_t> bvh_candidates(const Bvh& t1, const Bvh& t2, bool same_model, double margin,
                                          bool parallel) {
    if (t1.empty() || t2.empty()) return {};
    tbb::enumerable_thread_specific<Keys> buffers;
    const Traversal tr{t1, t2, same_model, margin, parallel, buffers};
    if (same_model) tr.inside(0, &buffers.local());
    else tr.pair(0, 0, &buffers.local());
    std::size_t total = 0;
    for (const Keys& k : buffers) total += k.size();
    Keys keys;
    keys.reserve(total);
    for (const Keys& k : buffers) keys.insert(keys.end(), k.begin(), k.end());
    // keys are unique, so the sorted sequence does not depend on how the buffers were filled
    const std::size_t n1 = t1.element_boxes().size();
    if (keys.size() < n1 / 4 || keys.size() < 4096) {
        if (parallel) tbb::parallel_sort(keys.begin(), keys.end());
        else std::sort(keys.begin(), keys.end());
        return keys;
    }
    // many candidates: counting sort on elem1, then each (short) elem1 bucket sorted by elem2
    std::vector<std::size_t> start(n1 + 1, 0);
    for (const std::uint64_t k : keys) ++start[std::size_t(k >> 32) + 1];
    for (std::size_t i = 0; i < n1; ++i) start[i + 1] += start[i];
    Keys sorted(keys.size());
    {
        std::vector<std::size_t> pos(start.begin(), start.end() - 1);
        for (const std::uint64_t k : keys) sorted[pos[std::size_t(k >> 32)]++] = k;
    }
    auto sort_buckets = [&](std::size_t lo, std::size_t hi) {
        for (std::size_t e = lo; e < hi; ++e)
            if (start[e + 1] - start[e] > 1)
                std::sort(sorted.begin() + std::ptrdiff_t(start[e]), sorted.begin() + std::ptrdiff_t(start[e + 1]));
    };
    if (parallel) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n1, 4096),
                          [&](const tbb::blocked_range<std::size_t>& r) { sort_buckets(r.begin(), r.end()); });
    } else {
        sort_buckets(0, n1);
    }
    return sorted;
}

DetectionOutputList bvh_narrow_phase(const IntersectionParams& params, CollisionModel& m1, const Bvh& t1,
                                     CollisionModel& m2, const Bvh& t2, const NarrowPhaseOptions& opt) {
    const bool same_model = &m1 == &m2;
    if (t1.element_boxes().size() != m1.size() || t2.element_boxes().size() != m2.size()) {
        throw_invalid_argument("bvh_narrow_phase(): the trees of '", m1.name(), "' and '", m2.name(),
                               "' are out of date (model sizes changed)");
    }
    const Keys keys = bvh_candidates(t1, t2, same_model, box_margin(params, m1, m2), opt.parallel);
    const bool node = same_node(m1, m2);
    auto run = [&](std::size_t begin, std::size_t end, DetectionOutputList& out) {
        for (std::size_t k = begin; k < end; ++k) {
            const auto e1 = Index(keys[k] >> 32);
            const auto e2 = Index(keys[k] & 0xffffffffu);
            if (node && !elements_may_collide(m1, e1, m2, e2)) continue;
            intersect_elements(params, m1, e1, m2, e2, out);
        }
    };
    DetectionOutputList outputs;
    if (!opt.parallel || kernel_writes_models(params, m1, m2) || keys.size() <= opt.chunk_size) {
        run(0, keys.size(), outputs);
        return outputs;
    }
    const std::size_t chunk = std::max<std::size_t>(1, opt.chunk_size);
    const std::size_t nchunks = (keys.size() + chunk - 1) / chunk;
    std::vector<DetectionOutputList> parts(nchunks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nchunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c)
            run(c * chunk, std::min(keys.size(), (c + 1) * chunk), parts[c]);
    });
    std::size_t total = 0;
    for (const auto& p : parts) total += p.size();
    outputs.reserve(total);
    for (auto& p : parts) outputs.insert(outputs.end(), p.begin(), p.end());
    return outputs;
}

CollisionPipeline::CollisionPipeline(IntersectionParams params, CollisionPipelineOptions opt)
    : params_(std::move(params)), opt_(opt) {
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
}

SceneDetection CollisionPipeline::detect() {
    std::vector<Aabb> roots(models_.size());
    for (std::size_t i = 0; i < models_.size(); ++i) {
        CollisionModel& m = *models_[i];
        if (!m.params().active) continue;
        Bvh& tree = trees_[i];
        if (m.params().moving) {
            m.validate();
            tree.refit(m, opt_.rebuild_ratio, opt_.leaf_size);
        } else if (tree.build_count() == 0 || tree.element_boxes().size() != m.size()) {
            m.validate();  // static: checked and built once (SOFA: bounding tree computed once)
            tree.build(m, opt_.leaf_size);
        }
        if (!tree.empty()) roots[i] = tree.root_box();
    }
    auto tree_of = [&](const CollisionModel* m) -> const Bvh& {
        for (std::size_t i = 0; i < models_.size(); ++i)
            if (models_[i] == m) return trees_[i];
        throw_invalid_argument("CollisionPipeline: unknown model");
    };
    SceneDetection result;
    for (const ModelPair& p : brute_force_broad_phase(params_, models_, &roots)) {
        p.model1->update();
        if (p.model2 != p.model1) p.model2->update();
        DetectionOutputList out = bvh_narrow_phase(params_, *p.model1, tree_of(p.model1), *p.model2,
                                                   tree_of(p.model2), opt_.narrow);
        if (!out.empty()) result.push_back({p.model1, p.model2, std::move(out)});
    }
    return result;
}

SceneDetection detect_scene_exhaustive(const IntersectionParams& params, const std::vector<CollisionModel*>& models) {
    SceneDetection result;
    for (const ModelPair& p : brute_force_broad_phase(params, models)) {
        ModelPairDetection d = detect_model_pair(params, *p.model1, *p.model2);
        if (!d.outputs.empty()) result.push_back({d.model1, d.model2, std::move(d.outputs)});
    }
    return result;
}

}  // namespace penalty
