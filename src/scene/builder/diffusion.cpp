// Diffusion of a scalar over a tetrahedral mesh: TetrahedronDiffusionFEMForceField (Vec1d), with
// the geometry of the mesh taken from the tagged Vec3d MechanicalObject above it
// (docs/components/diffusion.md).
#include "penalty/mechanics/tetrahedron_diffusion.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <sstream>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// Defaults: TetrahedronDiffusionFEMForceField's constructor.
constexpr AttributeSpec kTetrahedronDiffusion[] = {
    {"constantDiffusionCoefficient", K::real, "1", "m^2/s", ValueCheck::none, "D of every tetrahedron"},
    {"tetraDiffusionCoefficient", K::numbers, "(constantDiffusionCoefficient for each)", "m^2/s", ValueCheck::none,
     "D per tetrahedron"},
    {"anisotropyRatio", K::real, "1", "", ValueCheck::none, "r: transverse anisotropy (1: isotropic)"},
    {"transverseAnisotropyArray", K::points, "", "", ValueCheck::none, "one direction per tetrahedron (r != 1)"},
    {"tagMechanics", K::text, "meca", "", ValueCheck::none,
     "tag of the Vec3d MechanicalObject (this node or above) whose positions measure the tetrahedra"},
    {"mstate", K::link, "(the node's state)", "", ValueCheck::none, "its Vec1d state"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "the tetrahedra and their edges"},
    {"drawConduc", K::boolean, "0", "", ValueCheck::none, "drawing only"},
};

bool has_tag(const SceneComponent& c, const std::string& tag) {
    const io::SceneAttribute* tags = c.find("tags");
    if (tags == nullptr) return false;
    std::istringstream words(tags->value);
    for (std::string word; words >> word;)
        if (word == tag) return true;
    return false;
}

/// SOFA's getContext()->get(mechanicalObject, tag, SearchUp): the Vec3d state with `tag` in this
/// node, else the nearest ancestor's.
Vec3Object* tagged_geometry(SceneBuilder& b, const NodeBuild& info, const std::string& tag) {
    for (const io::SceneNode* n = info.scene_node; n != nullptr; n = n->parent) {
        const NodeBuild& nb = b.node_build(*n);
        if (nb.state_component != nullptr && nb.node != nullptr && has_tag(*nb.state_component, tag))
            if (auto* v = dynamic_cast<Vec3Object*>(nb.node->state())) return v;
    }
    return nullptr;
}

void build_tetrahedron_diffusion(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    b.guarded(c, [&] {
        auto* scalar = dynamic_cast<Vec1Object*>(&s);
        if (scalar == nullptr)
            io::throw_element_error(c, "penalty's TetrahedronDiffusionFEMForceField supports Vec1d states only");
        if (a.has("mstate") && a.link("mstate").component != info.state_component)
            a.fail("mstate", "must be the node's own MechanicalObject");
        const std::string tag = a.text("tagMechanics");
        Vec3Object* geometry = tagged_geometry(b, info, tag);
        if (geometry == nullptr)
            a.fail("tagMechanics", "no Vec3d MechanicalObject tagged '" + tag +
                                       "' in this node or above (its positions measure the tetrahedra)");
        auto* ff = &info.node->add_force_field<TetrahedronDiffusionFEMForceField>(*scalar, b.topology_of(a, info));
        ff->set_constant_coefficient(a.real("constantDiffusionCoefficient"));
        if (a.has("tetraDiffusionCoefficient"))
            ff->set_tetrahedron_coefficients(a.numbers("tetraDiffusionCoefficient"));
        const double ratio = a.real("anisotropyRatio");
        ff->set_anisotropy(
            ratio, a.has("transverseAnisotropyArray") ? a.points("transverseAnisotropyArray") : std::vector<Vec3>{});
        static_cast<void>(a.boolean("drawConduc"));  // drawing only
        b.record_origin(ff, c);
        b.add_init(1, c, [ff, geometry] {
            ff->set_geometry(geometry->position);  // SOFA reads the tagged state's positions at init
            ff->init();
        });
        b.role(c, [ff, ratio] {
            return "diffusion over " + counted(ff->tetrahedron_coefficients().size(), "tetrahedron", "tetrahedra") +
                   (ratio == 1.0 ? ", isotropic" : ", anisotropy ratio " + num(ratio));
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kDiffusionComponents[] = {
    {.type = "TetrahedronDiffusionFEMForceField",
     .family = F::force_field,
     .summary = "diffusion of a Vec1d scalar (temperature) over tetrahedra measured on a tagged Vec3d state",
     .attributes = kTetrahedronDiffusion,
     .build = build_tetrahedron_diffusion},
};

}  // namespace

std::span<const ComponentSpec> diffusion_components() { return kDiffusionComponents; }

}  // namespace penalty::scene::builder
