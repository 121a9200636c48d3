// SOFA's geometric and time-dependent projective constraints (docs/components/projective_constraints.md):
// LineProjectiveConstraint, PlaneProjectiveConstraint, DirectionProjectiveConstraint,
// PointProjectiveConstraint, PartialFixedProjectiveConstraint, LinearMovementProjectiveConstraint,
// ParabolicProjectiveConstraint, FixedRotationProjectiveConstraint, AttachProjectiveConstraint.
#include "penalty/mechanics/projective_constraints.hpp"
#include "penalty/mechanics/attach_constraint.hpp"
#include "penalty/mechanics/prescribed_motion_constraints.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

constexpr AttributeSpec kProjectiveTopologyLink = {
    "topology", K::link,          "(the node's topology)",
    "",         ValueCheck::none, "read for topological changes only (penalty's are static)"};

/// The constraint's state with the component's template: Vec3d, or Rigid3d when `rigid_allowed`
/// and the template (or the state) says so.
template <class DataTypes>
MechanicalObject<DataTypes>* typed_state(BaseState& s) {
    return dynamic_cast<MechanicalObject<DataTypes>*>(&s);
}

bool wants_rigid(const SceneComponent& c, BaseState& s, bool rigid_allowed) {
    const bool rigid =
        c.template_name.empty() ? typed_state<Rigid3Types>(s) != nullptr : is_rigid_template(c, c.template_name);
    if (rigid && !rigid_allowed) io::throw_element_error(c, "has no Rigid3d variant in SOFA (Vec3d states only)");
    if (rigid && typed_state<Rigid3Types>(s) == nullptr)
        io::throw_element_error(c, "template Rigid3d on a Vec3d state");
    if (!rigid && typed_state<Vec3Types>(s) == nullptr) io::throw_element_error(c, "template Vec3d on a Rigid3d state");
    return rigid;
}

std::vector<Index> index_list(SceneBuilder& b, const Attributes& a, std::string_view attr,
                              std::vector<Index> fallback) {
    if (!a.has(attr)) return fallback;
    std::vector<Index> out;
    for (PointId i : b.indices(a, attr)) out.push_back(i);
    return out;
}

void finish(SceneBuilder& b, const SceneComponent& c, BaseProjectiveConstraint& constraint, std::string what) {
    b.record_origin(&constraint, c);  // a topological change names it (docs/topological-changes.md)
    b.add_init(1, c, [p = &constraint] { p->init(); });
    b.role(c, [what = std::move(what)] { return what; });
    b.note_unread_attributes(c);
}

std::string points_phrase(std::size_t n) { return counted(n, "point", "points"); }

// ---- Line, Plane, Direction, Point ------------------------------------------------------------
// Defaults: the constructors (indices "0", vectors zero).
constexpr AttributeSpec kLine[] = {
    {"indices", K::indices, "0", "", ValueCheck::none, "points kept on the line"},
    {"origin", K::vector3, "0 0 0", "m", ValueCheck::none, "a point of the line"},
    {"direction", K::vector3, "0 0 0", "", ValueCheck::none, "its direction (normalised; zero: x)"},
    kProjectiveTopologyLink,
};
constexpr AttributeSpec kPlane[] = {
    {"indices", K::indices, "0", "", ValueCheck::none, "points kept on the plane"},
    {"origin", K::vector3, "0 0 0", "m", ValueCheck::none, "a point of the plane"},
    {"normal", K::vector3, "0 0 0", "", ValueCheck::none, "its normal (normalised; zero: no constraint, as SOFA)"},
    kProjectiveTopologyLink,
};
constexpr AttributeSpec kDirection[] = {
    {"indices", K::indices, "0", "", ValueCheck::none, "points moving along the direction only"},
    {"direction", K::vector3, "0 0 0", "", ValueCheck::none, "the direction (normalised; zero: points fixed)"},
    kProjectiveTopologyLink,
};
constexpr AttributeSpec kPoint[] = {
    {"indices", K::indices, "0", "", ValueCheck::none, "points put at `point`"},
    {"point", K::vector3, "0 0 0", "m", ValueCheck::none, "their position"},
    {"fixAll", K::boolean, "0", "", ValueCheck::none, "every point of the state"},
    kProjectiveTopologyLink,
};

