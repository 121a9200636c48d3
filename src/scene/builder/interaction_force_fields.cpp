// Force fields between a Vec3d state and a Rigid3d frame (docs/components/interaction_ellipsoid.md):
// InteractionEllipsoidForceField.
#include "penalty/mechanics/interaction_ellipsoid.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- InteractionEllipsoidForceField ----------------------------------------------------------
// Defaults: InteractionEllipsoidForceField's constructor.
constexpr AttributeSpec kInteractionEllipsoid[] = {
    {"object1", K::link, "(the node's state)", "", ValueCheck::none, "Vec3d points pushed by the ellipsoids"},
    {"object2", K::link, "(the node's state)", "", ValueCheck::none,
     "Rigid3d state whose frame carries the ellipsoids"},
    {"center", K::numbers, "", "m", ValueCheck::none, "ellipsoid centers in the frame (3 numbers each)"},
    {"vradius", K::numbers, "", "m", ValueCheck::none, "ellipsoid radii (3 non-zero numbers each)"},
    {"stiffness", K::real, "500", "N", ValueCheck::none, "> 0 pushes points out, < 0 holds them in"},
    {"damping", K::real, "5", "N.s/m", ValueCheck::none, "times the penetration depth"},
    {"object2_dof_index", K::integer, "0", "", ValueCheck::nonnegative, "the frame of object2 that carries them"},
    {"object2_forces", K::boolean, "1", "", ValueCheck::none, "the frame receives the opposite force"},
    {"object2_invert", K::boolean, "0", "", ValueCheck::none, "the inverse of the frame is used"},
    {"color", K::text, "0 0.5 1 1", "", ValueCheck::none, "display only"},
    {"draw", K::boolean, "1", "", ValueCheck::none, "display only"},
};

std::vector<Vec3> triples(const Attributes& a, std::string_view name) {
    const std::vector<double> v = a.has(name) ? a.numbers(name) : std::vector<double>{};
    if (v.size() % 3 != 0) a.fail(name, "needs 3 numbers per ellipsoid, found " + std::to_string(v.size()));
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < v.size(); i += 3) out.emplace_back(v[i], v[i + 1], v[i + 2]);
    return out;
}

void build_interaction_ellipsoid(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    if (!c.template_name.empty() && c.template_name != "Vec3,Rigid3" && c.template_name != "Vec3d,Rigid3d")
        io::throw_element_error(c, "template '" + c.template_name + "' is not supported (Vec3,Rigid3 only)");
    InteractionEllipsoidParameters p;
    p.centers = triples(a, "center");
    p.radii = triples(a, "vradius");
    for (const Vec3& r : p.radii)
        if ((r.array() == 0.0).any()) a.fail("vradius", "radii must be non-zero");
    p.stiffness = a.real("stiffness");
    p.damping = a.real("damping");
    p.frame_index = static_cast<Index>(a.integer("object2_dof_index"));
    p.object2_forces = a.boolean("object2_forces");
    p.object2_invert = a.boolean("object2_invert");
    static_cast<void>(a.text("color"));
    static_cast<void>(a.boolean("draw"));
    const auto create = [&b, &c, &info, p] {
        const Attributes attributes(c);
        BaseState* s1 = attributes.has("object1") ? b.linked_state(attributes, "object1") : &b.state(c, info);
        BaseState* s2 = attributes.has("object2") ? b.linked_state(attributes, "object2") : &b.state(c, info);
        if (s1 == nullptr) attributes.fail("object1", "links to a state that is not built");
        if (s2 == nullptr) attributes.fail("object2", "links to a state that is not built");
        auto* points = dynamic_cast<Vec3Object*>(s1);
        auto* frames = dynamic_cast<Rigid3Object*>(s2);
        if (points == nullptr) attributes.fail("object1", "must be a Vec3d state");
        if (frames == nullptr) attributes.fail("object2", "must be a Rigid3d state");
        if (static_cast<std::size_t>(p.frame_index) >= frames->num_dofs())
            attributes.fail("object2_dof_index", std::to_string(p.frame_index) + " is out of range (" +
                                                     std::to_string(frames->num_dofs()) + " frames)");
        auto* ff = &info.node->add_force_field<InteractionEllipsoidForceField>(*points, *frames, p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff] {
            const auto& q = ff->parameters();
            return counted(q.centers.size(), "ellipsoid", "ellipsoids") + " on a Rigid3d frame, stiffness " +
                   num(q.stiffness) + " N, damping " + num(q.damping) + " N.s/m" +
                   (q.object2_forces ? "" : ", the frame only read");
        });
    };
    b.build_when_ends_exist(c, a, create);
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kInteractionForceFieldComponents[] = {
    {.type = "InteractionEllipsoidForceField",
     .family = F::force_field,
     .summary = "ellipsoids on a Rigid3d frame pushing Vec3d points",
     .attributes = kInteractionEllipsoid,
     .build = build_interaction_ellipsoid},
};

}  // namespace

std::span<const ComponentSpec> interaction_force_field_components() { return kInteractionForceFieldComponents; }

}  // namespace penalty::scene::builder
