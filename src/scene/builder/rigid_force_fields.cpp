// Force fields on Rigid3d frames (docs/components/rigid_force_fields.md): JointSpringForceField
// and BeamFEMForceField.
#include "penalty/mechanics/beam_fem_force_field.hpp"
#include "penalty/mechanics/joint_spring_force_field.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

Rigid3Object& rigid_state(SceneBuilder& b, const SceneComponent& c, const NodeBuild& info) {
    if (!c.template_name.empty() && !is_rigid_template(c, c.template_name))
        io::throw_element_error(c, "acts on Rigid3d states only");
    auto* s = dynamic_cast<Rigid3Object*>(&b.state(c, info));
    if (s == nullptr) io::throw_element_error(c, "needs a Rigid3d MechanicalObject");
    return *s;
}

/// The Rigid3d state a link names (a node or a MechanicalObject), else `fallback`.
Rigid3Object& linked_rigid_state(SceneBuilder& b, const Attributes& a, std::string_view attr, Rigid3Object& fallback) {
    if (!a.has(attr)) return fallback;
    const io::LinkTarget t = a.link(attr);
    const io::SceneNode* target = t.node;
    if (t.component != nullptr) {
        if (find_component(t.component->type)->family != F::state)
            a.fail(attr, "must link to a node or a MechanicalObject");
        target = t.component->node;
    }
    if (target == nullptr || b.node_builds().count(target) == 0 || b.node_build(*target).node == nullptr)
        a.fail(attr, "links to no MechanicalObject built before this component");
    auto* s = dynamic_cast<Rigid3Object*>(b.node_build(*target).node->state());
    if (s == nullptr) a.fail(attr, "must link to a Rigid3d MechanicalObject");
    return *s;
}

// ---- JointSpringForceField --------------------------------------------------------------------
constexpr AttributeSpec kJointSpring[] = {
    {"spring", K::text, "", "", ValueCheck::none,
     "BEGIN_SPRING m1 m2 [FREE_AXIS, KS_T, KS_R, KS_B, KD, R_LIM_X/Y/Z, REST_T, REST_R] END_SPRING, repeated"},
    {"object1", K::link, "(the node's state)", "", ValueCheck::none, "frames m1"},
    {"object2", K::link, "(the node's state)", "", ValueCheck::none, "frames m2"},
    {"infile", K::text, "", "", ValueCheck::none, "constant joint forces from a file: not supported"},
    {"outfile", K::text, "", "", ValueCheck::none, "joint log file: not supported"},
    {"period", K::real, "0", "s", ValueCheck::none, "outfile period (no effect without outfile)"},
    {"reinit", K::boolean, "0", "", ValueCheck::none, "outfile rewriting (no effect without outfile)"},
    {"showLawfulTorsion", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"showExtraTorsion", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"showFactorSize", K::real, "1", "", ValueCheck::none, "display only"},
};

void build_joint_spring(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Rigid3Object& own = rigid_state(b, c, info);
    for (const char* file : {"infile", "outfile"})
        if (a.has(file) && !a.text(file).empty()) a.fail(file, "files are not supported by penalty");
    static_cast<void>(a.real("period"));
    static_cast<void>(a.boolean("reinit"));
    for (const char* flag : {"showLawfulTorsion", "showExtraTorsion"}) static_cast<void>(a.boolean(flag));
    static_cast<void>(a.real("showFactorSize"));
    Rigid3Object& s1 = linked_rigid_state(b, a, "object1", own);
    Rigid3Object& s2 = linked_rigid_state(b, a, "object2", own);
    std::vector<JointSpring> springs;
    try {
        springs = parse_joint_springs(a.text("spring"));
    } catch (const std::invalid_argument& e) {
        std::string what = e.what();
        const std::string prefix = "JointSpringForceField: spring: ";
        if (what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
        a.fail("spring", what);
    }
    b.guarded(c, [&] {
        auto* ff = &info.node->add_force_field<JointSpringForceField>(s1, s2, std::move(springs));
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff] { return counted(ff->springs().size(), "joint spring", "joint springs") + " between frames"; });
    });
    b.note_unread_attributes(c);
}