void build_line(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    wants_rigid(c, s, false);
    const std::vector<Index> idx = index_list(b, a, "indices", {0});
    auto& f = info.node->add_constraint<LineProjectiveConstraint>(*typed_state<Vec3Types>(s), idx, a.vector3("origin"),
                                                                  a.vector3("direction"));
    finish(b, c, f, "keeps " + points_phrase(idx.size()) + " on the line through " + vec(a.vector3("origin")));
}

void build_plane(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    wants_rigid(c, s, false);
    const std::vector<Index> idx = index_list(b, a, "indices", {0});
    auto& f = info.node->add_constraint<PlaneProjectiveConstraint>(*typed_state<Vec3Types>(s), idx, a.vector3("origin"),
                                                                   a.vector3("normal"));
    finish(b, c, f, "keeps " + points_phrase(idx.size()) + " on the plane of normal " + vec(a.vector3("normal")));
}

void build_direction(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    wants_rigid(c, s, false);
    const std::vector<Index> idx = index_list(b, a, "indices", {0});
    auto& f = info.node->add_constraint<DirectionProjectiveConstraint>(*typed_state<Vec3Types>(s), idx,
                                                                       a.vector3("direction"));
    finish(b, c, f, "moves " + points_phrase(idx.size()) + " along " + vec(a.vector3("direction")) + " only");
}

void build_point(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    wants_rigid(c, s, false);
    const std::vector<Index> idx = index_list(b, a, "indices", {0});
    const bool all = a.boolean("fixAll");
    auto& f =
        info.node->add_constraint<PointProjectiveConstraint>(*typed_state<Vec3Types>(s), idx, a.vector3("point"), all);
    finish(b, c, f, "puts " + (all ? "every point" : points_phrase(idx.size())) + " at " + vec(a.vector3("point")));
}

// ---- PartialFixed -----------------------------------------------------------------------------
constexpr AttributeSpec kPartialFixed[] = {
    {"indices", K::indices, "", "", ValueCheck::none, "constrained DOFs"},
    {"fixAll", K::boolean, "0", "", ValueCheck::none, "every DOF"},
    {"fixedDirections", K::numbers, "(all 1)", "", ValueCheck::none,
     "1 per fixed component (3 for Vec3d, 6 for Rigid3d)"},
    {"projectVelocity", K::boolean, "0", "", ValueCheck::none, "also zero the fixed components of the velocity"},
    kProjectiveTopologyLink,
};

void build_partial_fixed(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    wants_rigid(c, s, true);
    std::vector<bool> fixed(static_cast<std::size_t>(s.deriv_size()), true);
    if (a.has("fixedDirections")) {
        const std::vector<double> flags = a.numbers("fixedDirections");
        if (flags.size() != fixed.size())
            a.fail("fixedDirections", "expected " + std::to_string(fixed.size()) + " flags (0 or 1), found " +
                                          std::to_string(flags.size()));
        for (std::size_t k = 0; k < flags.size(); ++k) {
            if (flags[k] != 0 && flags[k] != 1)
                a.fail("fixedDirections", "flags must be 0 or 1, found " + num(flags[k]));
            fixed[k] = flags[k] != 0;
        }
    }
    const std::vector<Index> idx = index_list(b, a, "indices", {});
    const bool all = a.boolean("fixAll");
    auto& f =
        info.node->add_constraint<PartialFixedProjectiveConstraint>(s, idx, all, fixed, a.boolean("projectVelocity"));
    std::string axes;
    for (bool x : fixed) axes += x ? '1' : '0';
    finish(b, c, f, "fixes components " + axes + " of " + (all ? "every DOF" : counted(idx.size(), "DOF", "DOFs")));
}

// ---- LinearMovement ---------------------------------------------------------------------------
constexpr AttributeSpec kLinearMovement[] = {
    {"indices", K::indices, "0", "", ValueCheck::none, "moved DOFs"},
    {"keyTimes", K::numbers, "0", "s", ValueCheck::none, "key times, ascending"},
    {"movements", K::numbers, "(zero)", "m", ValueCheck::none,
     "a displacement (Vec3d: 3 numbers; Rigid3d: 6, rotation as Euler angles in rad) per key time"},
    {"relativeMovements", K::boolean, "1", "", ValueCheck::none, "movements relative to the initial positions"},
    {"showMovement", K::boolean, "0", "", ValueCheck::none, "display only"},
    kProjectiveTopologyLink,
};

