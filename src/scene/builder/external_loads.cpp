// Mechanical loads (SOFA's Sofa/Component/MechanicalLoad): PlaneForceField, ConstantForceField,
// ConicalForceField, on the node's Vec3d state. Formulas: include/penalty/mechanics/external_loads.hpp
// and docs/components/external_loads.md.
#include "penalty/mechanics/external_loads.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- PlaneForceField ------------------------------------------------------------------------
// Defaults: PlaneForceField's constructor (normal 0 1 0, d 0, stiffness 500, damping 5, maxForce 0,
// bilateral false, localRange -1 -1). Negative stiffness, damping or maxForce: SOFA's init warns
// and uses its default (500, 5, 0); so does penalty.
constexpr AttributeSpec kPlaneForceField[] = {
    {"normal", K::vector3, "0 1 0", "", ValueCheck::none, "plane normal n, used as given (not normalised)"},
    {"d", K::real, "0", "m", ValueCheck::none, "plane offset: points with x.n < d are pushed out"},
    {"stiffness", K::real, "500", "N/m", ValueCheck::none, "k: force -k (x.n - d) n (negative: SOFA uses 500)"},
    {"damping", K::real, "5", "N s/m", ValueCheck::none, "c: force +c (x.n - d) v (negative: SOFA uses 5)"},
    {"maxForce", K::real, "0", "N", ValueCheck::none, "clamp of |f| per point; 0: none"},
    {"bilateral", K::boolean, "0", "", ValueCheck::none, "push points on both sides towards the plane"},
    {"localRange", K::numbers, "-1 -1", "", ValueCheck::none, "first and last point index considered (-1: all)"},
    {"showPlane", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"showPlaneSize", K::real, "10", "m", ValueCheck::none, "display only"},
    {"planeColor", K::text, "0 0.5 0.2 1", "", ValueCheck::none, "display only"},
};

void build_plane_force_field(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    // PlaneForceField<Vec3d> or <Rigid3d> (PlaneForceField.cpp registers both): its state's type
    auto* rigid = dynamic_cast<Rigid3Object*>(&b.state(c, info));
    if (rigid != nullptr && !c.template_name.empty() && !is_rigid_template(c, c.template_name))
        io::throw_element_error(c, "template '" + c.template_name + "' does not match its Rigid3d MechanicalObject");
    if (rigid == nullptr) require_vec3_template(c);
    Vec3Object* s = rigid == nullptr ? &b.vec3_state(c, info) : nullptr;
    b.guarded(c, [&] {
        const PlaneForceFieldParameters defaults;
        PlaneForceFieldParameters p;
        p.normal = a.vector3("normal");
        p.offset = a.real("d");
        // PlaneForceField::init: a negative value is replaced by the default, with a warning
        const auto nonnegative_or_default = [&](std::string_view name, double fallback) {
            const double value = a.real(name);
            if (value >= 0.0) return value;
            b.warn(c.describe() + ": " + std::string(name) + " = " + num(value) + " is negative; SOFA uses " +
                   num(fallback));
            return fallback;
        };
        p.stiffness = nonnegative_or_default("stiffness", defaults.stiffness);
        p.damping = nonnegative_or_default("damping", defaults.damping);
        p.max_force = nonnegative_or_default("maxForce", defaults.max_force);
        p.bilateral = a.boolean("bilateral");
        if (a.has("localRange")) {
            const std::vector<double> range = a.numbers("localRange");
            if (range.size() != 2) a.fail("localRange", "expected 2 indices");
            const std::vector<int> ends = a.as_ints("localRange", range);
            const std::array<int, 2> r = {ends[0], ends[1]};
            // PlaneForceField::init: a set range must be two non-negative indices in order, else none
            if (r[0] < 0 || r[1] < 0 || r[0] > r[1])
                b.warn(c.describe() + ": localRange is not two indices in order; SOFA ignores it");
            else p.local_range = r;
        }
        static_cast<void>(a.boolean("showPlane"));  // display only: read, no effect
        static_cast<void>(a.real("showPlaneSize"));
        static_cast<void>(a.text("planeColor"));
        if (rigid != nullptr) b.record_origin(&info.node->add_force_field<RigidPlaneForceField>(*rigid, p), c);
        else b.record_origin(&info.node->add_force_field<PlaneForceField>(*s, p), c);
        b.role(c, [p] {
            std::string text = "plane x.n = " + num(p.offset) + " m, n = " + vec(p.normal) + ", stiffness " +
                               num(p.stiffness) + " N/m, damping " + num(p.damping) + " N s/m";
            if (p.max_force > 0.0) text += ", max force " + num(p.max_force) + " N";
            if (p.bilateral) text += ", bilateral";
            if (p.local_range[0] >= 0)
                text += ", points " + std::to_string(p.local_range[0]) + ".." + std::to_string(p.local_range[1]);
            return text;
        });
    });
    b.note_unread_attributes(c);
}

