// Collision: the six collision models, the intersection methods, the contact manager, and the
// pipelines (CollisionPipeline, CompositeCollisionPipeline with its SubCollisionPipelines),
// which are built once every node is (they gather the models below them).
#include "penalty/response/collision_response.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>
#include <sstream>

namespace penalty::scene {

namespace builder {
namespace {

using io::SceneComponent;
using io::SceneNode;
using K = AttributeKind;
using F = ComponentFamily;

// ---- collision models ---------------------------------------------------------------------------
/// SOFA's CollisionModel Data every model reads (CollisionModelParams).
constexpr AttributeSpec kModelCommon[] = {
    {"active", K::boolean, "1", "", ValueCheck::none, "excluded from detection when 0"},
    {"moving", K::boolean, "1", "", ValueCheck::none, "0: normals computed once"},
    {"simulated", K::boolean, "1", "", ValueCheck::none, "pairs of two non-simulated models are skipped"},
    {"selfCollision", K::boolean, "0", "", ValueCheck::none, "models of one node collide only if 1"},
    {"proximity", K::real, "0", "m", ValueCheck::nonnegative,
     "alias of contactDistance; when both are written, proximity's value is used (SOFA's parse order)"},
    {"contactDistance", K::real, "0", "m", ValueCheck::nonnegative, "added to the method's distances"},
    {"contactStiffness", K::real, "10", "N/m", ValueCheck::nonnegative, "k of the pair: k1 k2 / distance"},
    {"contactFriction", K::real, "0", "", ValueCheck::nonnegative, "summed into the pair's mu"},
    {"contactRestitution", K::real, "0", "", ValueCheck::nonnegative, "unused by the penalty response"},
    {"contactResponse", K::text, "", "", ValueCheck::none, "response of this model's pairs"},
    {"group", K::indices, "", "", ValueCheck::none, "models sharing a group never collide"},
    {"bothSide", K::boolean, "0", "", ValueCheck::none, "contacts on both sides of the surface"},
};
constexpr AttributeSpec kTopologyLink[] = {
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "MeshTopology or RegularGridTopology"},
};
constexpr AttributeSpec kTriangleModel[] = {
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "MeshTopology or RegularGridTopology"},
    {"computeNormals", K::boolean, "1", "", ValueCheck::none, "0: normals stay those of the first step"},
};
constexpr AttributeSpec kTriangleOctreeModel[] = {
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "MeshTopology or RegularGridTopology"},
    {"computeNormals", K::boolean, "1", "", ValueCheck::none, "0: normals stay those of the first step"},
    {"drawOctree", K::boolean, "0", "", ValueCheck::none, "visual only (ignored)"},
};
constexpr AttributeSpec kSphereModel[] = {
    {"radius", K::real, "1", "m", ValueCheck::positive, "of every sphere"},
    {"listRadius", K::numbers, "", "m", ValueCheck::none, "one radius per sphere, or a SphereLoader link"},
};
constexpr AttributeSpec kCylinderModel[] = {
    {"defaultRadius", K::real, "0.5", "m", ValueCheck::positive, ""},
    {"defaultHeight", K::real, "2", "m", ValueCheck::positive, ""},
    {"defaultLocalAxis", K::vector3, "0 1 0", "", ValueCheck::none, "axis in the frame"},
    {"radii", K::numbers, "", "m", ValueCheck::none, "one per cylinder"},
    {"heights", K::numbers, "", "m", ValueCheck::none, "one per cylinder"},
    {"localAxes", K::points, "", "", ValueCheck::none, "beyond SOFA: one axis per cylinder"},
};