template <class DataTypes>
std::vector<typename DataTypes::Deriv> key_movements(const Attributes& a) {
    using Deriv = typename DataTypes::Deriv;
    if (!a.has("movements")) return {zero_deriv<Deriv>()};
    const std::vector<double> v = a.numbers("movements");
    const std::size_t width = DataTypes::kDerivSize;
    if (v.size() % width != 0)
        a.fail("movements",
               "expected " + std::to_string(width) + " numbers per key movement, found " + std::to_string(v.size()));
    std::vector<Deriv> out(v.size() / width, zero_deriv<Deriv>());
    for (std::size_t k = 0; k < out.size(); ++k)
        std::copy(v.begin() + static_cast<std::ptrdiff_t>(k * width),
                  v.begin() + static_cast<std::ptrdiff_t>((k + 1) * width), reinterpret_cast<double*>(&out[k]));
    return out;
}

template <class DataTypes>
BaseProjectiveConstraint& add_linear_movement(SceneBuilder& b, const Attributes& a, NodeBuild& info, BaseState& s,
                                              std::vector<Index> idx, std::vector<double> times) {
    auto movements = key_movements<DataTypes>(a);
    if (movements.size() < times.size())
        a.fail("movements", std::to_string(times.size()) + " key times need as many movements, found " +
                                std::to_string(movements.size()));
    return info.node->add_constraint<LinearMovementProjectiveConstraint<DataTypes>>(
        *typed_state<DataTypes>(s), std::move(idx), std::move(times), std::move(movements),
        a.boolean("relativeMovements"), [sim = &b.simulation()] { return sim->time(); });
}

void build_linear_movement(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    const bool rigid = wants_rigid(c, s, true);
    static_cast<void>(a.boolean("showMovement"));
    std::vector<double> times = a.has("keyTimes") ? a.numbers("keyTimes") : std::vector<double>{0.0};
    for (std::size_t k = 1; k < times.size(); ++k)
        if (!(times[k] >= times[k - 1])) a.fail("keyTimes", "must be in ascending order (SOFA assumes it)");
    const std::vector<Index> idx = index_list(b, a, "indices", {0});
    const std::size_t keys = times.size();
    BaseProjectiveConstraint& f = rigid ? add_linear_movement<Rigid3Types>(b, a, info, s, idx, std::move(times))
                                        : add_linear_movement<Vec3Types>(b, a, info, s, idx, std::move(times));
    finish(b, c, f, "moves " + counted(idx.size(), "DOF", "DOFs") + " through " + counted(keys, "key", "keys"));
}

// ---- Parabolic --------------------------------------------------------------------------------
constexpr AttributeSpec kParabolic[] = {
    {"indices", K::indices, "", "", ValueCheck::none, "moved DOFs"},
    {"P1", K::vector3, "0 0 0", "m", ValueCheck::none, "start of the parabola"},
    {"P2", K::vector3, "0 0 0", "m", ValueCheck::none, "a point of it"},
    {"P3", K::vector3, "0 0 0", "m", ValueCheck::none, "its end"},
    {"BeginTime", K::real, "0", "s", ValueCheck::none, "start of the motion"},
    {"EndTime", K::real, "0", "s", ValueCheck::none, "end of the motion"},
    kProjectiveTopologyLink,
    // beyond SOFA
    {"velocityForEveryIndex", K::boolean, "0", "", ValueCheck::none,
     "beyond SOFA: every listed DOF gets the parabola's velocity (SOFA's projectVelocity gives it to the first only)"},
};

void build_parabolic(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    const bool rigid = wants_rigid(c, s, true);
    const Vec3 p1 = a.vector3("P1"), p2 = a.vector3("P2"), p3 = a.vector3("P3");
    if (p1 == p2 || p1 == p3 || p2 == p3)
        a.fail(p1 == p2 ? "P2" : "P3", "P1, P2 and P3 must be three distinct points (SOFA divides by zero otherwise)");
    const double begin = a.real("BeginTime"), end = a.real("EndTime");
    if (!(end > begin)) a.fail("EndTime", "must be after BeginTime (" + num(begin) + " s)");
    const std::vector<Index> idx = index_list(b, a, "indices", {});
    ContextClock clock = [sim = &b.simulation()] { return sim->time(); };
    ContextClock dt = [node = info.node] { return node->dt(); };
    const bool every_velocity = a.boolean("velocityForEveryIndex");
    BaseProjectiveConstraint* built = nullptr;
    if (rigid) {
        auto& k = info.node->add_constraint<ParabolicProjectiveConstraint<Rigid3Types>>(
            *typed_state<Rigid3Types>(s), idx, p1, p2, p3, begin, end, clock, dt);
        k.set_every_index_velocity(every_velocity);
        built = &k;
    } else {
        auto& k = info.node->add_constraint<ParabolicProjectiveConstraint<Vec3Types>>(
            *typed_state<Vec3Types>(s), idx, p1, p2, p3, begin, end, clock, dt);
        k.set_every_index_velocity(every_velocity);
        built = &k;
    }
    BaseProjectiveConstraint& f = *built;
    finish(b, c, f,
           "moves " + counted(idx.size(), "DOF", "DOFs") + " on a parabola from " + num(begin) + " s to " + num(end) +
               " s");
}

