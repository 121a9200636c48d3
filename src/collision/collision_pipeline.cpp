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

// Dual-tree traversal collecting the element pairs whose boxes pass the §3.8 test.
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

    void leaf_pair(const BvhNode& na, const BvhNode& nb) const {
        Keys& out = buffers.local();
        const auto& oa = a.order();
        const auto& ob = b.order();
        const auto& ba = a.element_boxes();
        const auto& bb = b.element_boxes();
        for (std::uint32_t s = na.first; s < na.first + na.count; ++s) {
            const std::uint32_t ea = oa[s];
            const Aabb& boxa = ba[ea];
            for (std::uint32_t t = nb.first; t < nb.first + nb.count; ++t) {
                const std::uint32_t eb = ob[t];
                if (boxa.overlaps(bb[eb], margin)) emit(out, ea, eb);
            }
        }
    }

    void pair(std::uint32_t ia, std::uint32_t ib) const {
        const BvhNode& na = a.nodes()[ia];
        const BvhNode& nb = b.nodes()[ib];
        if (!na.box.overlaps(nb.box, margin)) return;
        if (na.leaf() && nb.leaf()) {
            leaf_pair(na, nb);
            return;
        }
        const bool fork = parallel && na.count + nb.count >= kParallelTraversalMin;
        if (!na.leaf() && (nb.leaf() || na.count >= nb.count)) {
            const std::uint32_t l = ia + 1, r = na.right;
            if (fork) tbb::parallel_invoke([&] { pair(l, ib); }, [&] { pair(r, ib); });
            else {
                pair(l, ib);
                pair(r, ib);
            }
        } else {
            const std::uint32_t l = ib + 1, r = nb.right;
            if (fork) tbb::parallel_invoke([&] { pair(ia, l); }, [&] { pair(ia, r); });
            else {
                pair(ia, l);
                pair(ia, r);
            }
        }
    }

    // all pairs inside the subtree of node i (self traversal only)
    void inside(std::uint32_t i) const {
        const BvhNode& n = a.nodes()[i];
        if (n.leaf()) {
            Keys& out = buffers.local();
            const auto& o = a.order();
            const auto& boxes = a.element_boxes();
            for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
                for (std::uint32_t t = s + 1; t < n.first + n.count; ++t)
                    if (boxes[o[s]].overlaps(boxes[o[t]], margin)) emit(out, o[s], o[t]);
            return;
        }
        const std::uint32_t l = i + 1, r = n.right;
        if (parallel && n.count >= kParallelTraversalMin) {
            tbb::parallel_invoke([&] { inside(l); }, [&] { inside(r); }, [&] { pair(l, r); });
        } else {
            inside(l);
            inside(r);
            pair(l, r);
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
    if (same_model) tr.inside(0);
    else tr.pair(0, 0);
    std::size_t total = 0;
    for (const Keys& k : buffers) total += k.size();
    Keys keys;
    keys.reserve(total);
    for (const Keys& k : buffers) keys.insert(keys.end(), k.begin(), k.end());
    // keys are unique, so the sorted sequence does not depend on how the buffers were filled
    if (parallel) tbb::parallel_sort(keys.begin(), keys.end());
    else std::sort(keys.begin(), keys.end());
    return keys;
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
