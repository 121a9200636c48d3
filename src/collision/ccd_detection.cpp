// ContinuousDetection::detect: surfaces paired by a sweep over their swept boxes, the features of
// each pair from their trees (bvh_candidates), the exact tests of geometry/ccd.hpp (ccd_detection.hpp).
#include "ccd_surfaces.hpp"
#include "penalty/core/pair_key.hpp"

#include "penalty/core/error.hpp"
#include "penalty/geometry/segment_segment.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <tuple>

namespace penalty {

using namespace detail;

const char* crossing_kind_name(CrossingKind kind) {
    switch (kind) {
        case CrossingKind::point_triangle:
            return "point-triangle";
        case CrossingKind::edge_edge:
            return "edge-edge";
        case CrossingKind::sphere_triangle:
            return "sphere-triangle";
        case CrossingKind::sphere_sphere:
            return "sphere-sphere";
    }
    return "?";
}

std::string Crossing::describe() const {
    const auto name = [](const CollisionModel* m) { return m ? "'" + m->name() + "'" : std::string("?"); };
    std::string first, second;
    switch (kind) {
        case CrossingKind::point_triangle:
            first = "vertex " + std::to_string(dofs1[0]) + " of " + name(model1);
            second = "triangle " + std::to_string(element2) + " of " + name(model2);
            break;
        case CrossingKind::edge_edge:
            first = "edge (" + std::to_string(dofs1[0]) + ", " + std::to_string(dofs1[1]) + ") of " + name(model1);
            second = "edge (" + std::to_string(dofs2[0]) + ", " + std::to_string(dofs2[1]) + ") of " + name(model2);
            break;
        case CrossingKind::sphere_triangle:
            first = "sphere " + std::to_string(element1) + " of " + name(model1);
            second = "triangle " + std::to_string(element2) + " of " + name(model2);
            break;
        case CrossingKind::sphere_sphere:
            first = "sphere " + std::to_string(element1) + " of " + name(model1);
            second = "sphere " + std::to_string(element2) + " of " + name(model2);
            break;
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, " at %.3g of the step, %.3g m beyond", toi, depth);
    return first + (kind == CrossingKind::sphere_sphere ? " into " : " through ") + second + buf;
}

namespace {

/// The tasks of a surface pair (a ≤ b) from its test bits.
template <class Add>
void tasks_of(std::size_t a, std::size_t b, std::uint32_t bits, const Add& add) {
    const bool self = a == b;
    if (bits & kVertexTriangleAB) add(a, b, kVertexFeature, kTriangleFeature, CrossingKind::point_triangle);
    if (!self && (bits & kVertexTriangleBA)) add(b, a, kVertexFeature, kTriangleFeature, CrossingKind::point_triangle);
    if (bits & kEdgeEdge) add(a, b, kEdgeFeature, kEdgeFeature, CrossingKind::edge_edge);
    if (bits & kSphereTriangleAB) add(a, b, kSphereFeature, kTriangleFeature, CrossingKind::sphere_triangle);
    if (!self && (bits & kSphereTriangleBA)) add(b, a, kSphereFeature, kTriangleFeature, CrossingKind::sphere_triangle);
    if (bits & kSphereSphere) add(a, b, kSphereFeature, kSphereFeature, CrossingKind::sphere_sphere);
}

bool shares_dof(std::span<const Index> a, std::span<const Index> b) {
    for (Index x : a)
        for (Index y : b)
            if (x == y) return true;
    return false;
}

Vec3 lerp(const Vec3& a, const Vec3& b, double t) { return a + t * (b - a); }

}  // namespace

namespace detail {

/// Tests one candidate pair (features e1 of the task's first surface, e2 of its second); appends
/// a crossing to `out` when they met.
void test_candidate(const ContinuousDetection::Task& task, const ContinuousDetection::Surface& s1,
                    const ContinuousDetection::Surface& s2, std::uint32_t e1, std::uint32_t e2, const CcdOptions& o,
                    std::vector<Crossing>& out, std::size_t& capped) {
    const bool self = task.first == task.second;
    Crossing c;
    c.kind = task.crossing;
    c.surface1 = task.first;
    c.surface2 = task.second;
    CcdResult r;
    switch (task.kind1 * kFeatureKinds + task.kind2) {
        case kVertexFeature* kFeatureKinds + kTriangleFeature: {
            const Index p = s1.vertices[e1];
            const auto& t = s2.triangles[e2];
            if (self && (p == t[0] || p == t[1] || p == t[2])) return;
            r = point_triangle_ccd(s1.then(p), s2.then(t[0]), s2.then(t[1]), s2.then(t[2]), s1.now(p), s2.now(t[0]),
                                   s2.now(t[1]), s2.now(t[2]), o);
            if (!r.hit) return;
            c.model1 = s1.vertex_model[e1];
            c.model2 = s2.triangle_model[e2];
            c.dofs1 = {p, -1, -1};
            c.dofs2 = t;
            c.element2 = s2.triangle_element[e2];
            c.point = lerp(s1.then(p), s1.now(p), r.toi);
            c.depth = point_triangle_distance(s1.now(p), s2.now(t[0]), s2.now(t[1]), s2.now(t[2]));
            break;
        }
        case kEdgeFeature* kFeatureKinds + kEdgeFeature: {
            const auto& a = s1.edges[e1];
            const auto& b = s2.edges[e2];
            if (self && shares_dof(a, b)) return;
            r = edge_edge_ccd(s1.then(a[0]), s1.then(a[1]), s2.then(b[0]), s2.then(b[1]), s1.now(a[0]), s1.now(a[1]),
                              s2.now(b[0]), s2.now(b[1]), o);
            if (!r.hit) return;
            c.model1 = s1.edge_model[e1];
            c.model2 = s2.edge_model[e2];
            c.dofs1 = {a[0], a[1], -1};
            c.dofs2 = {b[0], b[1], -1};
            const SegmentSegmentResult at = segment_segment_closest_points(
                lerp(s1.then(a[0]), s1.now(a[0]), r.toi), lerp(s1.then(a[1]), s1.now(a[1]), r.toi),
                lerp(s2.then(b[0]), s2.now(b[0]), r.toi), lerp(s2.then(b[1]), s2.now(b[1]), r.toi));
            c.point = at.p;
            c.depth = edge_edge_distance(s1.now(a[0]), s1.now(a[1]), s2.now(b[0]), s2.now(b[1]));
            break;
        }
        case kSphereFeature* kFeatureKinds + kTriangleFeature: {
            const Index p = s1.sphere_dof[e1];
            const auto& t = s2.triangles[e2];
            if (self && s1.vec3 != nullptr && (p == t[0] || p == t[1] || p == t[2])) return;
            r = point_triangle_ccd(s1.then(p), s2.then(t[0]), s2.then(t[1]), s2.then(t[2]), s1.now(p), s2.now(t[0]),
                                   s2.now(t[1]), s2.now(t[2]), o);
            if (!r.hit) return;
            c.model1 = s1.sphere_model[e1];
            c.model2 = s2.triangle_model[e2];
            c.dofs1 = {p, -1, -1};
            c.dofs2 = t;
            c.element1 = s1.sphere_element[e1];
            c.element2 = s2.triangle_element[e2];
            c.point = lerp(s1.then(p), s1.now(p), r.toi);
            c.depth = point_triangle_distance(s1.now(p), s2.now(t[0]), s2.now(t[1]), s2.now(t[2]));
            break;
        }
        default: {  // sphere–sphere
            const Index p = s1.sphere_dof[e1];
            const double r1 = s1.sphere_radius[e1];
            const Index q = s2.sphere_dof[e2];
            const double r2 = s2.sphere_radius[e2];
            if (self && p == q) return;
            r = sphere_sphere_ccd(s1.then(p), s2.then(q), s1.now(p), s2.now(q), r1, r2);
            if (!r.hit) return;
            c.model1 = s1.sphere_model[e1];
            c.model2 = s2.sphere_model[e2];
            c.dofs1 = {p, -1, -1};
            c.dofs2 = {q, -1, -1};
            c.element1 = s1.sphere_element[e1];
            c.element2 = s2.sphere_element[e2];
            c.point = lerp(s1.then(p), s1.now(p), r.toi);
            c.depth = std::max(0.0, std::max(r1, r2) - (s2.now(q) - s1.now(p)).norm());
            break;
        }
    }
    c.toi = r.toi;
    if (r.capped) ++capped;
    out.push_back(c);
}

}  // namespace detail

namespace {

/// Calls f(s) for every slot s of `tree`'s order whose box overlaps `box`.
template <class F>
void query_tree(const Bvh& tree, const Aabb& box, const F& f) {
    const std::vector<BvhNode>& nodes = tree.nodes();
    const std::vector<Aabb>& ordered = tree.ordered_boxes();
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const BvhNode& n = nodes[stack[--top]];
        if (!n.box.overlaps(box)) continue;
        if (n.leaf()) {
            for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
                if (ordered[s].overlaps(box)) f(s);
            continue;
        }
        const std::uint32_t left = std::uint32_t(&n - nodes.data()) + 1;
        if (top + 2 > 64) {  // deeper than any tree of < 2^32 elements: cannot happen, but stay safe
            for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
                if (ordered[s].overlaps(box)) f(s);
            continue;
        }
        stack[top++] = n.right;
        stack[top++] = left;
    }
}

}  // namespace

