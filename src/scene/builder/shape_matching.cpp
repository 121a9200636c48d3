// SOFA's shape matching components (docs/components/shape_matching.md): ClusteringEngine and
// ShapeMatching (data engines, Sofa.Component.Engine.Analyze) and
// PositionBasedDynamicsProjectiveConstraint (Sofa.Component.Constraint.Projective). ClusteringEngine's
// clusters are computed once (its inputs are rest positions); ShapeMatching's targets depend on the
// state's current positions, so the constraint whose `position` links to them computes them each
// time it projects (SOFA reads the link then, which re-runs the engine on the new positions).
#include "penalty/mechanics/shape_matching.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <memory>
#include <optional>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

std::vector<Vec3> points_or_link(SceneBuilder& b, const Attributes& a, std::string_view attr) {
    if (!a.has(attr)) return {};
    return b.point_data(a, attr);
}

/// SOFA's getContext()->get(topo): the topology of the node, else of the nearest ancestor.
const MeshTopology* context_topology(SceneBuilder& b, const NodeBuild& info) {
    for (const io::SceneNode* sn = info.scene_node; sn != nullptr; sn = sn->parent) {
        const auto it = b.node_builds().find(sn);
        if (it != b.node_builds().end() && it->second.topology != nullptr) return it->second.topology;
    }
    return nullptr;
}

// ---- ClusteringEngine -------------------------------------------------------------------------
// Defaults: ClusteringEngine's constructor.
constexpr AttributeSpec kClustering[] = {
    {"position", K::points, "", "m", ValueCheck::none, "rest positions to cluster (inline or a link)"},
    {"useTopo", K::boolean, "1", "", ValueCheck::none, "geodesic neighbourhoods along the context topology's edges"},
    {"radius", K::real, "1", "m", ValueCheck::nonnegative, "neighbourhood range"},
    {"fixedRadius", K::real, "1", "m", ValueCheck::nonnegative, "range for the fixed (non-mechanical) points"},
    {"number", K::integer, "-1", "", ValueCheck::none, "number of clusters (-1: one per point)"},
    {"fixedPosition", K::points, "", "m", ValueCheck::none, "fixed (non-mechanical) points"},
    {"inFile", K::text, "", "", ValueCheck::none, "precomputed clusters (not read by penalty)"},
    {"outFile", K::text, "", "", ValueCheck::none, "cluster export (not written by penalty)"},
};

void build_clustering(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    require_vec3_template(c);
    for (const char* file : {"inFile", "outFile"})
        if (a.has(file)) a.fail(file, "cluster files are not supported: penalty computes the clusters");
    std::vector<std::vector<PointId>> clusters;
    b.guarded(c, [&] {
        if (!a.has("position")) io::throw_element_error(c, "needs its rest positions: give `position`");
        ClusteringParameters p;
        p.use_topology = a.boolean("useTopo");
        p.radius = a.real("radius");
        p.fixed_radius = a.real("fixedRadius");
        const std::int64_t number = a.integer("number");
        if (number < -1) a.fail("number", "must be -1 (every point) or a count >= 0");
        p.number = static_cast<int>(std::min<std::int64_t>(number, 1 << 30));
        const MeshTopology* topology = context_topology(b, info);
        clusters = clustering_engine(points_or_link(b, a, "position"),
                                     topology != nullptr ? &topology->vertices_around_vertex() : nullptr, p,
                                     points_or_link(b, a, "fixedPosition"));
    });
    const std::size_t n = clusters.size();
    b.record_engine_index_lists(c, "cluster", std::move(clusters));
    b.role(c, [n] { return "groups points into " + counted(n, "cluster", "clusters") + " (cluster)"; });
    b.note_unread_attributes(c);
}

