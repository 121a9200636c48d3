// TetrahedralCorotationalFEMForceField (SOFA's corotational tetrahedra of Nesme et al. 2005),
// on the tetrahedra of the node's topology (SceneBuilder::topology_of).
// docs/components/corotational_fem.md gives the formulas and their SOFA sources.
// FastTetrahedralCorotationalForceField (the edge-stored variant):
// docs/components/fast_tetrahedral_corotational.md.
#include "penalty/mechanics/corotational_fem.hpp"
#include "penalty/mechanics/fast_tetrahedral_corotational.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// Defaults: BaseLinearElasticityFEMForceField (youngModulus 5000, poissonRatio 0.45),
// TetrahedralCorotationalFEMForceField's constructor (method large, the rest false/empty).
constexpr AttributeSpec kCorotationalFem[] = {
    {"youngModulus", K::real, "5000", "Pa", ValueCheck::positive, ""},
    {"poissonRatio", K::real, "0.45", "", ValueCheck::none, "in (-1, 0.5)"},
    {"method", K::text, "large", "", ValueCheck::none,
     "small (linear), large (corotational, edge frame) or polar (corotational, polar rotation); any other text is "
     "large, as SOFA"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its tetrahedra"},
    {"localStiffnessFactor", K::numbers, "(none)", "", ValueCheck::none,
     "M factors for N elements: element i's Young's modulus times factor[i*M/N]"},
    {"updateStiffnessMatrix", K::boolean, "0", "", ValueCheck::none,
     "large/polar: strain-displacement matrix from the current shape each step (rest volume kept)"},
    {"computeGlobalMatrix", K::boolean, "0", "", ValueCheck::none,
     "storage only, except with method polar: no force (SOFA's unfinished branch, reproduced)"},
    {"assembling", K::boolean, "0", "", ValueCheck::none, "alias of computeGlobalMatrix"},
    // display only (SOFA draws the elements with them; they change no number)
    {"drawing", K::boolean, "1", "", ValueCheck::none, "display only"},
    {"displayWholeVolume", K::boolean, "0", "", ValueCheck::none, "display only"},
    {"drawColor1", K::text, "", "", ValueCheck::none, "display only"},
    {"drawColor2", K::text, "", "", ValueCheck::none, "display only"},
    {"drawColor3", K::text, "", "", ValueCheck::none, "display only"},
    {"drawColor4", K::text, "", "", ValueCheck::none, "display only"},
};

CorotationalFemOptions corotational_options(const Attributes& a, SceneBuilder& b, const SceneComponent& c) {
    CorotationalFemOptions o;
    // TetrahedralCorotationalFEMForceField::reinit: "small", "polar", otherwise large
    const std::string method = a.text("method");
    if (method == "small") o.method = FemMethod::Small;
    else if (method == "polar") o.method = FemMethod::Polar;
    else if (method != "large") b.warn(c.describe() + ": method '" + method + "' is taken as large, as SOFA does");
    if (a.has("localStiffnessFactor")) o.local_stiffness_factors = a.numbers("localStiffnessFactor");
    o.update_stiffness = a.boolean("updateStiffnessMatrix");
    o.assembling = a.has("computeGlobalMatrix") ? a.boolean("computeGlobalMatrix") : a.boolean("assembling");
    if (o.method == FemMethod::Polar && o.assembling)
        b.warn(c.describe() +
               ": method polar with computeGlobalMatrix adds no force in SOFA (an unfinished branch); "
               "reproduced");
    return o;
}

void build_corotational_fem(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const double young = a.real("youngModulus");
        const double poisson = a.real("poissonRatio");
        if (!(poisson > -1.0 && poisson < 0.5)) a.fail("poissonRatio", "must be in (-1, 0.5)");
        CorotationalFemOptions options = corotational_options(a, b, c);
        const MeshTopology& topology = b.topology_of(a, info);
        if (topology.tetrahedra().empty())
            b.warn(c.describe() + ": no tetrahedra in its topology (SOFA warns too): no force");
        const std::string law = ", E = " + num(young) + " Pa, nu = " + num(poisson) + ", " +
                                (options.method == FemMethod::Large   ? "corotational (large)"
                                 : options.method == FemMethod::Polar ? "corotational (polar)"
                                                                      : "linear (small)") +
                                (options.update_stiffness ? ", stiffness updated each step" : "");
        auto* ff = &info.node->add_force_field<TetrahedralCorotationalFEMForceField>(s, topology.tetrahedra(), young,
                                                                                     poisson, std::move(options));
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, law] { return counted(ff->tetrahedra().size(), "tetrahedron", "tetrahedra") + law; });
    });
    b.note_unread_attributes(c);
}