void ContinuousDetection::candidates(const Task& task, bool parallel, std::vector<std::uint64_t>& keys) const {
    // keys (PairKey(e1, e2).bits()) of the features whose swept boxes overlap: the trees' dual traversal
    // when both kinds have one, else every box of the list against the other's tree (or list)
    const Surface& s1 = *surfaces_[task.first];
    const Surface& s2 = *surfaces_[task.second];
    const auto k1 = std::size_t(task.kind1), k2 = std::size_t(task.kind2);
    const bool same = task.first == task.second && task.kind1 == task.kind2;
    keys.clear();
    if (s1.has_tree(task.kind1) && s2.has_tree(task.kind2)) {
        keys = bvh_candidates(s1.trees[k1], s2.trees[k2], same, 0.0, parallel);
        return;
    }
    const std::vector<Aabb>& b1 = s1.boxes[k1].boxes;
    const std::vector<Aabb>& b2 = s2.boxes[k2].boxes;
    const auto key = [](std::size_t e1, std::size_t e2) { return pair_key::make(e1, e2); };
    if (same) {  // one small list against itself: e1 > e2
        for (std::size_t i = 0; i < b1.size(); ++i)
            for (std::size_t j = 0; j < i; ++j)
                if (b1[i].overlaps(b2[j])) keys.push_back(key(i, j));
        return;
    }
    if (!s1.has_tree(task.kind1) && !s2.has_tree(task.kind2)) {
        // two small lists: every pair of boxes, the first's pruned by the second's union
        for (std::size_t i = 0; i < b1.size(); ++i) {
            if (!b1[i].overlaps(s2.kind_box[k2])) continue;
            for (std::size_t j = 0; j < b2.size(); ++j)
                if (b1[i].overlaps(b2[j])) keys.push_back(key(i, j));
        }
        return;  // already ascending
    }
    if (s1.has_tree(task.kind1)) {  // the first has a tree, the second is a list
        const Bvh& tree = s1.trees[k1];
        for (std::size_t j = 0; j < b2.size(); ++j)
            query_tree(tree, b2[j], [&](std::uint32_t slot) { keys.push_back(key(tree.order()[slot], j)); });
    } else {  // the second has a tree, the first is a list
        const Bvh& tree = s2.trees[k2];
        for (std::size_t i = 0; i < b1.size(); ++i)
            query_tree(tree, b1[i], [&](std::uint32_t slot) { keys.push_back(key(i, tree.order()[slot])); });
    }
    std::sort(keys.begin(), keys.end());
}