CollisionModelParams model_params(const Attributes& a, const NodeBuild& info) {
    const SceneComponent& c = a.component();
    CollisionModelParams p;
    p.name = c.name.empty() ? c.type : c.name;
    p.active = a.boolean("active");
    p.moving = a.boolean("moving");
    p.simulated = a.boolean("simulated");
    p.self_collision = a.boolean("selfCollision");
    // `proximity` is an alias of contactDistance (CollisionModel's addAlias): Base::parse sets the
    // Data once per written name in alphabetical order, so proximity wins when both are written
    p.contact_distance = a.real("contactDistance");
    p.contact_distance = a.real_or("proximity", p.contact_distance);
    p.contact_stiffness = a.real("contactStiffness");
    p.contact_friction = a.real("contactFriction");
    p.contact_restitution = a.real("contactRestitution");
    p.contact_response = a.text("contactResponse");
    try {
        check_response_name(p.contact_response);
    } catch (const std::invalid_argument& e) {
        a.fail("contactResponse", e.what());
    }
    for (PointId g : a.indices("group")) p.group.push_back(g);
    p.node = info.node_id;
    p.both_side = a.boolean("bothSide");
    return p;
}

/// What `penalty info` says of a model: elements, flags, stiffness, pipelines.
std::string describe_model(SceneBuilder& b, const CollisionModel& m, const std::string& shape) {
    const CollisionModelParams& p = m.params();
    std::string out = std::to_string(m.size()) + " ";
    switch (m.type()) {
        case ModelType::Point:
            out = counted(m.size(), "point", "points");
            break;
        case ModelType::Line:
            out = counted(m.size(), "edge", "edges");
            break;
        case ModelType::Triangle:
            out = counted(m.size(), "triangle", "triangles");
            break;
        case ModelType::Sphere:
            out = counted(m.size(), "sphere", "spheres");
            break;
        case ModelType::RigidSphere:
            out = counted(m.size(), "rigid sphere", "rigid spheres");
            break;
        case ModelType::Cylinder:
            out = counted(m.size(), "cylinder", "cylinders");
            break;
        case ModelType::Tetrahedron:
            out = counted(m.size(), "tetrahedron", "tetrahedra");
            break;
    }
    out += shape;
    if (!p.simulated && !p.moving) out += ", static obstacle (simulated=0, moving=0)";
    else if (!p.simulated) out += ", not simulated";
    else if (!p.moving) out += ", simulated, not moving";
    else out += ", simulated";
    out += ", contactStiffness " + num(p.contact_stiffness);
    if (p.contact_distance > 0) out += ", contactDistance " + num(p.contact_distance);
    if (p.self_collision) out += ", self-collision";
    if (!p.active) out += ", inactive";
    if (!p.group.empty()) {
        out += ", group";
        for (int g : p.group) {
            out += ' ';
            out += std::to_string(g);
        }
    }
    if (!p.contact_response.empty()) out += ", contactResponse " + p.contact_response;
    std::string in;
    for (const ScenePipeline& sp : b.pipelines())
        for (const SceneCollisionModel* x : sp.models)
            if (x->model.get() == &m) in += (in.empty() ? "" : ", ") + sp.name;
    return out + (in.empty() ? "; in no collision pipeline: never collides" : "; pipeline " + in);
}

/// Registers a built model (its role, its unread attributes) with the scene.
void add_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info, std::unique_ptr<CollisionModel> model,
               const std::string& shape = {}) {
    b.note_unread_attributes(c);
    b.role(c, [&b, m = model.get(), shape] { return describe_model(b, *m, shape); });
    // The model's node for the same-node rule is its own (params().node); the node holding its
    // state may be an ancestor (SceneBuilder::state_owner).
    b.add_collision_model(SceneCollisionModel{std::move(model), b.state_owner(info)->node, &c});
}

/// Builds a model on the node's Vec3d state with `make(state, params)`.
template <class Make>
void build_vec3_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info, Make make) {
    const Attributes a(c);
    BaseState& state = b.state(c, info);
    std::unique_ptr<CollisionModel> model;
    b.guarded(c, [&] {
        const CollisionModelParams p = model_params(a, info);
        auto* v = dynamic_cast<Vec3Object*>(&state);
        if (!v) io::throw_element_error(c, "needs a Vec3d MechanicalObject");
        model = make(a, *v, p);
    });
    add_model(b, c, info, std::move(model));
}