// ---- ShapeMatching ----------------------------------------------------------------------------
constexpr AttributeSpec kShapeMatching[] = {
    {"position", K::link, "", "", ValueCheck::none, "the current positions: a link to a Vec3d state's position"},
    {"cluster", K::link, "", "", ValueCheck::none, "the clusters: a link to a ClusteringEngine's cluster"},
    {"iterations", K::integer, "1", "", ValueCheck::nonnegative, "shape matching passes per update"},
    {"affineRatio", K::real, "0", "", ValueCheck::none, "blending of the affine fit (1) and the rigid one (0)"},
    {"fixedweight", K::real, "1", "", ValueCheck::none, "weight of the fixed (non-mechanical) points"},
    {"fixedPosition0", K::points, "", "m", ValueCheck::none, "rest positions of the fixed points"},
    {"fixedPosition", K::points, "", "m", ValueCheck::none, "current positions of the fixed points"},
};

/// A ShapeMatching component as the constraint reading it uses it: the state whose current
/// positions it reads, the state whose rest positions it matches (its context's), its clusters.
struct ShapeMatchingSource {
    Vec3Object* current = nullptr;
    Vec3Object* rest = nullptr;
    std::vector<std::vector<PointId>> clusters;
    ShapeMatchingParameters params;
    std::vector<Vec3> fixed_rest, fixed;
};

ShapeMatchingSource shape_matching_source(SceneBuilder& b, const SceneComponent& c) {
    const Attributes a(c);
    ShapeMatchingSource s;
    s.rest = &b.vec3_state(c, b.node_build(*c.node));
    if (!a.has("position"))
        io::throw_element_error(c, "needs the current positions: give `position=\"@dofs.position\"`");
    s.current = dynamic_cast<Vec3Object*>(b.linked_state(a, "position"));
    if (s.current == nullptr) a.fail("position", "must link to a Vec3d MechanicalObject's position built before");
    if (!a.has("cluster")) io::throw_element_error(c, "needs its clusters: give `cluster=\"@clustering.cluster\"`");
    const io::LinkTarget t = a.link("cluster");
    const auto* lists = t.component != nullptr ? b.engine_index_lists(*t.component, t.data) : nullptr;
    if (lists == nullptr) a.fail("cluster", "must link to a ClusteringEngine's cluster (@clustering.cluster)");
    s.clusters = *lists;
    s.params.iterations = static_cast<unsigned>(a.integer("iterations"));
    s.params.affine_ratio = a.real("affineRatio");
    s.params.fixed_weight = a.real("fixedweight");
    s.fixed_rest = points_or_link(b, a, "fixedPosition0");
    s.fixed = points_or_link(b, a, "fixedPosition");
    if (s.current->num_dofs() != s.rest->num_dofs())
        a.fail("position", "links to " + std::to_string(s.current->num_dofs()) + " points, but the context state has " +
                               std::to_string(s.rest->num_dofs()));
    // the checks of the clusters and of the fixed points, on the positions as loaded
    b.guarded(c, [&] { (void)ShapeMatching(s.clusters, s.rest->position, s.params, s.fixed_rest, s.fixed); });
    return s;
}

/// SOFA's ObjectFactory makes a ShapeMatching without a template (or with Rigid3d) the Rigid3d one,
/// whose doUpdate is empty and which finds no Rigid3d state beside a Vec3d one: its targetPosition
/// stays empty (ShapeMatching<Rigid3Types>::doUpdate).
bool is_sofa_rigid_shape_matching(const SceneComponent& c) {
    return c.template_name.empty() || is_rigid_template(c, c.template_name);
}
constexpr const char* kRigidShapeMatchingNote =
    " has no template, which SOFA makes Rigid3d (an empty doUpdate): no target positions, so the "
    "constraint does nothing, as in SOFA (write template=\"Vec3\" for shape matching)";

void build_shape_matching(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    if (is_sofa_rigid_shape_matching(c)) {
        b.role(c, [] { return std::string("computes nothing (Rigid3d in SOFA: template not Vec3)"); });
        b.note_unread_attributes(c);
        return;
    }
    const ShapeMatchingSource s = shape_matching_source(b, c);
    b.role(c, [n = s.clusters.size()] { return "matches " + counted(n, "cluster", "clusters") + " (targetPosition)"; });
    b.note_unread_attributes(c);
}