// ---- FixedRotation ----------------------------------------------------------------------------
constexpr AttributeSpec kFixedRotation[] = {
    {"FixedXRotation", K::boolean, "0", "", ValueCheck::none, "no rotation about the world x axis"},
    {"FixedYRotation", K::boolean, "0", "", ValueCheck::none, "no rotation about y"},
    {"FixedZRotation", K::boolean, "0", "", ValueCheck::none, "no rotation about z"},
};

void build_fixed_rotation(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    auto* rigid = typed_state<Rigid3Types>(s);
    if (rigid == nullptr || (!c.template_name.empty() && !is_rigid_template(c, c.template_name)))
        io::throw_element_error(c, "acts on Rigid3d states only");
    const bool x = a.boolean("FixedXRotation"), y = a.boolean("FixedYRotation"), z = a.boolean("FixedZRotation");
    auto& f = info.node->add_constraint<FixedRotationProjectiveConstraint>(*rigid, x, y, z);
    std::string axes = std::string(x ? "x" : "") + (y ? "y" : "") + (z ? "z" : "");
    finish(b, c, f,
           axes.empty() ? "fixes no rotation" : "keeps the rotations about " + axes + " at their initial value");
}

// ---- Attach -----------------------------------------------------------------------------------
constexpr AttributeSpec kAttach[] = {
    {"object1", K::link, "(the node's state)", "", ValueCheck::none, "state followed"},
    {"object2", K::link, "(the node's state)", "", ValueCheck::none, "state that follows"},
    {"indices1", K::indices, "", "", ValueCheck::none, "DOFs of object1"},
    {"indices2", K::indices, "", "", ValueCheck::none, "DOFs of object2 attached to them"},
    {"twoWay", K::boolean, "0", "", ValueCheck::none, "average both ends' responses (same state only)"},
    {"freeRotations", K::boolean, "0", "", ValueCheck::none, "Rigid3d: rotations left free"},
    {"lastFreeRotation", K::boolean, "0", "", ValueCheck::none, "only false is supported"},
    {"restRotations", K::boolean, "0", "", ValueCheck::none, "only false is supported"},
    {"clamp", K::boolean, "0", "", ValueCheck::none, "only false is supported"},
    {"lastDir", K::vector3, "0 0 0", "", ValueCheck::none, "only zero (no release plane) is supported"},
    {"lastPos", K::vector3, "0 0 0", "m", ValueCheck::none, "read with lastDir only"},
    {"minDistance", K::real, "-1", "m", ValueCheck::none, "release pairs farther apart (-1: never)"},
    {"positionFactor", K::real, "1", "", ValueCheck::none, "Vec3d: share of the position correction"},
    {"velocityFactor", K::real, "1", "", ValueCheck::none, "Vec3d: share of the velocity correction"},
    {"responseFactor", K::real, "1", "", ValueCheck::none, "Vec3d: share of the response correction (twoWay)"},
    {"constraintFactor", K::numbers, "", "", ValueCheck::none, "per pair factor in [0, 1] (Vec3d)"},
};

/// The state a link names, else the node's.
BaseState& linked_state(SceneBuilder& b, const Attributes& a, std::string_view attr, const NodeBuild& info) {
    if (!a.has(attr)) return b.state(a.component(), info);
    const io::LinkTarget t = a.link(attr);
    const io::SceneNode* target = t.node;
    if (t.component != nullptr) {
        if (find_component(t.component->type)->family != F::state)
            a.fail(attr, "must link to a node or a MechanicalObject");
        target = t.component->node;
    }
    if (target == nullptr || b.node_builds().count(target) == 0 || b.node_build(*target).node == nullptr ||
        b.node_build(*target).node->state() == nullptr)
        a.fail(attr, "links to no MechanicalObject built before this component");
    return *b.node_build(*target).node->state();
}

