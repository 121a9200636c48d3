// ContinuousDetection's surfaces: the models grouped by state, their features, the recorded start
// of the motion and the swept-box trees (ccd_detection.hpp).
#include "ccd_surfaces.hpp"
#include "penalty/core/index_types.hpp"

#include "penalty/collision/models.hpp"
#include "penalty/core/error.hpp"

#include <algorithm>
#include <set>
#include <unordered_map>
#include <unordered_set>

namespace penalty {

using namespace detail;

namespace detail {

namespace {
CollisionModelParams swept_box_params() {
    CollisionModelParams p;
    p.name = "swept boxes";
    return p;
}
}  // namespace

SweptBoxes::SweptBoxes() : CollisionModel(ModelType::Point, swept_box_params()) {}

void SweptBoxes::element_boxes(std::size_t begin, std::size_t end, Aabb* out) const {
    std::copy(boxes.begin() + std::ptrdiff_t(begin), boxes.begin() + std::ptrdiff_t(end), out);
}

}  // namespace detail

namespace {

/// The model's state: exactly one of the two is set (both null for a model without features).
struct ModelState {
    const Vec3State* vec3 = nullptr;
    const Rigid3State* rigid = nullptr;
    [[nodiscard]] const void* key() const {
        return vec3 ? static_cast<const void*>(vec3) : static_cast<const void*>(rigid);
    }
};

ModelState state_of(const CollisionModel& m) {
    switch (m.type()) {
        case ModelType::Point:
            return {&static_cast<const PointModel&>(m).state(), nullptr};
        case ModelType::Line:
            return {&static_cast<const LineModel&>(m).state(), nullptr};
        case ModelType::Triangle:
            return {&static_cast<const TriangleModel&>(m).state(), nullptr};
        case ModelType::Sphere:
            return {&static_cast<const SphereModel&>(m).state(), nullptr};
        case ModelType::RigidSphere:
            return {nullptr, &static_cast<const RigidSphereModel&>(m).state()};
        case ModelType::Cylinder:
        case ModelType::Tetrahedron:
            return {};  // no feature the guard tests (docs/no-tunnelling.md)
    }
    return {};
}

bool has_vertices(ModelType t) { return t == ModelType::Point || t == ModelType::Line || t == ModelType::Triangle; }
bool has_edges(ModelType t) { return t == ModelType::Line || t == ModelType::Triangle; }
bool has_triangles(ModelType t) { return t == ModelType::Triangle; }
bool has_spheres(ModelType t) { return t == ModelType::Sphere || t == ModelType::RigidSphere; }

/// The tests a model pair adds to its surface pair, m1 on surface a, m2 on surface b (in that
/// order of the bits' `ab`).
std::uint32_t tests_of(ModelType t1, ModelType t2, bool edge_edge) {
    std::uint32_t bits = 0;
    if (has_vertices(t1) && has_triangles(t2)) bits |= kVertexTriangleAB;
    if (has_vertices(t2) && has_triangles(t1)) bits |= kVertexTriangleBA;
    if (edge_edge && has_edges(t1) && has_edges(t2)) bits |= kEdgeEdge;
    if (has_spheres(t1) && has_triangles(t2)) bits |= kSphereTriangleAB;
    if (has_spheres(t2) && has_triangles(t1)) bits |= kSphereTriangleBA;
    if (has_spheres(t1) && has_spheres(t2)) bits |= kSphereSphere;
    return bits;
}

/// The bits of (m1 on a, m2 on b) seen from (b, a).
std::uint32_t swapped(std::uint32_t bits) {
    const auto move = [&](std::uint32_t from, std::uint32_t to) { return (bits & from) ? to : 0u; };
    return move(kVertexTriangleAB, kVertexTriangleBA) | move(kVertexTriangleBA, kVertexTriangleAB) |
           (bits & kEdgeEdge) | move(kSphereTriangleAB, kSphereTriangleBA) |
           move(kSphereTriangleBA, kSphereTriangleAB) | (bits & kSphereSphere);
}

PairKey edge_key(Index a, Index b) { return PairKey::unordered(std::uint32_t(a), std::uint32_t(b)); }

}  // namespace

std::size_t ContinuousDetection::Surface::feature_count(int kind) const {
    switch (kind) {
        case kVertexFeature:
            return vertices.size();
        case kEdgeFeature:
            return edges.size();
        case kTriangleFeature:
            return triangles.size();
        default:
            return sphere_dof.size();
    }
}

void ContinuousDetection::Surface::update_trees() {
    const auto box_of = [&](std::initializer_list<Index> dofs, double grow) {
        Aabb b;
        for (Index d : dofs) {
            b.extend(then(d));
            b.extend(now(d));
        }
        if (grow > 0.0) b.inflate(grow);
        return b;
    };
    boxes[kVertexFeature].boxes.resize(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i) boxes[kVertexFeature].boxes[i] = box_of({vertices[i]}, 0.0);
    boxes[kEdgeFeature].boxes.resize(edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i)
        boxes[kEdgeFeature].boxes[i] = box_of({edges[i][0], edges[i][1]}, 0.0);
    boxes[kTriangleFeature].boxes.resize(triangles.size());
    for (std::size_t i = 0; i < triangles.size(); ++i)
        boxes[kTriangleFeature].boxes[i] = box_of({triangles[i][0], triangles[i][1], triangles[i][2]}, 0.0);
    boxes[kSphereFeature].boxes.resize(sphere_dof.size());
    for (std::size_t i = 0; i < sphere_dof.size(); ++i)
        boxes[kSphereFeature].boxes[i] = box_of({sphere_dof[i]}, sphere_radius[i]);
    swept_box = Aabb{};
    for (int k = 0; k < kFeatureKinds; ++k) {
        const auto kk = std::size_t(k);
        kind_box[kk] = Aabb{};
        if (boxes[kk].boxes.empty()) continue;
        if (has_tree(k)) {
            if (!tree_built[kk]) trees[kk].build(boxes[kk], 4);
            else trees[kk].refit(boxes[kk], 2.0, 4);
            tree_built[kk] = true;
            kind_box[kk] = trees[kk].root_box();
        } else {
            for (const Aabb& b : boxes[kk].boxes) kind_box[kk].extend(b);
        }
        swept_box.extend(kind_box[kk]);
    }
}

ContinuousDetection::ContinuousDetection() = default;
ContinuousDetection::~ContinuousDetection() = default;

std::size_t ContinuousDetection::surface_count() const { return surfaces_.size(); }
const std::string& ContinuousDetection::surface_name(std::size_t s) const { return surfaces_.at(s)->name; }

void ContinuousDetection::set_pairs(std::span<const ModelPair> pairs, bool edge_edge) {
    for (const ModelPair& p : pairs)
        if (p.model1 == nullptr || p.model2 == nullptr)
            throw_invalid_argument("ContinuousDetection::set_pairs: a null model");
    pairs_.assign(pairs.begin(), pairs.end());
    pair_edge_edge_.assign(pairs_.size(), edge_edge ? 1 : 0);
    build_surfaces();
}

void ContinuousDetection::add_pipeline_pairs(const IntersectionParams& params,
                                             std::span<CollisionModel* const> models) {
    std::vector<ModelPair> kept;
    broad_phase(params, models, kept);
    const auto key = [](const ModelPair& p) {
        return std::hash<const void*>()(p.model1) * 0x9e3779b97f4a7c15ull ^ std::hash<const void*>()(p.model2);
    };
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> listed;
    for (std::size_t i = 0; i < pairs_.size(); ++i) listed[key(pairs_[i])].push_back(i);
    for (const ModelPair& p : kept) {
        bool found = false;
        if (auto it = listed.find(key(p)); it != listed.end())
            for (std::size_t i : it->second) found = found || pairs_[i] == p;
        if (found) continue;
        // edge–edge contacts: Line–Line intersectors, or the method's line–line switch
        const bool lines = p.model1->type() == ModelType::Line && p.model2->type() == ModelType::Line;
        pairs_.push_back(p);
        pair_edge_edge_.push_back(lines || params.use_line_line ? 1 : 0);
    }
    build_surfaces();
}

void ContinuousDetection::build_surfaces() {
    surfaces_.clear();
    pair_tests_.clear();
    started_ = false;
    std::unordered_map<const void*, std::size_t> surface_of_state;
    std::unordered_map<const CollisionModel*, std::size_t>& surface_of_model = surface_of_;
    surface_of_model.clear();
    std::unordered_map<PairKey, std::uint32_t> tests;  // (lower surface, higher surface) → tests
    const auto surface_for = [&](const CollisionModel& m) -> std::size_t {
        if (auto it = surface_of_model.find(&m); it != surface_of_model.end()) return it->second;
        const ModelState st = state_of(m);
        if (st.key() == nullptr) return std::size_t(-1);
        auto [it, added] = surface_of_state.emplace(st.key(), surfaces_.size());
        if (added) {
            auto s = std::make_unique<Surface>();
            s->vec3 = st.vec3;
            s->rigid = st.rigid;
            surfaces_.push_back(std::move(s));
        }
        Surface& s = *surfaces_[it->second];
        s.models.push_back(&m);
        s.name += (s.name.empty() ? "" : "+") + m.name();
        surface_of_model.emplace(&m, it->second);
        return it->second;
    };
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
        const ModelPair& p = pairs_[k];
        const std::size_t a = surface_for(*p.model1), b = surface_for(*p.model2);
        if (a == std::size_t(-1) || b == std::size_t(-1)) continue;
        std::uint32_t bits = tests_of(p.model1->type(), p.model2->type(), pair_edge_edge_[k] != 0);
        const PairKey key = PairKey::unordered(std::uint32_t(a), std::uint32_t(b));
        if (a > b) bits = swapped(bits);
        if (a == b) bits |= swapped(bits);  // within one surface both ways are one test
        if (bits != 0) tests[key] |= bits;
    }
    pair_tests_.assign(tests.begin(), tests.end());
    std::sort(pair_tests_.begin(), pair_tests_.end());
    // the features of each surface, each once (vertices and edges by DOF, triangles by DOF triple)
    for (auto& sp : surfaces_) {
        Surface& s = *sp;
        std::vector<char> is_vertex(s.state_size(), 0);
        std::unordered_set<PairKey> edge_seen;
        std::set<std::array<Index, 3>> triangle_seen;
        const auto add_vertex = [&](Index v, const CollisionModel* m) {
            if (v < 0 || std::size_t(v) >= is_vertex.size()) return;
            if (is_vertex[std::size_t(v)]) return;
            is_vertex[std::size_t(v)] = 1;
            s.vertices.push_back(v);
            s.vertex_model.push_back(m);
        };
        const auto add_edge = [&](Index a, Index b, const CollisionModel* m) {
            if (a == b || !edge_seen.insert(edge_key(a, b)).second) return;
            s.edges.push_back({a, b});
            s.edge_model.push_back(m);
        };
        const auto add_spheres = [&](const auto& spheres, const CollisionModel* m) {  // Sphere, RigidSphere
            for (std::size_t i = 0; i < spheres.size(); ++i) {
                s.sphere_dof.push_back(Index(i));
                s.sphere_radius.push_back(spheres.radius(Index(i)));
                s.sphere_model.push_back(m);
                s.sphere_element.push_back(Index(i));
            }
        };
        for (const CollisionModel* m : s.models) {
            switch (m->type()) {
                case ModelType::Point: {
                    const auto& pm = static_cast<const PointModel&>(*m);
                    for (std::size_t i = 0; i < pm.size(); ++i) add_vertex(Index(i), m);
                    break;
                }
                case ModelType::Line: {
                    const auto& lm = static_cast<const LineModel&>(*m);
                    for (std::size_t i = 0; i < lm.size(); ++i) {
                        const Edge& e = lm.edge(Index(i));
                        add_vertex(Index(e[0]), m);
                        add_vertex(Index(e[1]), m);
                        add_edge(Index(e[0]), Index(e[1]), m);
                    }
                    break;
                }
                case ModelType::Triangle: {
                    const auto& tm = static_cast<const TriangleModel&>(*m);
                    for (std::size_t i = 0; i < tm.size(); ++i) {
                        const Triangle& t = tm.triangle(Index(i));
                        std::array<Index, 3> dofs{Index(t[0]), Index(t[1]), Index(t[2])};
                        std::array<Index, 3> sorted = dofs;
                        std::sort(sorted.begin(), sorted.end());
                        for (Index d : dofs) add_vertex(d, m);
                        for (int k = 0; k < 3; ++k) add_edge(dofs[std::size_t(k)], dofs[std::size_t((k + 1) % 3)], m);
                        if (!triangle_seen.insert(sorted).second) continue;
                        s.triangles.push_back(dofs);
                        s.triangle_model.push_back(m);
                        s.triangle_element.push_back(Index(i));
                    }
                    break;
                }
                case ModelType::Sphere:
                    add_spheres(static_cast<const SphereModel&>(*m), m);
                    break;
                case ModelType::RigidSphere:
                    add_spheres(static_cast<const RigidSphereModel&>(*m), m);
                    break;
                default:
                    break;
            }
        }
    }
}