void build_point_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_vec3_model(b, c, info, [&](const Attributes& a, Vec3Object& v, const CollisionModelParams& p) {
        return std::make_unique<PointModel>(v, a.has("topology") ? &b.topology_of(a, info) : info.topology, p);
    });
}
void build_line_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_vec3_model(b, c, info, [&](const Attributes& a, Vec3Object& v, const CollisionModelParams& p) {
        return std::make_unique<LineModel>(v, b.topology_of(a, info), p);
    });
}
void build_triangle_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_vec3_model(b, c, info, [&](const Attributes& a, Vec3Object& v, const CollisionModelParams& p) {
        auto m = std::make_unique<TriangleModel>(v, b.topology_of(a, info), p);
        m->compute_normals = a.boolean("computeNormals");
        return m;
    });
}
void build_tetrahedron_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_vec3_model(b, c, info, [&](const Attributes& a, Vec3Object& v, const CollisionModelParams& p) {
        return std::make_unique<TetrahedronModel>(v, b.topology_of(a, info), p);
    });
}

void build_sphere_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& state = b.state(c, info);
    std::unique_ptr<CollisionModel> model;
    b.guarded(c, [&] {
        const CollisionModelParams p = model_params(a, info);
        auto* v = dynamic_cast<Vec3Object*>(&state);
        auto* r = dynamic_cast<Rigid3Object*>(&state);
        const double radius = a.real("radius");
        std::vector<double> list;
        if (a.is_link("listRadius")) {
            const io::LinkTarget t = a.link("listRadius");
            if (t.component == nullptr || component_category(t.component->type) != ComponentCategory::loader)
                a.fail("listRadius", "must link to a SphereLoader's listRadius");
            list = b.mesh_of(*t.component).radii;
        } else if (a.has("listRadius")) {
            list = a.numbers("listRadius");
        }
        for (double x : list)
            if (!(x > 0)) a.fail("listRadius", "radii must be > 0");
        const bool want_rigid = is_rigid_template(c, c.template_name) || (c.template_name.empty() && r != nullptr);
        if (want_rigid) {
            if (!r) io::throw_element_error(c, "template Rigid3d needs a Rigid3d MechanicalObject");
            model = std::make_unique<RigidSphereModel>(*r, radius, std::move(list), p);
        } else {
            if (!v) io::throw_element_error(c, "needs a Vec3d MechanicalObject (or template=\"Rigid3d\")");
            model = std::make_unique<SphereModel>(*v, radius, std::move(list), p);
        }
    });
    add_model(b, c, info, std::move(model),
              a.has("listRadius") ? ", radii from listRadius" : ", radius " + num(a.real("radius")));
}

void build_cylinder_model(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& state = b.state(c, info);
    std::unique_ptr<CollisionModel> model;
    b.guarded(c, [&] {
        const CollisionModelParams p = model_params(a, info);
        auto* r = dynamic_cast<Rigid3Object*>(&state);
        if (!r) io::throw_element_error(c, "needs a Rigid3d MechanicalObject");
        const double radius = a.real("defaultRadius");
        const double height = a.real("defaultHeight");
        auto m = std::make_unique<CylinderModel>(*r, radius, height, a.vector3("defaultLocalAxis"), p);
        m->radii = a.numbers("radii");
        m->heights = a.numbers("heights");
        m->local_axes = a.points("localAxes");  // beyond SOFA (no scene name there)
        model = std::move(m);
    });
    add_model(b, c, info, std::move(model));
}