template <class DataTypes>
BaseProjectiveConstraint& add_attach(NodeBuild& info, BaseState& s1, BaseState& s2, AttachParameters p) {
    return info.node->add_constraint<AttachProjectiveConstraint<DataTypes>>(*typed_state<DataTypes>(s1),
                                                                            *typed_state<DataTypes>(s2), std::move(p));
}

void build_attach(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s1 = linked_state(b, a, "object1", info);
    BaseState& s2 = linked_state(b, a, "object2", info);
    const bool rigid = wants_rigid(c, s2, true);
    if ((typed_state<Rigid3Types>(s1) != nullptr) != rigid)
        a.fail("object1", "object1 and object2 must have the same template");
    for (const char* flag : {"lastFreeRotation", "restRotations", "clamp"})
        if (a.boolean(flag)) a.fail(flag, "only false is supported by penalty");
    if (a.vector3("lastDir").norm() > 1.0e-10)
        a.fail("lastDir", "release planes are not supported by penalty (zero only)");
    static_cast<void>(a.vector3("lastPos"));
    AttachParameters p;
    p.indices1 = index_list(b, a, "indices1", {});
    p.indices2 = index_list(b, a, "indices2", {});
    if (p.indices1.size() != p.indices2.size())
        a.fail("indices2", "has " + std::to_string(p.indices2.size()) + " entries for " +
                               std::to_string(p.indices1.size()) +
                               " in indices1 (SOFA pairs the first ones and warns)");
    p.two_way = a.boolean("twoWay");
    if (p.two_way && &s1 != &s2) a.fail("twoWay", "is supported when object1 and object2 are the same state");
    p.free_rotations = a.boolean("freeRotations");
    p.min_distance = a.real("minDistance");
    p.position_factor = a.real("positionFactor");
    p.velocity_factor = a.real("velocityFactor");
    p.response_factor = a.real("responseFactor");
    p.constraint_factor = a.numbers("constraintFactor");
    if (!p.constraint_factor.empty() && p.constraint_factor.size() != p.indices2.size())
        a.fail("constraintFactor", "needs one value per pair (" + std::to_string(p.indices2.size()) + ")");
    const std::size_t pairs = p.indices2.size();
    BaseProjectiveConstraint& f =
        rigid ? add_attach<Rigid3Types>(info, s1, s2, std::move(p)) : add_attach<Vec3Types>(info, s1, s2, std::move(p));
    finish(b, c, f,
           "attaches " + counted(pairs, "DOF", "DOFs") + " of " + std::string(s2.state_name()) + " to " +
               std::string(s1.state_name()));
}

constexpr ComponentSpec kProjectiveConstraintComponents[] = {
    {.type = "LineProjectiveConstraint",
     .family = F::constraint,
     .summary = "points kept on a line",
     .attributes = kLine,
     .build = build_line},
    {.type = "PlaneProjectiveConstraint",
     .family = F::constraint,
     .summary = "points kept on a plane",
     .attributes = kPlane,
     .build = build_plane},
    {.type = "DirectionProjectiveConstraint",
     .family = F::constraint,
     .summary = "points moving along one direction",
     .attributes = kDirection,
     .build = build_direction},
    {.type = "PointProjectiveConstraint",
     .family = F::constraint,
     .summary = "points held at one point",
     .attributes = kPoint,
     .build = build_point},
    {.type = "PartialFixedProjectiveConstraint",
     .family = F::constraint,
     .summary = "DOFs fixed along some axes",
     .attributes = kPartialFixed,
     .build = build_partial_fixed},
    {.type = "LinearMovementProjectiveConstraint",
     .family = F::constraint,
     .summary = "piecewise linear prescribed motion",
     .attributes = kLinearMovement,
     .build = build_linear_movement},
    {.type = "ParabolicProjectiveConstraint",
     .family = F::constraint,
     .summary = "parabolic prescribed motion",
     .attributes = kParabolic,
     .build = build_parabolic},
    {.type = "FixedRotationProjectiveConstraint",
     .family = F::constraint,
     .summary = "rotations about world axes fixed",
     .attributes = kFixedRotation,
     .build = build_fixed_rotation},
    {.type = "AttachProjectiveConstraint",
     .family = F::constraint,
     .summary = "DOFs of one state following another's",
     .attributes = kAttach,
     .build = build_attach},
};

}  // namespace

std::span<const ComponentSpec> projective_constraint_components() { return kProjectiveConstraintComponents; }

}  // namespace penalty::scene::builder
