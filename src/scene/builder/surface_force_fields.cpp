// Force fields on triangle surfaces: TriangularFEMForceField, TriangleFEMForceField,
// TriangularBendingSprings.
// Both take their triangles from the node's topology (SceneBuilder::topology_of).
#include "penalty/mechanics/bending_springs.hpp"
#include "penalty/mechanics/triangular_fem.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- TriangularFEMForceField ----------------------------------------------------------------
// Defaults: BaseLinearElasticityFEMForceField (youngModulus 5000, poissonRatio 0.45),
// TriangularFEMForceField (method large).
constexpr AttributeSpec kTriangularFem[] = {
    {"youngModulus", K::real, "5000", "Pa", ValueCheck::positive, "membrane, unit thickness"},
    {"poissonRatio", K::real, "0.45", "", ValueCheck::none, "in (-1, 0.5)"},
    {"method", K::text, "large", "", ValueCheck::none, "large (co-rotational) or small (linear, world x-y)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles"},
    // display only (SOFA draws stresses with them; they change no number)
    {"showStressValue", K::boolean, "1", "", ValueCheck::none, "display only"},
    {"showStressVector", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"computePrincipalStress", K::boolean, "0", "", ValueCheck::none, "diagnostic only"},
};

// TriangleFEMForceField: the same attributes plus thickness and planeStrain.
constexpr AttributeSpec kTriangleFem[] = {
    {"youngModulus", K::real, "5000", "Pa", ValueCheck::positive, ""},
    {"poissonRatio", K::real, "0.45", "", ValueCheck::none, "in (-1, 0.5)"},
    {"method", K::text, "large", "", ValueCheck::none, "large (co-rotational) or small (linear, world x-y)"},
    {"thickness", K::real, "1", "m", ValueCheck::positive, "scales the stiffness"},
    {"planeStrain", K::boolean, "0", "", ValueCheck::none, "plane strain instead of plane stress"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles (or its quads, split in two)"},
};

void build_triangle_fem(SceneBuilder& b, const SceneComponent& c, NodeBuild& info, TriangleFemFlavor flavor) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        TriangleFemParameters p;
        p.flavor = flavor;
        p.young_modulus = a.real("youngModulus");
        p.poisson_ratio = a.real("poissonRatio");
        if (!(p.poisson_ratio > -1.0 && p.poisson_ratio < 0.5)) a.fail("poissonRatio", "must be in (-1, 0.5)");
        const std::string method_name = a.text("method");
        if (method_name == "small") p.method = FemMethod::Small;
        else if (method_name != "large") a.fail("method", "'" + method_name + "' is not supported (small or large)");
        if (flavor == TriangleFemFlavor::TriangleFEM) {
            p.thickness = a.real("thickness");
            p.plane_strain = a.boolean("planeStrain");
        } else {
            static_cast<void>(a.boolean("showStressValue"));  // display only: read, no effect
            static_cast<void>(a.boolean("showStressVector"));
            static_cast<void>(a.boolean("computePrincipalStress"));
        }
        auto* ff = &info.node->add_force_field<TriangularFEMForceField>(s, b.topology_of(a, info), p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p] {
            std::string text = counted(ff->triangles().size(), "triangle", "triangles") +
                               ", E = " + num(p.young_modulus) + " Pa, nu = " + num(p.poisson_ratio) + ", " +
                               (p.method == FemMethod::Large ? "co-rotational (large)" : "linear (small)");
            if (p.flavor == TriangleFemFlavor::TriangleFEM)
                text += std::string(", thickness ") + num(p.thickness) + " m, " +
                        (p.plane_strain ? "plane strain" : "plane stress");
            return text;
        });
    });
    b.note_unread_attributes(c);
}

void build_triangular_fem(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_triangle_fem(b, c, info, TriangleFemFlavor::TriangularFEM);
}

void build_older_triangle_fem(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    build_triangle_fem(b, c, info, TriangleFemFlavor::TriangleFEM);
}

// ---- TriangularBendingSprings ---------------------------------------------------------------
// Defaults: TriangularBendingSprings (stiffness 100000, damping 1).
constexpr AttributeSpec kTriangularBendingSprings[] = {
    {"stiffness", K::real, "100000", "N/m", ValueCheck::nonnegative, "every spring's ks"},
    {"damping", K::real, "1", "N s/m", ValueCheck::nonnegative, "every spring's kd"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its triangles and edges"},
    {"showSprings", K::boolean, "1", "", ValueCheck::none, "display only"},
};

void build_triangular_bending_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const double ks = a.real("stiffness");
        const double kd = a.real("damping");
        static_cast<void>(a.boolean("showSprings"));  // display only: read, no effect
        const MeshTopology& topology = b.topology_of(a, info);
        auto* ff = &info.node->add_force_field<SpringForceField>(s);
        ff->set_null_length(kBendingSpringNullLength);
        ff->set_sofa_interaction(false);  // SOFA's TriangularBendingSprings is a ForceField, not a SpringForceField
        b.record_origin(ff, c);
        // springs from the rest positions once the state is initialised (SOFA: init → reinit)
        b.add_init(1, c, [ff, &topology, &s, ks, kd] {
            for (const Spring& spring : triangular_bending_springs(topology, s.rest_position, ks, kd))
                ff->add_spring(spring);
            ff->init();
        });
        b.role(c, [ff] {
            return counted(ff->springs().size(), "bending spring", "bending springs") +
                   " across the edges shared by two triangles";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kSurfaceForceFieldComponents[] = {
    {.type = "TriangularFEMForceField",
     .family = F::force_field,
     .summary = "co-rotational triangle membrane FEM",
     .attributes = kTriangularFem,
     .build = build_triangular_fem},
    {.type = "TriangleFEMForceField",
     .family = F::force_field,
     .summary = "co-rotational triangle FEM (older)",
     .attributes = kTriangleFem,
     .build = build_older_triangle_fem},
    {.type = "TriangularBendingSprings",
     .family = F::force_field,
     .summary = "springs between the opposite vertices of adjacent triangles",
     .attributes = kTriangularBendingSprings,
     .build = build_triangular_bending_springs},
};

}  // namespace

std::span<const ComponentSpec> surface_force_field_components() { return kSurfaceForceFieldComponents; }

}  // namespace penalty::scene::builder