// ---- intersection methods -------------------------------------------------------------------------
constexpr AttributeSpec kBeyondSofa[] = {
    {"beyondSofaPairs", K::boolean, "0", "", ValueCheck::none,
     "beyond SOFA: detect the pairs SOFA has no intersector for"},
    {"fixSofaQuirks", K::text, "", "", ValueCheck::none, "beyond SOFA: names of SOFA bugs to fix (or all)"},
    {"zeroDistanceNormal", K::text, "fallbackX", "", ValueCheck::none, "fallbackX, drop or sofaNaN"},
};
constexpr AttributeSpec kNewProximity[] = {
    {"alarmDistance", K::real, "1", "m", ValueCheck::nonnegative, "pairs closer than this are contacts"},
    {"contactDistance", K::real, "0.5", "m", ValueCheck::nonnegative, "rest distance of a contact, <= alarmDistance"},
    {"useLineLine", K::boolean, "0", "", ValueCheck::none, "Line-Line pairs"},
};
constexpr AttributeSpec kMinProximity[] = {
    {"alarmDistance", K::real, "1", "m", ValueCheck::nonnegative, "pairs closer than this are contacts"},
    {"contactDistance", K::real, "0.5", "m", ValueCheck::nonnegative, "rest distance of a contact, <= alarmDistance"},
    {"useLineLine", K::boolean, "1", "", ValueCheck::none, "Line-Line pairs"},
    {"useSphereTriangle", K::boolean, "1", "", ValueCheck::none, "Sphere vs Point, Line, Triangle pairs"},
    {"usePointPoint", K::boolean, "1", "", ValueCheck::none, "Point-Point pairs"},
    {"useLinePoint", K::boolean, "1", "", ValueCheck::none, "Line-Point pairs"},
    {"useSurfaceNormals", K::boolean, "0", "", ValueCheck::none, "Triangle-Point normal: the triangle's"},
};
constexpr AttributeSpec kLocalMinDistance[] = {
    {"alarmDistance", K::real, "1", "m", ValueCheck::nonnegative, "pairs closer than this are contacts"},
    {"contactDistance", K::real, "0.5", "m", ValueCheck::nonnegative, "rest distance of a contact, <= alarmDistance"},
    {"filterIntersection", K::boolean, "1", "", ValueCheck::none, "cone filters of the closest features"},
    {"angleCone", K::real, "0", "rad", ValueCheck::nonnegative, "extra cone angle"},
    {"coneFactor", K::real, "0.5", "", ValueCheck::nonnegative, "cone of the points' neighbours"},
    {"useLMDFilters", K::boolean, "0", "", ValueCheck::none, "skip the built-in validity filters"},
};

/// The accepted quirk names, for error messages.
std::string quirk_choices() {
    std::string out = "known: all";
    for (const SofaQuirkInfo& q : sofa_quirk_table()) out += ", " + std::string(q.name);
    return out;
}

/// The beyond-SOFA switches every method reads, then the command line's quirk fixes.
void read_beyond_sofa(SceneBuilder& b, const Attributes& a, IntersectionParams& p) {
    p.enable_beyond_sofa_pairs = a.boolean("beyondSofaPairs");
    std::istringstream words(a.text("fixSofaQuirks"));
    for (std::string w; words >> w;)
        if (!enable_sofa_quirk_fix(p.quirks, w))
            a.fail("fixSofaQuirks", "unknown SOFA quirk '" + w + "' (" + quirk_choices() + ")");
    if (a.has("zeroDistanceNormal")) {
        const std::string policy = a.text("zeroDistanceNormal");
        if (policy == "fallbackX") p.quirks.zero_distance_normal = ZeroDistanceNormal::FallbackX;
        else if (policy == "drop") p.quirks.zero_distance_normal = ZeroDistanceNormal::Drop;
        else if (policy == "sofaNaN") p.quirks.zero_distance_normal = ZeroDistanceNormal::SofaNaN;
        else a.fail("zeroDistanceNormal", "expected fallbackX, drop or sofaNaN");
    }
    p.quirks = merge_sofa_quirk_fixes(p.quirks, b.options().sofa_quirk_fixes);
    p.validate();
}

/// Reads a method's parameters (starting from `p`, the library's for the method) and records them.
template <class ReadOwn>
void build_intersection(SceneBuilder& b, const SceneComponent& c, IntersectionParams p, ReadOwn read_own) {
    const Attributes a(c);
    b.guarded(c, [&] {
        if (find_attribute(*find_component(c.type), "alarmDistance") != nullptr) {  // not DiscreteIntersection
            p.alarm_distance = a.real("alarmDistance");
            p.contact_distance = a.real("contactDistance");
            if (p.contact_distance > p.alarm_distance) a.fail("contactDistance", "must not exceed alarmDistance");
        }
        read_own(a, p);
        read_beyond_sofa(b, a, p);
    });
    b.add_intersection(c, p);
    b.note_unread_attributes(c);
}