// ---- ConstantForceField ---------------------------------------------------------------------
// ConstantForceField's Data: indices (empty: every point), indexFromEnd false, forces, totalForce.
constexpr AttributeSpec kConstantForceField[] = {
    {"indices", K::indices, "(every point)", "", ValueCheck::none,
     "points the forces apply to, or a link @engine.indices"},
    {"forces", K::points, "", "N", ValueCheck::none, "one force per index, or one force for every index"},
    {"totalForce", K::vector3, "", "N", ValueCheck::none, "split evenly over the indices (when no forces)"},
    {"indexFromEnd", K::boolean, "0", "", ValueCheck::none, "index j means point n-1-j"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "accepted (SOFA: its point count)"},
    {"showArrowSize", K::real, "0", "", ValueCheck::none, "display only"},
};

void build_constant_force_field(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    require_vec3_template(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        ConstantForceFieldParameters p;
        if (a.has("indices"))
            for (const PointId i : b.indices(a, "indices")) p.indices.push_back(i);
        if (a.has("forces")) p.forces = a.points("forces");
        p.total_force = a.optional_vector3("totalForce");
        if (p.total_force && a.has("forces"))
            b.warn(c.describe() + ": both forces and totalForce are given; forces are used (SOFA)");
        p.index_from_end = a.boolean("indexFromEnd");
        static_cast<void>(a.real("showArrowSize"));  // display only: read, no effect
        if (a.has("topology")) static_cast<void>(a.link("topology"));
        auto* ff = &info.node->add_force_field<ConstantForceField>(s, std::move(p));
        b.record_origin(ff, c);
        // SOFA makes the component Invalid (no force) when the forces do not number the indices
        // (ConstantForceField::computeForceFromForcesVector): refused in a scene file, taken after
        // a write while the scene runs (until a write makes the counts fit again)
        b.add_init(1, c, [ff, rebuilt = b.rebuilding()] {
            ff->init();
            if (!ff->valid() && !rebuilt)
                throw std::invalid_argument("ConstantForceField: " + std::to_string(ff->forces_data().size()) +
                                            " forces for " + std::to_string(ff->indices().size()) +
                                            " indices (give one force, or one per index; SOFA applies no force)");
        });
        b.role(c, [ff] {
            return "constant force on " + counted(ff->points().size(), "point", "points") + ", total " +
                   vec(ff->total_force()) + " N";
        });
    });
    b.note_unread_attributes(c);
}

// ---- ConicalForceField ----------------------------------------------------------------------
// Defaults: ConicalForceField's constructor (coneCenter and coneHeight 0, coneAngle 10,
// stiffness 500, damping 5).
constexpr AttributeSpec kConicalForceField[] = {
    {"coneCenter", K::vector3, "0 0 0", "m", ValueCheck::none, "apex of the cone"},
    {"coneHeight", K::vector3, "0 0 0", "m", ValueCheck::none, "axis: direction and length (radius of the cap)"},
    {"coneAngle", K::real, "10", "deg", ValueCheck::none, "half-angle"},
    {"stiffness", K::real, "500", "N/m", ValueCheck::none, "k: force k d towards the cone"},
    {"damping", K::real, "5", "N s/m", ValueCheck::none, "c (see docs/components/external_loads.md)"},
    {"color", K::text, "0 0 1 1", "", ValueCheck::none, "display only"},
};

void build_conical_force_field(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    require_vec3_template(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        ConicalForceFieldParameters p;
        p.center = a.vector3("coneCenter");
        p.height = a.vector3("coneHeight");
        p.angle_deg = a.real("coneAngle");
        p.stiffness = a.real("stiffness");
        p.damping = a.real("damping");
        static_cast<void>(a.text("color"));  // display only: read, no effect
        auto* ff = &info.node->add_force_field<ConicalForceField>(s, p);
        b.record_origin(ff, c);
        b.role(c, [p] {
            return "cone apex " + vec(p.center) + " m, axis " + vec(p.height) + " m, half-angle " + num(p.angle_deg) +
                   " deg, stiffness " + num(p.stiffness) + " N/m, damping " + num(p.damping) + " N s/m";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kExternalLoadComponents[] = {
    {.type = "PlaneForceField",
     .family = F::force_field,
     .summary = "pushes points (Vec3d) or frame centres (Rigid3d) back above a plane (penalty)",
     .attributes = kPlaneForceField,
     .build = build_plane_force_field},
    {.type = "ConstantForceField",
     .family = F::force_field,
     .summary = "constant forces on given points",
     .attributes = kConstantForceField,
     .build = build_constant_force_field},
    {.type = "ConicalForceField",
     .family = F::force_field,
     .summary = "pushes points back into a cone (penalty)",
     .attributes = kConicalForceField,
     .build = build_conical_force_field},
};

}  // namespace

std::span<const ComponentSpec> external_load_components() { return kExternalLoadComponents; }

}  // namespace penalty::scene::builder