void ContinuousDetection::find_tasks() {
    // surfaces whose swept boxes overlap: a sweep along x over their boxes, then the pairs' tests
    tasks_.clear();
    near_.clear();
    sweep_.resize(surfaces_.size());
    for (std::size_t i = 0; i < surfaces_.size(); ++i) sweep_[i] = i;
    sweep_.erase(
        std::remove_if(sweep_.begin(), sweep_.end(), [&](std::size_t i) { return surfaces_[i]->swept_box.empty(); }),
        sweep_.end());
    std::sort(sweep_.begin(), sweep_.end(), [&](std::size_t a, std::size_t b) {
        const double xa = surfaces_[a]->swept_box.min.x(), xb = surfaces_[b]->swept_box.min.x();
        return xa < xb || (xa == xb && a < b);
    });
    for (std::size_t u = 0; u < sweep_.size(); ++u) {
        const std::size_t a = sweep_[u];
        const Aabb& ba = surfaces_[a]->swept_box;
        near_.push_back(PairKey(std::uint32_t(a), std::uint32_t(a)));  // itself (self-collision, if kept)
        for (std::size_t w = u + 1; w < sweep_.size() && surfaces_[sweep_[w]]->swept_box.min.x() <= ba.max.x(); ++w) {
            const std::size_t b = sweep_[w];
            if (!ba.overlaps(surfaces_[b]->swept_box)) continue;
            near_.push_back(PairKey::unordered(std::uint32_t(a), std::uint32_t(b)));
        }
    }
    std::sort(near_.begin(), near_.end());
    for (const PairKey key : near_) {
        const auto it =
            std::lower_bound(pair_tests_.begin(), pair_tests_.end(), std::pair<PairKey, std::uint32_t>{key, 0u});
        if (it == pair_tests_.end() || it->first != key) continue;
        const std::size_t a = key.first(), b = key.second();
        ++stats_.surface_pairs;
        tasks_of(a, b, it->second, [&](std::size_t first, std::size_t second, int k1, int k2, CrossingKind kind) {
            const Surface& s1 = *surfaces_[first];
            const Surface& s2 = *surfaces_[second];
            if (s1.feature_count(k1) == 0 || s2.feature_count(k2) == 0) return;
            if (!s1.kind_box[std::size_t(k1)].overlaps(s2.kind_box[std::size_t(k2)])) return;
            tasks_.push_back(Task{first, second, k1, k2, kind});
        });
    }
}