void ContinuousDetection::record_start() {
    for (auto& sp : surfaces_) {
        Surface& s = *sp;
        const std::size_t n = s.state_size();
        s.recorded_size = n;
        s.start_live = false;
        s.start.resize(n);
        if (s.vec3) {
            std::copy(s.vec3->position.begin(), s.vec3->position.end(), s.start.begin());
        } else {
            for (std::size_t i = 0; i < n; ++i) s.start[i] = s.rigid->position[i].center;
        }
    }
    started_ = true;
}

std::optional<std::size_t> ContinuousDetection::surface_of(const CollisionModel& m) const {
    const auto it = surface_of_.find(&m);
    if (it == surface_of_.end()) return std::nullopt;
    return it->second;
}

Vec3 ContinuousDetection::start_position(const CollisionModel& model, Index dof) const {
    for (const auto& s : surfaces_)
        if (std::find(s->models.begin(), s->models.end(), &model) != s->models.end()) {
            if (dof < 0 || std::size_t(dof) >= s->state_size())
                throw_invalid_argument("ContinuousDetection::start_position: DOF ", dof, " outside the state of '",
                                       model.name(), "'");
            return s->then(dof);
        }
    throw_invalid_argument("ContinuousDetection::start_position: model '", model.name(), "' is not tested");
}

}  // namespace penalty
