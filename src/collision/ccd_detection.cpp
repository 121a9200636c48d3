// ContinuousDetection::detect: surfaces paired by a sweep over their swept boxes, the features of
// each pair from their trees (bvh_candidates), the exact tests of geometry/ccd.hpp (ccd_detection.hpp).
#include "ccd_surfaces.hpp"

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
        case CrossingKind::point_triangle: return "point-triangle";
        case CrossingKind::edge_edge: return "edge-edge";
        case CrossingKind::sphere_triangle: return "sphere-triangle";
        case CrossingKind::sphere_sphere: return "sphere-sphere";
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
        case kVertexFeature * kFeatureKinds + kTriangleFeature: {
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
        case kEdgeFeature * kFeatureKinds + kEdgeFeature: {
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
        case kSphereFeature * kFeatureKinds + kTriangleFeature: {
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

const std::vector<Crossing>& ContinuousDetection::detect(const CcdOptions& options) {
    if (!started_) throw std::logic_error("ContinuousDetection::detect: no start recorded (record_start)");
    for (const auto& s : surfaces_)
        if (s->state_size() != s->recorded_size)
            throw std::logic_error("ContinuousDetection::detect: the state of '" + s->name +
                                   "' changed size since record_start");
    stats_ = ContinuousDetectionStats{};
    stats_.surfaces = surfaces_.size();
    tbb::parallel_for(std::size_t(0), surfaces_.size(), [&](std::size_t i) { surfaces_[i]->update_trees(); });

    // surface pairs whose swept boxes overlap: the listed pairs, tested in their (sorted) order
    tasks_.clear();
    for (const auto& [key, bits] : pair_tests_) {
        const std::size_t a = std::size_t(key >> 32), b = std::size_t(key & 0xffffffffu);
        const Surface& sa = *surfaces_[a];
        const Surface& sb = *surfaces_[b];
        if (sa.swept_box.empty() || sb.swept_box.empty() || !sa.swept_box.overlaps(sb.swept_box)) continue;
        ++stats_.surface_pairs;
        tasks_of(a, b, bits, [&](std::size_t first, std::size_t second, int k1, int k2, CrossingKind kind) {
            if (surfaces_[first]->feature_count(k1) == 0 || surfaces_[second]->feature_count(k2) == 0) return;
            tasks_.push_back(Task{first, second, k1, k2, kind});
        });
    }
    task_crossings_.resize(std::max(task_crossings_.size(), tasks_.size()));
    task_candidates_.assign(tasks_.size(), 0);
    std::vector<std::size_t> capped(tasks_.size(), 0);
    const bool inner_parallel = tasks_.size() < 4;
    tbb::parallel_for(std::size_t(0), tasks_.size(), [&](std::size_t k) {
        const Task& task = tasks_[k];
        const Surface& s1 = *surfaces_[task.first];
        const Surface& s2 = *surfaces_[task.second];
        std::vector<Crossing>& out = task_crossings_[k];
        out.clear();
        const bool same_tree = task.first == task.second && task.kind1 == task.kind2;
        const std::vector<std::uint64_t> keys = bvh_candidates(s1.trees[std::size_t(task.kind1)], s2.trees[std::size_t(task.kind2)],
                                                               same_tree, 0.0, inner_parallel);
        task_candidates_[k] = keys.size();
        for (std::uint64_t key : keys)
            test_candidate(task, s1, s2, std::uint32_t(key >> 32), std::uint32_t(key), options, out, capped[k]);
        // a feature through several elements of the other surface at once (a vertex through a
        // shared edge, an edge through a vertex) is one crossing: its earliest
        std::stable_sort(out.begin(), out.end(), [](const Crossing& x, const Crossing& y) {
            return std::tie(x.dofs1, x.element1, x.toi) < std::tie(y.dofs1, y.element1, y.toi);
        });
        out.erase(std::unique(out.begin(), out.end(),
                              [](const Crossing& x, const Crossing& y) { return x.dofs1 == y.dofs1 && x.element1 == y.element1; }),
                  out.end());
    });
    crossings_.clear();
    for (std::size_t k = 0; k < tasks_.size(); ++k) {
        crossings_.insert(crossings_.end(), task_crossings_[k].begin(), task_crossings_[k].end());
        stats_.candidates += task_candidates_[k];
        stats_.capped += capped[k];
    }
    std::stable_sort(crossings_.begin(), crossings_.end(), [](const Crossing& x, const Crossing& y) { return x.toi < y.toi; });
    return crossings_;
}

}  // namespace penalty
