#include "penalty/collision/intersection.hpp"

#include "kernels.hpp"
#include "penalty/core/error.hpp"

#include <array>
#include <cmath>

namespace penalty {

const char* intersection_method_name(IntersectionMethod m) {
    switch (m) {
        case IntersectionMethod::Discrete:
            return "DiscreteIntersection";
        case IntersectionMethod::NewProximity:
            return "NewProximityIntersection";
        case IntersectionMethod::MinProximity:
            return "MinProximityIntersection";
        case IntersectionMethod::LocalMinDistance:
            return "LocalMinDistance";
    }
    return "?";
}

const char* intersection_method_short_name(IntersectionMethod m) {
    switch (m) {
        case IntersectionMethod::Discrete:
            return "Discrete";
        case IntersectionMethod::NewProximity:
            return "NewProximity";
        case IntersectionMethod::MinProximity:
            return "MinProximity";
        case IntersectionMethod::LocalMinDistance:
            return "LocalMinDistance";
    }
    return "?";
}

const char* pair_support_name(PairSupport s) {
    switch (s) {
        case PairSupport::Supported:
            return "supported";
        case PairSupport::Ignored:
            return "ignored";
        case PairSupport::Unsupported:
            return "unsupported";
        case PairSupport::BeyondSofa:
            return "beyond-SOFA";
    }
    return "?";
}

namespace {
constexpr std::array<SofaQuirkInfo, 18> kSofaQuirks{{
    {"minproximity_line_sphere_mirror", &SofaQuirkFixes::fix_minproximity_line_sphere_mirror,
     "MinProximity Line-Sphere: closest point on the segment, not mirrored about its midpoint (spec 14.1)"},
    {"newproximity_triangle_sphere_edge_flags", &SofaQuirkFixes::fix_newproximity_triangle_sphere_edge_flags,
     "NewProximity Triangle-Sphere: edges AC and BC tested with their own ownership flags (spec 14.2)"},
    {"newproximity_triangle_sphere_edge_range", &SofaQuirkFixes::fix_newproximity_triangle_sphere_edge_range,
     "NewProximity Triangle-Sphere: edge parameters bounded below, no contact on an edge's extension"},
    {"newproximity_triangle_triangle_vertex1_flag", &SofaQuirkFixes::fix_newproximity_triangle_triangle_vertex1_flag,
     "NewProximity Triangle-Triangle: vertex 1 of the first triangle needs its ownership flag (spec 14.3)"},
    {"newproximity_triangle_triangle_normal_overwrite",
     &SofaQuirkFixes::fix_newproximity_triangle_triangle_normal_overwrite,
     "NewProximity Triangle-Triangle: stored triangle normals left alone (spec 14.4)"},
    {"mechanical_object_float_short_forms", &SofaQuirkFixes::fix_mechanical_object_float_short_forms,
     "MechanicalObject: dx dy dz, rx ry rz, scale, sx sy sz read in double, not rounded to float as SOFA's parse does "
     "(command line or BuildOptions only: the scene is read before any intersection component)"},
    {"rigid_orientation_as_written", &SofaQuirkFixes::fix_rigid_orientation_as_written,
     "Rigid3 MechanicalObject: orientation quaternions normalized when read and when written after init, not kept "
     "as written as SOFA's (a non-unit one maps the frame's points by a matrix that is not a rotation) (command line "
     "or BuildOptions only)"},
    {"regular_grid_float_bounds", &SofaQuirkFixes::fix_regular_grid_float_bounds,
     "RegularGridTopology: xmin..zmax and scale read in double, not rounded to float as SOFA's parse does "
     "(command line or BuildOptions only)"},
    {"number_trailing_text", &SofaQuirkFixes::fix_number_trailing_text,
     "a number attribute with text after its number (tolerance=\"10-3\") is an error, not read as its leading number "
     "as SOFA's Data<T>::read does (command line or BuildOptions only)"},
    {"topology_removal_out_of_range", &SofaQuirkFixes::fix_topology_removal_out_of_range,
     "TopologicalChangeProcessor: an edge, triangle, quad, tetrahedron or hexahedron index past the topology's end is "
     "an "
     "error, not dropped with a warning as SOFA's *SetTopologyModifier::remove* do (command line or BuildOptions "
     "only)"},
    {"incision_invalid_path", &SofaQuirkFixes::fix_incision_invalid_path,
     "TopologicalChangeProcessor INCISE=: a segment whose path does not reach its end point across the surface is an "
     "error, not skipped with the rest of its line as SOFA's processTopologicalChanges does (command line or "
     "BuildOptions only)"},
    {"uniform_mass_lazy_write", &SofaQuirkFixes::fix_uniform_mass_lazy_write,
     "UniformMass: a totalMass or vertexMass written after init reaches the weight and the mass matrix at the same "
     "step, as a fresh scene, not the weight first with the old value as SOFA's lazy update callback does (command "
     "line or BuildOptions only)"},
    {"mesh_spring_stiffness_write", &SofaQuirkFixes::fix_mesh_spring_stiffness_write,
     "MeshSpringForceField: a stiffness or damping written after init gives each spring value / rest length as a "
     "fresh scene, not the written value for every spring as SOFA's SpringForceField lists do (command line or "
     "BuildOptions only)"},
    {"box_roi_write", &SofaQuirkFixes::fix_box_roi_write,
     "BoxROI: a box or orientedBox written after init selects as a fresh scene would (corners ordered, the oriented "
     "boxes made from the written value), not with the box as written and the oriented boxes of init as SOFA's "
     "roiInit, which runs once (command line or BuildOptions only)"},
    {"subset_data_last_index", &SofaQuirkFixes::fix_subset_data_last_index,
     "Edge/Triangle/QuadPressureForceField: a removal renames the entries of the topology's current last element, not "
     "those of SOFA's TopologySubsetData last index kept from init (command line or BuildOptions only)"},
    {"triangle_fem_slot_data", &SofaQuirkFixes::fix_triangle_fem_slot_data,
     "TriangleFEMForceField: after a topological change each triangle's rest data are made again from the rest "
     "positions, as a fresh scene, not kept by slot from init as SOFA's (no topology data: a slot keeps the data of "
     "the triangle first there) (command line or BuildOptions only)"},
    {"sphere_loader_src_transform", &SofaQuirkFixes::fix_sphere_loader_src_transform,
     "MechanicalObject src=\"@SphereLoader\": the state keeps its own translation, rotation and scale3d, not the "
     "loader's, which SOFA's src link copies so that the loaded points are moved twice (command line or "
     "BuildOptions only)"},
    {"mesh_loader_float_scale", &SofaQuirkFixes::fix_mesh_loader_float_scale,
     "mesh loaders (MeshOBJLoader, MeshGmshLoader, ..., GridMeshCreator): scale read in double, not rounded to float "
     "as SOFA's MeshLoader::parse does (command line or BuildOptions only)"},
}};
}  // namespace

std::span<const SofaQuirkInfo> sofa_quirk_table() { return kSofaQuirks; }

bool enable_sofa_quirk_fix(SofaQuirkFixes& fixes, std::string_view name) {
    if (name == "all") {
        for (const SofaQuirkInfo& q : kSofaQuirks) fixes.*q.member = true;
        return true;
    }
    for (const SofaQuirkInfo& q : kSofaQuirks) {
        if (q.name == name) {
            fixes.*q.member = true;
            return true;
        }
    }
    return false;
}

std::vector<std::string> enabled_sofa_quirk_fixes(const SofaQuirkFixes& fixes) {
    std::vector<std::string> out;
    for (const SofaQuirkInfo& q : kSofaQuirks)
        if (fixes.*q.member) out.emplace_back(q.name);
    return out;
}

SofaQuirkFixes merge_sofa_quirk_fixes(const SofaQuirkFixes& a, const SofaQuirkFixes& b) {
    SofaQuirkFixes out = a;
    for (const SofaQuirkInfo& q : kSofaQuirks) out.*q.member = a.*q.member || b.*q.member;
    if (b.zero_distance_normal != ZeroDistanceNormal::FallbackX) out.zero_distance_normal = b.zero_distance_normal;
    return out;
}

const char* zero_distance_normal_name(ZeroDistanceNormal policy) {
    switch (policy) {
        case ZeroDistanceNormal::FallbackX:
            return "fallbackX";
        case ZeroDistanceNormal::Drop:
            return "drop";
        case ZeroDistanceNormal::SofaNaN:
            return "sofaNaN";
    }
    return "?";
}

IntersectionParams IntersectionParams::discrete() {
    IntersectionParams p;
    p.method = IntersectionMethod::Discrete;
    p.alarm_distance = 0.0;
    p.contact_distance = 0.0;
    return p;
}
IntersectionParams IntersectionParams::new_proximity() {
    IntersectionParams p;
    p.method = IntersectionMethod::NewProximity;
    p.use_line_line = false;
    return p;
}
IntersectionParams IntersectionParams::min_proximity() {
    IntersectionParams p;
    p.method = IntersectionMethod::MinProximity;
    p.use_line_line = true;
    return p;
}
IntersectionParams IntersectionParams::local_min_distance() {
    IntersectionParams p;
    p.method = IntersectionMethod::LocalMinDistance;
    return p;
}

void IntersectionParams::validate() const {
    auto check = [this](const char* what, double v) {
        if (!(v >= 0.0) || !std::isfinite(v)) {
            throw_invalid_argument(intersection_method_name(method), ": parameter ", what, " is ", v,
                                   " (must be finite and >= 0)");
        }
    };
    check("alarmDistance", alarm_distance);
    check("contactDistance", contact_distance);
    check("angleCone", angle_cone);
    check("coneFactor", cone_factor);
}

// ---------------------------------------------------------------------------------------------
// Registered order: the first model of a pair is the one with the higher rank
// (Cylinder > Tetrahedron > Triangle > Line > Sphere > RigidSphere > Point), which reproduces
// every registration of spec §5.2/§6 (e.g. Triangle–Point, Sphere–RigidSphere, RigidSphere–Point).
namespace {
int rank(ModelType t) {
    switch (t) {
        case ModelType::Point:
            return 0;
        case ModelType::RigidSphere:
            return 1;
        case ModelType::Sphere:
            return 2;
        case ModelType::Line:
            return 3;
        case ModelType::Triangle:
            return 4;
        case ModelType::Tetrahedron:
            return 5;
        case ModelType::Cylinder:
            return 6;
    }
    return 0;
}
}  // namespace

bool is_registered_order(ModelType a, ModelType b) { return rank(a) >= rank(b); }

// ---------------------------------------------------------------------------------------------
// The dispatch table: [method][model 1][model 2] in registered order. Every cell not listed
// below is Unsupported (no intersector in SOFA).
namespace {

using detail::KernelFn;

/// A MinProximity use* switch that turns a pair into "ignored" when false.
enum class Switch : std::uint8_t { None, SphereTriangle, PointPoint, LinePoint, LineLine };

struct Entry {
    PairSupport support = PairSupport::Unsupported;
    KernelFn fn = nullptr;
    Switch sw = Switch::None;
};

constexpr int kM = kIntersectionMethodCount;
constexpr int kT = kModelTypeCount;
using Table = std::array<std::array<std::array<Entry, kT>, kT>, kM>;

Table build_table() {
    Table t{};
    using M = IntersectionMethod;
    using T = ModelType;
    auto set = [&t](M m, T a, T b, PairSupport s, KernelFn fn, Switch sw = Switch::None) {
        PENALTY_DEMAND(is_registered_order(a, b));
        t[std::size_t(m)][std::size_t(a)][std::size_t(b)] = Entry{s, fn, sw};
    };
    constexpr auto S = PairSupport::Supported;
    constexpr auto I = PairSupport::Ignored;
    constexpr auto B = PairSupport::BeyondSofa;
    namespace k = detail;

    // Every method derives from DiscreteIntersection: sphere pairs start as Discrete, then are
    // overridden below by each method's own routine (Tetrahedron–Point: see beyond-SOFA rows).
    // --- DiscreteIntersection
    set(M::Discrete, T::Sphere, T::Sphere, S, k::discrete_sphere_sphere);
    set(M::Discrete, T::RigidSphere, T::RigidSphere, S, k::discrete_sphere_sphere);
    set(M::Discrete, T::Sphere, T::RigidSphere, S, k::discrete_sphere_sphere);
    set(M::Discrete, T::Triangle, T::Line, S, k::discrete_triangle_line);
    set(M::Discrete, T::Tetrahedron, T::Point, B, k::tetrahedron_point);

    // --- NewProximityIntersection
    set(M::NewProximity, T::Sphere, T::Sphere, S, k::np_sphere_sphere);
    set(M::NewProximity, T::RigidSphere, T::RigidSphere, S, k::np_sphere_sphere);
    set(M::NewProximity, T::Sphere, T::RigidSphere, S, k::np_sphere_sphere);
    set(M::NewProximity, T::Sphere, T::Point, S, k::np_sphere_point);
    set(M::NewProximity, T::RigidSphere, T::Point, S, k::np_sphere_point);
    set(M::NewProximity, T::Point, T::Point, S, k::np_point_point);
    set(M::NewProximity, T::Line, T::Point, S, k::np_line_point);
    set(M::NewProximity, T::Line, T::Line, S, k::np_line_line);
    set(M::NewProximity, T::Line, T::Sphere, S, k::np_line_sphere);
    set(M::NewProximity, T::Line, T::RigidSphere, S, k::np_line_sphere);
    set(M::NewProximity, T::Triangle, T::Point, S, k::np_triangle_point);
    set(M::NewProximity, T::Triangle, T::Sphere, S, k::np_triangle_sphere);
    set(M::NewProximity, T::Triangle, T::RigidSphere, S, k::np_triangle_sphere);
    set(M::NewProximity, T::Triangle, T::Line, S, k::np_triangle_line);
    set(M::NewProximity, T::Triangle, T::Triangle, S, k::np_triangle_triangle);
    set(M::NewProximity, T::Cylinder, T::Cylinder, B, k::cylinder_cylinder);
    set(M::NewProximity, T::Cylinder, T::Triangle, B, k::cylinder_triangle);
    set(M::NewProximity, T::Cylinder, T::Sphere, B, k::cylinder_sphere);
    set(M::NewProximity, T::Cylinder, T::RigidSphere, B, k::cylinder_sphere);
    set(M::NewProximity, T::Tetrahedron, T::Point, B, k::tetrahedron_point);

    // --- MinProximityIntersection
    set(M::MinProximity, T::Sphere, T::Sphere, S, k::min_sphere_sphere);
    set(M::MinProximity, T::RigidSphere, T::RigidSphere, S, k::min_sphere_sphere);
    set(M::MinProximity, T::Sphere, T::RigidSphere, S, k::min_sphere_sphere);
    set(M::MinProximity, T::Sphere, T::Point, S, k::min_sphere_point, Switch::SphereTriangle);
    set(M::MinProximity, T::RigidSphere, T::Point, S, k::min_sphere_point, Switch::SphereTriangle);
    set(M::MinProximity, T::Point, T::Point, S, k::min_point_point, Switch::PointPoint);
    set(M::MinProximity, T::Line, T::Point, S, k::min_line_point, Switch::LinePoint);
    set(M::MinProximity, T::Line, T::Line, S, k::min_line_line, Switch::LineLine);
    set(M::MinProximity, T::Line, T::Sphere, S, k::min_line_sphere, Switch::SphereTriangle);
    set(M::MinProximity, T::Line, T::RigidSphere, S, k::min_line_sphere, Switch::SphereTriangle);
    set(M::MinProximity, T::Triangle, T::Point, S, k::min_triangle_point);
    set(M::MinProximity, T::Triangle, T::Sphere, S, k::min_triangle_sphere, Switch::SphereTriangle);
    set(M::MinProximity, T::Triangle, T::RigidSphere, S, k::min_triangle_sphere, Switch::SphereTriangle);
    set(M::MinProximity, T::Triangle, T::Line, I, nullptr);
    set(M::MinProximity, T::Triangle, T::Triangle, I, nullptr);
    set(M::MinProximity, T::Cylinder, T::Cylinder, B, k::cylinder_cylinder);
    set(M::MinProximity, T::Cylinder, T::Triangle, B, k::cylinder_triangle);
    set(M::MinProximity, T::Cylinder, T::Sphere, B, k::cylinder_sphere);
    set(M::MinProximity, T::Cylinder, T::RigidSphere, B, k::cylinder_sphere);
    set(M::MinProximity, T::Tetrahedron, T::Point, B, k::tetrahedron_point);

    // --- LocalMinDistance (Vec3 spheres only, rigid sphere pairs through the Discrete routine)
    set(M::LocalMinDistance, T::Sphere, T::Sphere, S, k::lmd_sphere_sphere);
    set(M::LocalMinDistance, T::RigidSphere, T::RigidSphere, S, k::lmd_rigid_sphere_pair);
    set(M::LocalMinDistance, T::Sphere, T::RigidSphere, S, k::lmd_rigid_sphere_pair);
    set(M::LocalMinDistance, T::Sphere, T::Point, S, k::lmd_sphere_point);
    set(M::LocalMinDistance, T::Point, T::Point, S, k::lmd_point_point);
    set(M::LocalMinDistance, T::Line, T::Point, S, k::lmd_line_point);
    set(M::LocalMinDistance, T::Line, T::Line, S, k::lmd_line_line);
    set(M::LocalMinDistance, T::Line, T::Sphere, S, k::lmd_line_sphere);
    set(M::LocalMinDistance, T::Triangle, T::Point, S, k::lmd_triangle_point);
    set(M::LocalMinDistance, T::Triangle, T::Sphere, S, k::lmd_triangle_sphere);
    set(M::LocalMinDistance, T::Triangle, T::Line, I, nullptr);
    set(M::LocalMinDistance, T::Triangle, T::Triangle, I, nullptr);
    set(M::LocalMinDistance, T::Tetrahedron, T::Point, B, k::tetrahedron_point);
    return t;
}

const Table& table() {
    static const Table t = build_table();
    return t;
}

const Entry& entry(IntersectionMethod m, ModelType a, ModelType b) {
    if (!is_registered_order(a, b)) std::swap(a, b);
    return table()[std::size_t(m)][std::size_t(a)][std::size_t(b)];
}

bool switch_on(const IntersectionParams& p, Switch s) {
    switch (s) {
        case Switch::None:
            return true;
        case Switch::SphereTriangle:
            return p.use_sphere_triangle;
        case Switch::PointPoint:
            return p.use_point_point;
        case Switch::LinePoint:
            return p.use_line_point;
        case Switch::LineLine:
            return p.use_line_line;
    }
    return true;
}

bool active(const IntersectionParams& p, const Entry& e) {
    if (e.fn == nullptr) return false;
    if (e.support == PairSupport::Supported) return switch_on(p, e.sw);
    return e.support == PairSupport::BeyondSofa && p.enable_beyond_sofa_pairs;
}

// vertex indices of an element of a mesh-based model sharing a state with another model
bool has_vertex(const CollisionModel& m, Index e, Index v) {
    switch (m.type()) {
        case ModelType::Triangle:
            for (auto x : static_cast<const TriangleModel&>(m).triangle(e))
                if (x == v) return true;
            return false;
        case ModelType::Line:
            for (auto x : static_cast<const LineModel&>(m).edge(e))
                if (x == v) return true;
            return false;
        case ModelType::Tetrahedron:
            for (auto x : static_cast<const TetrahedronModel&>(m).tetrahedron(e))
                if (x == v) return true;
            return false;
        default:
            return false;
    }
}

const void* model_state_address(const CollisionModel& m) {
    switch (m.type()) {
        case ModelType::Point:
            return &static_cast<const PointModel&>(m).state();
        case ModelType::Line:
            return &static_cast<const LineModel&>(m).state();
        case ModelType::Triangle:
            return &static_cast<const TriangleModel&>(m).state();
        case ModelType::Sphere:
            return &static_cast<const SphereModel&>(m).state();
        case ModelType::RigidSphere:
            return &static_cast<const RigidSphereModel&>(m).state();
        case ModelType::Cylinder:
            return &static_cast<const CylinderModel&>(m).state();
        case ModelType::Tetrahedron:
            return &static_cast<const TetrahedronModel&>(m).state();
    }
    return nullptr;
}

}  // namespace

// self-collision element filters for two models of the same node (spec §3.2, §3.4)
bool elements_may_collide(const CollisionModel& m1, Index e1, const CollisionModel& m2, Index e2) {
    if (&m1 == &m2) {
        if (m1.type() == ModelType::Point) {
            const auto* topo = static_cast<const PointModel&>(m1).topology();
            if (topo != nullptr) {
                const auto& vav = topo->vertices_around_vertex();
                if (std::size_t(e1) < vav.size())
                    for (auto v : vav[std::size_t(e1)])
                        if (v == e2) return false;
            }
        } else if (m1.type() == ModelType::Line) {
            const auto& l = static_cast<const LineModel&>(m1);
            for (auto a : l.edge(e1))
                for (auto b : l.edge(e2))
                    if (a == b) return false;
        }
        return true;
    }
    // a mesh element vs a point of the same state that is one of its vertices
    if (m2.type() == ModelType::Point && model_state_address(m1) == model_state_address(m2))
        return !has_vertex(m1, e1, e2);
    return true;
}

PairSupport pair_support(const IntersectionParams& params, ModelType a, ModelType b) {
    const Entry& e = entry(params.method, a, b);
    if (e.support == PairSupport::Supported && !switch_on(params, e.sw)) return PairSupport::Ignored;
    return e.support;
}

detail::KernelFn detail::pair_kernel(const IntersectionParams& params, const CollisionModel& m1,
                                     const CollisionModel& m2) {
    if (!is_registered_order(m1.type(), m2.type()) && m1.type() != m2.type()) {
        throw_invalid_argument("intersect_elements(): models '", m1.name(), "' (", model_type_name(m1.type()),
                               ") and '", m2.name(), "' (", model_type_name(m2.type()),
                               ") are not in registered order; swap them");
    }
    const Entry& e = entry(params.method, m1.type(), m2.type());
    if (!active(params, e)) {
        throw_invalid_argument("intersect_elements(): ", intersection_method_name(params.method),
                               " has no active "
                               "intersector for ",
                               model_type_name(m1.type()), "-", model_type_name(m2.type()), " (",
                               pair_support_name(pair_support(params, m1.type(), m2.type())), ")");
    }
    return e.fn;
}

detail::KernelParts detail::pair_kernel_parts(const IntersectionParams& params, const CollisionModel& m1,
                                              const CollisionModel& m2) {
    const KernelFn fn = pair_kernel(params, m1, m2);
    if (fn == &np_triangle_triangle && np_triangle_triangle_writes_normals(params, m1, m2))
        return {&np_triangle_triangle_normals, &np_triangle_triangle_geometry};
    // (NewProximity's triangle filter drops only triangles' unowned features and degenerate
    // triangles: nothing but the degenerate ones in a soup whose triangles own every feature)
    if (fn == &np_triangle_point || fn == &np_triangle_sphere) {
        if (static_cast<const TriangleModel&>(m1).owns_every_feature()) return {nullptr, fn};
        return {nullptr, fn, &filter_triangle_candidates};
    }
    if (fn == &min_triangle_point || fn == &min_triangle_sphere) return {nullptr, fn, &filter_triangle_candidates};
    if (fn == &np_line_line || fn == &min_line_line) return {nullptr, fn, &filter_line_line_candidates};
    if (fn == &np_sphere_point) return {nullptr, fn, nullptr, &np_sphere_point_all};
    return {nullptr, fn};
}

int intersect_elements(const IntersectionParams& params, CollisionModel& m1, Index e1, CollisionModel& m2, Index e2,
                       DetectionOutputList& out) {
    const detail::KernelFn fn = detail::pair_kernel(params, m1, m2);
    if (e1 < 0 || std::size_t(e1) >= m1.size() || e2 < 0 || std::size_t(e2) >= m2.size()) {
        throw_invalid_argument("intersect_elements(): element index out of range: ", m1.name(), "[", e1, "] (size ",
                               m1.size(), "), ", m2.name(), "[", e2, "] (size ", m2.size(), ")");
    }
    detail::PairCtx ctx{params, m1, m2, e1, e2, out};
    return fn(ctx);
}

bool has_active_intersector(const IntersectionParams& params, ModelType a, ModelType b) {
    return active(params, entry(params.method, a, b));
}

double box_margin(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2) {
    return params.method == IntersectionMethod::Discrete
               ? params.alarm_distance
               : params.alarm_distance + m1.params().contact_distance + m2.params().contact_distance;
}

void exhaustive_narrow_phase(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                             DetectionOutputList& out, std::vector<Aabb>& box_scratch) {
    m1.validate();
    if (&m2 != &m1) m2.validate();
    m1.update();
    if (&m2 != &m1) m2.update();
    detail::exhaustive_element_pairs(params, m1, m2, out, box_scratch);
}

void detail::exhaustive_element_pairs(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                                      DetectionOutputList& out, std::vector<Aabb>& box_scratch) {
    const Entry& e = entry(params.method, m1.type(), m2.type());
    PENALTY_DEMAND(is_registered_order(m1.type(), m2.type()) && active(params, e));
    // SOFA's cube test margin (§3.8): conservative, never changes the set of outputs
    const double margin = box_margin(params, m1, m2);
    const bool same_model = &m1 == &m2;
    const bool node = same_node(m1, m2);
    box_scratch.resize(m2.size());
    for (std::size_t j = 0; j < m2.size(); ++j) box_scratch[j] = m2.element_box(Index(j));
    for (std::size_t i = 0; i < m1.size(); ++i) {
        const Aabb box1 = m1.element_box(Index(i));
        const std::size_t end = same_model ? i : m2.size();
        for (std::size_t j = 0; j < end; ++j) {
            if (!box1.overlaps(box_scratch[j], margin)) continue;
            if (node && !elements_may_collide(m1, Index(i), m2, Index(j))) continue;
            detail::PairCtx ctx{params, m1, m2, Index(i), Index(j), out};
            e.fn(ctx);
        }
    }
}

ModelPairDetection detect_model_pair(const IntersectionParams& params, CollisionModel& a, CollisionModel& b) {
    params.validate();
    a.validate();
    if (&b != &a) b.validate();
    ModelPairDetection res;
    const bool keep_order = is_registered_order(a.type(), b.type());
    res.model1 = keep_order ? &a : &b;
    res.model2 = keep_order ? &b : &a;
    res.support = pair_support(params, res.model1->type(), res.model2->type());
    if (!keep_model_pair(*res.model1, *res.model2)) {
        res.skipped = true;
        return res;
    }
    if (!has_active_intersector(params, res.model1->type(), res.model2->type())) return res;
    std::vector<Aabb> boxes;
    exhaustive_narrow_phase(params, *res.model1, *res.model2, res.outputs, boxes);
    return res;
}

}  // namespace penalty