void build_new_proximity(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    build_intersection(b, c, IntersectionParams::new_proximity(),
                       [](const Attributes& a, IntersectionParams& p) { p.use_line_line = a.boolean("useLineLine"); });
}
void build_min_proximity(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    build_intersection(b, c, IntersectionParams::min_proximity(), [](const Attributes& a, IntersectionParams& p) {
        p.use_line_line = a.boolean("useLineLine");
        p.use_sphere_triangle = a.boolean("useSphereTriangle");
        p.use_point_point = a.boolean("usePointPoint");
        p.use_line_point = a.boolean("useLinePoint");
        p.use_surface_normals = a.boolean("useSurfaceNormals");
    });
}
void build_local_min_distance(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    build_intersection(b, c, IntersectionParams::local_min_distance(), [](const Attributes& a, IntersectionParams& p) {
        p.filter_intersection = a.boolean("filterIntersection");  // SOFA's LocalMinDistance Data and defaults
        p.angle_cone = a.real("angleCone");
        p.cone_factor = a.real("coneFactor");
        p.use_lmd_filters = a.boolean("useLMDFilters");
    });
}
void build_discrete(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    build_intersection(b, c, IntersectionParams::discrete(), [](const Attributes&, IntersectionParams&) {});
}

// ---- pipelines and their parts --------------------------------------------------------------------
constexpr AttributeSpec kResponse[] = {
    {"response", K::text, "PenalityContactForceField", "", ValueCheck::none, "contact response; \"\": none"},
    {"responseParams", K::text, "", "", ValueCheck::none, "name=value pairs (e.g. damping=0.1&mu=0.5)"},
};
constexpr AttributeSpec kPipeline[] = {
    {"depth", K::integer, "6", "", ValueCheck::none,
     "depth of SOFA's bounding trees (the order of the contacts; negative: 6)"},
};
constexpr AttributeSpec kComposite[] = {
    {"subCollisionPipelines", K::links, "", "", ValueCheck::none, "SubCollisionPipeline components"},
};
constexpr AttributeSpec kSubPipeline[] = {
    {"collisionModels", K::links, "", "", ValueCheck::none, "the models it detects"},
    {"broadPhaseDetection", K::link, "", "", ValueCheck::none, "BruteForceBroadPhase"},
    {"narrowPhaseDetection", K::link, "", "", ValueCheck::none, "BVHNarrowPhase"},
    {"intersectionMethod", K::link, "", "", ValueCheck::none, "intersection method"},
    {"contactManager", K::link, "", "", ValueCheck::none, "CollisionResponse"},
    {"depth", K::integer, "6", "", ValueCheck::none, "depth of SOFA's bounding trees (the order of the contacts)"},
};

// Beyond SOFA: the tunnelling guard (docs/no-tunnelling.md), read by collision_pipelines.cpp.
constexpr AttributeSpec kNoTunnelling[] = {
    {"noTunnelling", K::text, "off", "", ValueCheck::none,
     "beyond SOFA: tunnelling guard off, warn (report crossings), substep or stiffen (prevent them)"},
    {"noTunnellingMaxHalvings", K::integer, "6", "", ValueCheck::positive,
     "substep/stiffen: a step is split into at most 2^this solves (1 to 16)"},
    {"noTunnellingStiffenFraction", K::real, "0.5", "", ValueCheck::positive,
     "stiffen: contacts deeper than this fraction of their rest distance are stiffened (below 1)"},
    {"noTunnellingMaxStiffening", K::real, "10000", "", ValueCheck::positive,
     "largest factor the stiffening law gives a contact stiffness (>= 1)"},
};

