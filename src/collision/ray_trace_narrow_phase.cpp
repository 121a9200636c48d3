// SOFA's RayTraceNarrowPhase (RayTraceNarrowPhase::addCollisionPair, findPairsVolume) and the
// per-step data of TriangleOctreeCollisionModel (computeBoundingTree), re-implemented.
#include "penalty/collision/ray_trace_narrow_phase.hpp"
#include "mechanics/sofa_vector_ops.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty {

namespace {

using sofa_vec::dot3;

/// SOFA's Vec::normalize: divided by its norm when the norm exceeds machine epsilon, else kept.
void normalize_like_sofa(Vec3& v) {
    const double norm = std::sqrt(v.x() * v.x() + v.y() * v.y() + v.z() * v.z());
    if (norm > std::numeric_limits<double>::epsilon()) v /= norm;
}

/// (p1 − p0) × (p2 − p0), normalised as SOFA does.
Vec3 triangle_normal(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const Vec3 a = p1 - p0;
    const Vec3 b = p2 - p0;
    Vec3 n(a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(), a.x() * b.y() - a.y() * b.x());
    normalize_like_sofa(n);
    return n;
}

}  // namespace

OctreeSurface* RayTraceNarrowPhase::find(const CollisionModel& model) {
    for (auto& s : surfaces_)
        if (s->model == &model) return s.get();
    return nullptr;
}

const OctreeSurface* RayTraceNarrowPhase::find(const CollisionModel& model) const {
    return const_cast<RayTraceNarrowPhase*>(this)->find(model);
}

void RayTraceNarrowPhase::add_surface(TriangleModel& model) {
    if (find(model) != nullptr) return;
    auto s = std::make_unique<OctreeSurface>();
    s->model = &model;
    s->normals.resize(model.size());
    for (std::size_t i = 0; i < model.size(); ++i) s->triangles.push_back(model.triangle(Index(i)));
    for (std::size_t i = 0; i < model.size(); ++i)
        s->normals[i] = triangle_normal(model.p(Index(i), 0), model.p(Index(i), 1), model.p(Index(i), 2));
    surfaces_.push_back(std::move(s));
}

void RayTraceNarrowPhase::update_surface(OctreeSurface& s) {
    const TriangleModel& m = *s.model;
    s.octree.clear();
    if (s.computed && !m.params().moving) return;  // SOFA: an immobile model keeps its box and normals
    const auto& x = m.state().position;
    s.computed = true;
    if (x.empty()) return;
    s.normals.resize(m.size(), Vec3::Zero());
    s.vertex_normals.assign(x.size(), Vec3::Zero());
    s.box = Aabb{};
    s.box.extend(x[0]);
    // triangle 0 is left out (SOFA's loop starts at 1); each vertex normal sums the normals as
    // they were before this update
    for (std::size_t i = 1; i < m.size(); ++i) {
        const Triangle& t = m.triangle(Index(i));
        for (int k = 0; k < 3; ++k) s.vertex_normals[std::size_t(t[std::size_t(k)])] += s.normals[i];
        s.normals[i] = triangle_normal(m.p(Index(i), 0), m.p(Index(i), 1), m.p(Index(i), 2));
        for (int k = 0; k < 3; ++k) s.box.extend(m.p(Index(i), k));
    }
    for (Vec3& n : s.vertex_normals) normalize_like_sofa(n);
}

void RayTraceNarrowPhase::find_pairs(OctreeSurface& a, OctreeSurface& b, DetectionOutputList& out) {
    const TriangleModel& ma = *a.model;
    const TriangleModel& mb = *b.model;
    if (!a.octree.built()) a.octree.build(ma.state().position, a.triangles);
    if (!b.octree.built()) b.octree.build(mb.state().position, b.triangles);
    constexpr std::uint32_t kOwned[3] = {TriangleModel::kP1, TriangleModel::kP2, TriangleModel::kP3};
    for (std::size_t j = 0; j < ma.size(); ++j) {
        const Triangle& tri = ma.triangle(Index(j));
        int rank = 0;  // among the vertices triangle j owns
        for (int k = 0; k < 3; ++k) {
            if ((ma.flags(Index(j)) & kOwned[k]) == 0) continue;
            const int id_rank = rank++;
            const Vec3& p = ma.state().position[std::size_t(tri[std::size_t(k)])];
            const Vec3& normal = a.vertex_normals[std::size_t(tri[std::size_t(k)])];
            if (p.x() < b.box.min.x() || p.x() > b.box.max.x() || p.y() < b.box.min.y() || p.y() > b.box.max.y() ||
                p.z() < b.box.min.z() || p.z() > b.box.max.z())
                continue;
            const Vec3 inward = -normal;
            const RayHit hit = b.octree.trace(p, inward);
            if (hit.triangle < 0) continue;
            if (dot3(a.normals[j], b.normals[std::size_t(hit.triangle)]) > 0) continue;  // B's triangle faces away
            // A's own far side must lie beyond B's triangle (else P is outside A, or A is open)
            const RayHit own = a.octree.trace(p, inward);
            if (own.triangle < 0 || own.t < hit.t) continue;
            if (dot3(a.normals[j], a.normals[std::size_t(own.triangle)]) > 0) continue;
            const Index e2 = Index(hit.triangle);
            const Vec3 q = mb.p(e2, 0) * (1.0 - hit.u - hit.v) + mb.p(e2, 1) * hit.u + mb.p(e2, 2) * hit.v;
            DetectionOutput o;
            o.elem1 = ElementIndex(Index(j));
            o.elem2 = ElementIndex(e2);
            o.point = {p, q};
            o.normal = normal;
            o.value = -hit.t;
            o.id = std::int64_t(j) * 3 + id_rank;
            out.push_back(o);
        }
    }
}

const SceneDetection& RayTraceNarrowPhase::detect(const SceneDetection& broad_pairs) {
    // SOFA's pipeline computes every model's bounding tree before the narrow phase
    for (auto& s : surfaces_)
        if (s->model->params().active) update_surface(*s);
    result_.clear();
    for (const ModelPairDetection& pair : broad_pairs) {
        if (pair.skipped || !pair.narrow_phase || pair.model1 == nullptr || pair.model2 == nullptr) continue;
        OctreeSurface* a = find(*pair.model1);
        OctreeSurface* b = find(*pair.model2);
        if (a == nullptr || b == nullptr) continue;  // findPairsVolume needs two octree models
        for (int side = 0; side < 2; ++side) {
            OctreeSurface& first = side == 0 ? *a : *b;
            OctreeSurface& second = side == 0 ? *b : *a;
            ModelPairDetection d;
            d.model1 = first.model;
            d.model2 = second.model;
            d.support = pair.support;
            find_pairs(first, second, d.outputs);
            result_.push_back(std::move(d));
        }
    }
    return result_;
}

}  // namespace penalty
