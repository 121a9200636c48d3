// Force fields on triangle and quad surfaces (docs/components/shell_force_fields.md):
// TriangularFEMForceFieldOptim, FastTriangularBendingSprings, QuadBendingFEMForceField.
#include "penalty/mechanics/fast_triangular_bending_springs.hpp"
#include "penalty/mechanics/quad_bending_fem.hpp"
#include "penalty/mechanics/triangular_fem_optim.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- TriangularFEMForceFieldOptim -------------------------------------------------------------
constexpr AttributeSpec kTriangularFemOptim[] = {
    {"youngModulus", K::numbers, "5000", "Pa", ValueCheck::none, "E, one value or one per triangle"},
    {"poissonRatio", K::numbers, "0.45", "", ValueCheck::none, "nu in [0, 0.5), one value or one per triangle"},
    {"method", K::text, "large", "", ValueCheck::none, "only large (SOFA ignores other values with a warning)"},
    {"restScale", K::real, "1", "", ValueCheck::positive, "scale of the rest shape (pre-stretch), when written"},
    {"damping", K::real, "0", "", ValueCheck::none, "no effect (SOFA never reads it)"},
    {"computePrincipalStress", K::boolean, "0", "", ValueCheck::none, "output only"},
    {"showStressVector", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"showStressThreshold", K::real, "0", "", ValueCheck::none, "display only"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles"},
};

void build_triangular_fem_optim(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    TriangularFemOptimParameters p;
    p.young_modulus = elasticity_values(a, "youngModulus", p.young_modulus, false);
    p.poisson_ratio = elasticity_values(a, "poissonRatio", p.poisson_ratio, true);
    if (a.has("restScale")) p.rest_scale = a.real("restScale");
    if (a.text("method") != "large")
        b.warn(c.file + ":" + std::to_string(c.find("method")->line) + ": " + c.describe() + ": method '" +
               a.text("method") + "' ignored: TriangularFEMForceFieldOptim is large-displacement only (as SOFA)");
    static_cast<void>(a.real("damping"));
    static_cast<void>(a.boolean("computePrincipalStress"));
    static_cast<void>(a.boolean("showStressVector"));
    static_cast<void>(a.real("showStressThreshold"));
    const MeshTopology& topology = b.topology_of(a, info);
    b.guarded(c, [&] {
        auto* ff = &info.node->add_force_field<TriangularFEMForceFieldOptim>(s, topology, p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p] {
            return counted(ff->rest_triangles().size(), "corotational triangle", "corotational triangles") +
                   ", E = " + num(p.young_modulus.front()) + " Pa, nu = " + num(p.poisson_ratio.front());
        });
    });
    b.note_unread_attributes(c);
}

// ---- FastTriangularBendingSprings -------------------------------------------------------------
constexpr AttributeSpec kFastBending[] = {
    {"bendingStiffness", K::real, "1", "N m", ValueCheck::nonnegative, "material bending stiffness"},
    {"minDistValidity", K::real, "0.000001", "m", ValueCheck::nonnegative, "shorter diagonals or edges: no element"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles and edges"},
};

void build_fast_bending(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    const double stiffness = a.real("bendingStiffness"), min_dist = a.real("minDistValidity");
    const MeshTopology& topology = b.topology_of(a, info);
    b.guarded(c, [&] {
        auto* ff = &info.node->add_force_field<FastTriangularBendingSprings>(s, topology, stiffness, min_dist);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, stiffness] {
            return counted(ff->elements().size(), "bending element", "bending elements") +
                   " across the edges shared by two triangles, stiffness " + num(stiffness);
        });
    });
    b.note_unread_attributes(c);
}

// ---- QuadBendingFEMForceField -----------------------------------------------------------------
constexpr AttributeSpec kQuadBending[] = {
    {"youngModulus", K::numbers, "1000", "Pa", ValueCheck::none, "E, one value or one per quad"},
    {"poissonRatio", K::numbers, "0.45", "", ValueCheck::none, "nu in [0, 0.5), one value or one per quad"},
    {"thickness", K::real, "1", "m", ValueCheck::positive, "plate thickness"},
    {"method", K::text, "small", "", ValueCheck::none, "only small (SOFA has no other)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its quads"},
};

void build_quad_bending(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    QuadBendingParameters p;
    p.young_modulus = elasticity_values(a, "youngModulus", p.young_modulus, false);
    p.poisson_ratio = elasticity_values(a, "poissonRatio", p.poisson_ratio, true);
    p.thickness = a.real("thickness");
    if (a.text("method") != "small") a.fail("method", "only 'small' is implemented (as in SOFA)");
    const MeshTopology& topology = b.topology_of(a, info);
    if (topology.quads().empty()) io::throw_element_error(c, "its topology has no quads");
    b.guarded(c, [&] {
        auto* ff = &info.node->add_force_field<QuadBendingFEMForceField>(s, topology, p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [&topology, p] {
            return counted(topology.quads().size(), "plate quad", "plate quads") +
                   ", E = " + num(p.young_modulus.front()) + " Pa, thickness " + num(p.thickness) +
                   " m (small displacements)";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kShellForceFieldComponents[] = {
    {.type = "TriangularFEMForceFieldOptim",
     .family = F::force_field,
     .summary = "corotational membrane triangles (SOFA's fast variant)",
     .attributes = kTriangularFemOptim,
     .build = build_triangular_fem_optim},
    {.type = "FastTriangularBendingSprings",
     .family = F::force_field,
     .summary = "linear bending across the edges shared by two triangles",
     .attributes = kFastBending,
     .build = build_fast_bending},
    {.type = "QuadBendingFEMForceField",
     .family = F::force_field,
     .summary = "Mindlin plate quads (small displacements)",
     .attributes = kQuadBending,
     .build = build_quad_bending},
};

}  // namespace

std::span<const ComponentSpec> shell_force_field_components() { return kShellForceFieldComponents; }

}  // namespace penalty::scene::builder