// ---- BeamFEMForceField ------------------------------------------------------------------------
// Defaults: BeamFEMForceField's constructor.
constexpr AttributeSpec kBeam[] = {
    {"youngModulus", K::numbers, "5000", "Pa", ValueCheck::none, "E, one value or one per beam"},
    {"poissonRatio", K::numbers, "0.45", "", ValueCheck::none, "nu (G = E / (2 (1 + nu))), one value or one per beam"},
    {"radius", K::real, "0.1", "m", ValueCheck::positive, "outer radius of the circular section"},
    {"radiusInner", K::real, "0", "m", ValueCheck::nonnegative, "inner radius (hollow section)"},
    {"useSymmetricAssembly", K::boolean, "0", "", ValueCheck::none,
     "stiffness matrix from the rest frames (symmetric)"},
    {"listSegment", K::indices, "(every edge)", "", ValueCheck::none, "the edges that are beams"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its edges"},
};

void build_beam(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Rigid3Object& s = rigid_state(b, c, info);
    BeamParameters p;
    if (a.has("youngModulus")) p.young_modulus = a.numbers("youngModulus");
    if (a.has("poissonRatio")) p.poisson_ratio = a.numbers("poissonRatio");
    if (p.young_modulus.empty()) a.fail("youngModulus", "is empty");
    if (p.poisson_ratio.empty()) a.fail("poissonRatio", "is empty");
    for (double e : p.young_modulus)
        if (!(e > 0)) a.fail("youngModulus", "must be > 0, found " + num(e));
    for (double nu : p.poisson_ratio)
        if (!(nu > -1 && nu < 0.5)) a.fail("poissonRatio", "must be in (-1, 0.5), found " + num(nu));
    p.radius = a.real("radius");
    p.radius_inner = a.real("radiusInner");
    if (!(p.radius_inner < p.radius)) a.fail("radiusInner", "must be smaller than radius (" + num(p.radius) + " m)");
    p.symmetric_assembly = a.boolean("useSymmetricAssembly");
    const MeshTopology& topology = b.topology_of(a, info);
    std::vector<std::array<Index, 2>> edges;
    for (const auto& e : topology.edges()) edges.push_back({Index(e[0]), Index(e[1])});
    if (a.has("listSegment")) {
        std::vector<std::array<Index, 2>> chosen;
        for (PointId i : a.indices("listSegment")) {
            if (static_cast<std::size_t>(i) >= edges.size())
                a.fail("listSegment",
                       "edge " + std::to_string(i) + " out of range (" + std::to_string(edges.size()) + " edges)");
            chosen.push_back(edges[static_cast<std::size_t>(i)]);
        }
        edges = std::move(chosen);
    }
    b.guarded(c, [&] {
        auto* ff = &info.node->add_force_field<BeamFEMForceField>(s, std::move(edges), p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p] {
            return counted(ff->beam_count(), "beam", "beams") +
                   " (Euler-Bernoulli, E = " + num(p.young_modulus.front()) + " Pa, r = " + num(p.radius) + " m)";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kRigidForceFieldComponents[] = {
    {.type = "JointSpringForceField",
     .family = F::force_field,
     .summary = "joint springs between Rigid3d frames",
     .attributes = kJointSpring,
     .build = build_joint_spring},
    {.type = "BeamFEMForceField",
     .family = F::force_field,
     .summary = "elastic beams (SOFA's, shear-free) between Rigid3d frames",
     .attributes = kBeam,
     .build = build_beam},
};

}  // namespace

std::span<const ComponentSpec> rigid_force_field_components() { return kRigidForceFieldComponents; }

}  // namespace penalty::scene::builder
