// TetrahedronHyperelasticityFEMForceField (docs/components/hyperelasticity.md).
#include "penalty/mechanics/hyperelastic_fem.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// Defaults: TetrahedronHyperelasticityFEMForceField's constructor (materialName ArrudaBoyce).
constexpr AttributeSpec kHyperelasticity[] = {
    {"materialName", K::text, "ArrudaBoyce", "", ValueCheck::none,
     "ArrudaBoyce, StVenantKirchhoff, NeoHookean, MooneyRivlin or Ogden"},
    {"ParameterSet", K::numbers, "", "Pa", ValueCheck::none,
     "the material's parameters: (mu, k0), (mu, lambda), (mu, lambda), (c1, c2, k0) or (mu1, alpha1, k0)"},
    {"AnisotropyDirections", K::numbers, "", "", ValueCheck::none,
     "fiber directions: not supported (isotropic materials only)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its tetrahedra"},
};

constexpr HyperelasticMaterial kMaterials[] = {
    HyperelasticMaterial::ArrudaBoyce, HyperelasticMaterial::StVenantKirchhoff, HyperelasticMaterial::NeoHookean,
    HyperelasticMaterial::MooneyRivlin, HyperelasticMaterial::Ogden};

void build_hyperelasticity(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    HyperelasticLaw law;
    const std::string name = a.text("materialName");
    bool known = false;
    for (const HyperelasticMaterial m : kMaterials)
        if (material_name(m) == name) {
            law.material = m;
            known = true;
        }
    if (!known)
        a.fail("materialName",
               "'" + name + "' is not supported (ArrudaBoyce, StVenantKirchhoff, NeoHookean, MooneyRivlin or Ogden)");
    if (a.has("AnisotropyDirections") && !a.numbers("AnisotropyDirections").empty())
        a.fail("AnisotropyDirections", "anisotropic materials are not supported");
    if (!a.has("ParameterSet")) a.fail("ParameterSet", "is required (SOFA reads the material's parameters from it)");
    law.parameters = a.numbers("ParameterSet");
    const std::size_t count = material_parameter_count(law.material);
    if (law.parameters.size() != count)
        a.fail("ParameterSet", name + " needs " + std::to_string(count) + " parameters, found " +
                                   std::to_string(law.parameters.size()));
    if (law.material == HyperelasticMaterial::Ogden && law.parameters[1] == 0)
        a.fail("ParameterSet", "Ogden's alpha1 must be non-zero");
    const MeshTopology& topology = b.topology_of(a, info);
    b.guarded(c, [&] {
        auto* ff = &info.node->add_force_field<TetrahedronHyperelasticityFEMForceField>(s, topology.tetrahedra(), law);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, name] {
            return counted(ff->tetrahedra().size(), "tetrahedron", "tetrahedra") + ", " + name + " material";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kHyperelasticityComponents[] = {
    {.type = "TetrahedronHyperelasticityFEMForceField",
     .family = F::force_field,
     .summary = "hyperelastic tetrahedral FEM (ArrudaBoyce, StVenantKirchhoff, NeoHookean, MooneyRivlin, Ogden)",
     .attributes = kHyperelasticity,
     .build = build_hyperelasticity},
};

}  // namespace

std::span<const ComponentSpec> hyperelasticity_components() { return kHyperelasticityComponents; }

}  // namespace penalty::scene::builder