void build_pipeline(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    b.add_pipeline_component(c);
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kCollisionComponents[] = {
    {.type = "CollisionPipeline",
     .family = F::collision_pipeline,
     .summary = "collision pipeline (broad phase, narrow phase, response)",
     .attributes = kPipeline,
     .shared_attributes = kNoTunnelling,
     .build = build_pipeline},
    {.type = "CompositeCollisionPipeline",
     .family = F::composite_pipeline,
     .summary = "runs several SubCollisionPipelines",
     .attributes = kComposite,
     .shared_attributes = kNoTunnelling,
     .build = build_pipeline},
    {.type = "SubCollisionPipeline",
     .family = F::sub_pipeline,
     .summary = "collision pipeline restricted to listed models",
     .attributes = kSubPipeline,
     .build = note_unread_attributes_only},
    {.type = "BruteForceBroadPhase",
     .family = F::broad_phase,
     .summary = "broad phase over all model pairs",
     .build = note_unread_attributes_only},
    {.type = "BVHNarrowPhase",
     .family = F::narrow_phase,
     .summary = "bounding-volume narrow phase",
     .build = note_unread_attributes_only},
    {.type = "RayTraceNarrowPhase",
     .family = F::narrow_phase,
     .summary = "ray-cast narrow phase between TriangleOctreeCollisionModel surfaces",
     .build = note_unread_attributes_only},
    {.type = "CollisionResponse",
     .family = F::contact_manager,
     .summary = "contact manager (response=PenalityContactForceField)",
     .attributes = kResponse,
     .build = note_unread_attributes_only},
    {.type = "MinProximityIntersection",
     .family = F::intersection,
     .summary = "proximity intersection (MinProximity)",
     .attributes = kMinProximity,
     .shared_attributes = kBeyondSofa,
     .build = build_min_proximity},
    {.type = "NewProximityIntersection",
     .family = F::intersection,
     .summary = "proximity intersection (NewProximity)",
     .attributes = kNewProximity,
     .shared_attributes = kBeyondSofa,
     .build = build_new_proximity},
    {.type = "DiscreteIntersection",
     .family = F::intersection,
     .summary = "discrete (overlap-only) intersection",
     .shared_attributes = kBeyondSofa,
     .build = build_discrete},
    {.type = "LocalMinDistance",
     .family = F::intersection,
     .summary = "proximity intersection (LocalMinDistance)",
     .attributes = kLocalMinDistance,
     .shared_attributes = kBeyondSofa,
     .build = build_local_min_distance},
    {.type = "PointCollisionModel",
     .family = F::collision_model,
     .summary = "point collision model",
     .attributes = kTopologyLink,
     .shared_attributes = kModelCommon,
     .build = build_point_model},
    {.type = "LineCollisionModel",
     .family = F::collision_model,
     .summary = "edge collision model",
     .attributes = kTopologyLink,
     .shared_attributes = kModelCommon,
     .build = build_line_model},
    {.type = "TriangleCollisionModel",
     .family = F::collision_model,
     .summary = "triangle collision model",
     .attributes = kTriangleModel,
     .shared_attributes = kModelCommon,
     .build = build_triangle_model},
    {.type = "TriangleOctreeCollisionModel",
     .family = F::collision_model,
     .summary = "triangle collision model with an octree (RayTraceNarrowPhase)",
     .attributes = kTriangleOctreeModel,
     .shared_attributes = kModelCommon,
     .build = build_triangle_model},
    {.type = "SphereCollisionModel",
     .family = F::collision_model,
     .summary = "sphere collision model (Vec3d or Rigid3d)",
     .attributes = kSphereModel,
     .shared_attributes = kModelCommon,
     .build = build_sphere_model},
    {.type = "CylinderCollisionModel",
     .family = F::collision_model,
     .summary = "cylinder collision model (Rigid3d)",
     .attributes = kCylinderModel,
     .shared_attributes = kModelCommon,
     .build = build_cylinder_model},
    {.type = "TetrahedronCollisionModel",
     .family = F::collision_model,
     .summary = "tetrahedron collision model",
     .attributes = kTopologyLink,
     .shared_attributes = kModelCommon,
     .build = build_tetrahedron_model},
};

}  // namespace

std::span<const ComponentSpec> collision_components() { return kCollisionComponents; }

}  // namespace builder

}  // namespace penalty::scene