// ---- FastTetrahedralCorotationalForceField ------------------------------------------------------
// Defaults: BaseLinearElasticityFEMForceField (youngModulus 5000, poissonRatio 0.45),
// FastTetrahedralCorotationalForceField's constructor (method qr, drawing 1).
constexpr AttributeSpec kFastCorotational[] = {
    {"youngModulus", K::numbers, "5000", "Pa", ValueCheck::none, "E > 0, one value or one per tetrahedron"},
    {"poissonRatio", K::numbers, "0.45", "", ValueCheck::none, "nu in [0, 0.5), one value or one per tetrahedron"},
    {"method", K::text, "qr", "", ValueCheck::none,
     "qr or large (frame of edges 01, 02), polar (polar factor of the deformation gradient), polar2 (polar factor of "
     "the edge matrix), none, linear or small (no rotation)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "its tetrahedra and edges"},
    {"drawing", K::boolean, "1", "", ValueCheck::none, "display only"},
    {"drawColor1", K::text, "", "", ValueCheck::none, "display only"},
    {"drawColor2", K::text, "", "", ValueCheck::none, "display only"},
    {"drawColor3", K::text, "", "", ValueCheck::none, "display only"},
    {"drawColor4", K::text, "", "", ValueCheck::none, "display only"},
};

void build_fast_corotational(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    FastTetrahedralCorotationalParameters p;
    p.young_modulus = elasticity_values(a, "youngModulus", {5000}, false);
    p.poisson_ratio = elasticity_values(a, "poissonRatio", {0.45}, true);
    // FastTetrahedralCorotationalForceField::init's names of the methods
    const std::string method = a.text("method");
    if (method == "qr" || method == "large") p.rotation = FastTetrahedralRotation::qr;
    else if (method == "polar") p.rotation = FastTetrahedralRotation::polar;
    else if (method == "polar2") p.rotation = FastTetrahedralRotation::polar_modified;
    else if (method == "none" || method == "linear" || method == "small") p.rotation = FastTetrahedralRotation::linear;
    else a.fail("method", "must be qr, large, polar, polar2, none, linear or small, found '" + method + "'");
    static_cast<void>(a.boolean("drawing"));
    const MeshTopology& topology = b.topology_of(a, info);
    b.guarded(c, [&] {
        if (topology.tetrahedra().empty())
            b.warn(c.describe() + ": no tetrahedra in its topology (SOFA logs an error): no force");
        auto* ff = &info.node->add_force_field<FastTetrahedralCorotationalForceField>(s, topology, p);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, p, method] {
            return counted(ff->rest_tetrahedra().size(), "tetrahedron", "tetrahedra") +
                   ", E = " + num(p.young_modulus.front()) + " Pa, nu = " + num(p.poisson_ratio.front()) +
                   ", rotation " + method + ", stiffness stored per edge";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kCorotationalFemComponents[] = {
    {.type = "TetrahedralCorotationalFEMForceField",
     .family = F::force_field,
     .summary = "corotational tetrahedral FEM (small, large, polar)",
     .attributes = kCorotationalFem,
     .build = build_corotational_fem},
    {.type = "FastTetrahedralCorotationalForceField",
     .family = F::force_field,
     .summary = "corotational tetrahedral FEM with the stiffness stored per edge (qr, polar, polar2, linear)",
     .attributes = kFastCorotational,
     .build = build_fast_corotational},
};

}  // namespace

std::span<const ComponentSpec> corotational_fem_components() { return kCorotationalFemComponents; }

}  // namespace penalty::scene::builder