const std::vector<Crossing>& ContinuousDetection::detect(const CcdOptions& options) {
    if (!started_) throw std::logic_error("ContinuousDetection::detect: no start recorded (record_start)");
    for (const auto& s : surfaces_)
        if (s->state_size() != s->recorded_size)
            throw std::logic_error("ContinuousDetection::detect: the state of '" + s->name +
                                   "' changed size since record_start");
    stats_ = ContinuousDetectionStats{};
    stats_.surfaces = surfaces_.size();
    tbb::parallel_for(std::size_t(0), surfaces_.size(), [&](std::size_t i) { surfaces_[i]->update_trees(); });

    find_tasks();
    task_crossings_.resize(std::max(task_crossings_.size(), tasks_.size()));
    task_keys_.resize(std::max(task_keys_.size(), tasks_.size()));
    task_candidates_.assign(tasks_.size(), 0);
    std::vector<std::size_t> capped(tasks_.size(), 0);
    const bool inner_parallel = tasks_.size() < 4;
    tbb::parallel_for(std::size_t(0), tasks_.size(), [&](std::size_t k) {
        const Task& task = tasks_[k];
        const Surface& s1 = *surfaces_[task.first];
        const Surface& s2 = *surfaces_[task.second];
        std::vector<Crossing>& out = task_crossings_[k];
        out.clear();
        std::vector<std::uint64_t>& keys = task_keys_[k];
        candidates(task, inner_parallel, keys);
        task_candidates_[k] = keys.size();
        for (std::uint64_t key : keys)
            test_candidate(task, s1, s2, pair_key::first(key), pair_key::second(key), options, out, capped[k]);
        // a feature through several elements of the other surface at once (a vertex through a
        // shared edge, an edge through a vertex) is one crossing: its earliest
        std::stable_sort(out.begin(), out.end(), [](const Crossing& x, const Crossing& y) {
            return std::tie(x.dofs1, x.element1, x.toi) < std::tie(y.dofs1, y.element1, y.toi);
        });
        out.erase(std::unique(out.begin(), out.end(),
                              [](const Crossing& x, const Crossing& y) {
                                  return x.dofs1 == y.dofs1 && x.element1 == y.element1;
                              }),
                  out.end());
    });
    crossings_.clear();
    for (std::size_t k = 0; k < tasks_.size(); ++k) {
        crossings_.insert(crossings_.end(), task_crossings_[k].begin(), task_crossings_[k].end());
        stats_.candidates += task_candidates_[k];
        stats_.capped += capped[k];
    }
    std::stable_sort(crossings_.begin(), crossings_.end(),
                     [](const Crossing& x, const Crossing& y) { return x.toi < y.toi; });
    return crossings_;
}

}  // namespace penalty