// ---- PositionBasedDynamicsProjectiveConstraint ------------------------------------------------
constexpr AttributeSpec kPositionBasedDynamics[] = {
    {"position", K::points, "", "m", ValueCheck::none,
     "target positions (inline, a link to positions, or to a ShapeMatching's targetPosition)"},
    {"stiffness", K::real, "1", "", ValueCheck::none, "blending of the current (0) and target (1) positions"},
};

/// The targets of `position`: a ShapeMatching's, computed from its state's positions each time
/// they are read (the rest data taken at the first read, SOFA's ShapeMatching::init), or fixed points.
TargetPositions target_positions(SceneBuilder& b, const Attributes& a, std::size_t state_size) {
    if (!a.has("position")) io::throw_element_error(a.component(), "needs its target positions: give `position`");
    if (a.is_link("position")) {
        const io::LinkTarget t = a.link("position");
        if (t.component != nullptr && t.component->type == "ShapeMatching") {
            if (t.data != "targetPosition") a.fail("position", "reads a ShapeMatching's targetPosition only");
            b.build_data_engine(*t.component);
            if (is_sofa_rigid_shape_matching(*t.component)) {
                b.warn(a.component().describe() + ": " + t.component->describe() + kRigidShapeMatchingNote);
                return nullptr;  // no targets: SOFA's projections report a size error and do nothing
            }
            auto s = std::make_shared<ShapeMatchingSource>(shape_matching_source(b, *t.component));
            if (s->current->num_dofs() != state_size)
                a.fail("position", "gives " + std::to_string(s->current->num_dofs()) + " targets for a state of " +
                                       std::to_string(state_size) + " points");
            auto matcher = std::make_shared<std::optional<ShapeMatching>>();
            return [s, matcher](const std::vector<Vec3>&, std::vector<Vec3>& out) {
                if (!matcher->has_value())
                    matcher->emplace(s->clusters, s->rest->rest_position, s->params, s->fixed_rest, s->fixed);
                (*matcher)->targets(s->current->position, out);
            };
        }
    }
    std::vector<Vec3> fixed = points_or_link(b, a, "position");
    if (fixed.size() != state_size)
        a.fail("position", "gives " + std::to_string(fixed.size()) + " targets for a state of " +
                               std::to_string(state_size) + " points");
    return [fixed = std::move(fixed)](const std::vector<Vec3>&, std::vector<Vec3>& out) { out = fixed; };
}

void build_position_based_dynamics(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    require_vec3_template(c);
    Vec3Object& state = b.vec3_state(c, info);
    TargetPositions targets = target_positions(b, a, state.num_dofs());
    const double stiffness = a.real("stiffness");
    auto& f = info.node->add_constraint<PositionBasedDynamicsConstraint>(state, std::move(targets), stiffness,
                                                                         [node = info.node] { return node->dt(); });
    b.record_origin(&f, c);
    b.add_init(1, c, [p = &f] { p->init(); });
    b.role(c, [stiffness] { return "moves the points toward their targets (stiffness " + num(stiffness) + ")"; });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kShapeMatchingComponents[] = {
    {.type = "ClusteringEngine",
     .family = F::data_engine,
     .summary = "overlapping clusters of points (farthest-point seeds, geodesic or Euclidean neighbourhoods)",
     .attributes = kClustering,
     .build = build_clustering},
    {.type = "ShapeMatching",
     .family = F::data_engine,
     .summary = "per-cluster best rigid (or affine-blended) fit of the rest shape: targetPosition",
     .attributes = kShapeMatching,
     .build = build_shape_matching},
    {.type = "PositionBasedDynamicsProjectiveConstraint",
     .family = F::constraint,
     .summary = "positions moved toward target positions after each step, velocities from the motion",
     .attributes = kPositionBasedDynamics,
     .build = build_position_based_dynamics},
};

}  // namespace

std::span<const ComponentSpec> shape_matching_components() { return kShapeMatchingComponents; }

}  // namespace penalty::scene::builder
