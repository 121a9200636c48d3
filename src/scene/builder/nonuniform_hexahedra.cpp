// NonUniformHexahedronFEMForceFieldAndMass (docs/components/sparse-grid.md): the hexahedral FEM
// and mass of a sparse grid with virtual finer levels, condensed from the finest cells.
#include "penalty/mechanics/nonuniform_hexahedron_fem.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// Defaults: NonUniformHexahedronFEMForceFieldAndMass's and HexahedronFEMForceFieldAndMass's
// constructors (BaseLinearElasticityFEMForceField: E 5000, nu 0.45).
constexpr AttributeSpec kNonUniform[] = {
    {"nbVirtualFinerLevels", K::integer, "0", "", ValueCheck::nonnegative,
     "finer levels of the sparse grid the matrices are condensed from (1 to the grid's)"},
    {"youngModulus", K::real, "5000", "Pa", ValueCheck::positive, "E (SOFA reads element 0's for every cell)"},
    {"poissonRatio", K::real, "0.45", "", ValueCheck::none, "nu in [0, 0.5)"},
    {"method", K::text, "large", "", ValueCheck::none, "large (corotational): the only one supported"},
    {"density", K::real, "1", "kg/m^3", ValueCheck::positive, "mass density"},
    {"lumpedMass", K::boolean, "0", "", ValueCheck::none, "diagonal mass: absolute row sums of the element matrices"},
    {"useMass", K::boolean, "1", "", ValueCheck::none, "0: every particle has totalMass / (number of elements)"},
    {"totalMass", K::real, "0", "kg", ValueCheck::nonnegative, "with useMass 0"},
    {"updateStiffnessMatrix", K::boolean, "0", "", ValueCheck::none, "storage only: no effect"},
};

void build_nonuniform(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    if (!info.sparse_grid)
        io::throw_element_error(c, "needs a SparseGridTopology in its node (its virtual finer levels)");
    const SparseGridTopology& grid = *info.sparse_grid;
    if (grid.ramification() != nullptr)
        io::throw_element_error(c,
                                "a ramified sparse grid (SparseGridRamificationTopology, SparseGridMultipleTopology) "
                                "is not supported here");
    const std::int64_t levels = a.integer("nbVirtualFinerLevels");
    if (levels < 1 || levels > grid.finer_levels())
        a.fail("nbVirtualFinerLevels", "must be between 1 and the SparseGridTopology's nbVirtualFinerLevels (" +
                                           std::to_string(grid.finer_levels()) + ")");
    const double young = a.real("youngModulus"), poisson = a.real("poissonRatio");
    if (!(poisson >= 0 && poisson < 0.5)) a.fail("poissonRatio", "must be in [0, 0.5), found " + num(poisson));
    if (a.text("method") != "large") a.fail("method", "only 'large' is supported by penalty");
    static_cast<void>(a.boolean("updateStiffnessMatrix"));
    HexahedronMatrixMass::Parameters mp;
    mp.density = a.real("density");
    mp.lumped = a.boolean("lumpedMass");
    mp.use_mass = a.boolean("useMass");
    mp.total_mass = a.real("totalMass");
    const bool fill = Attributes(*info.topology_component).boolean("fillWeighted");
    b.guarded(c, [&] {
        CondensedHexahedra m =
            condense_hexahedra(grid, int(levels), young, poisson, mp.density, fill, s.transform.scale3d);
        auto* ff = &info.node->add_force_field<HexahedronFEMForceField>(s, *info.topology, young, poisson);
        ff->set_element_stiffness(std::move(m.stiffness));
        b.record_origin(ff, c);
        auto* mass = &info.node->set_mass<HexahedronMatrixMass>(s, grid.hexahedra(), std::move(m.mass),
                                                                grid.coefficients(fill), mp);
        b.record_mass(*mass, *info.node, c);
        // SOFA's init: the force field (rotations, condensed matrices), then the masses
        b.add_init(1, c, [ff, mass] {
            ff->init();
            mass->init();
        });
        b.role(c, [n = grid.hexahedra().size(), levels, young, poisson] {
            return counted(n, "hexahedron", "hexahedra") + " condensed from " + std::to_string(levels) +
                   " virtual finer levels, E = " + num(young) + " Pa, nu = " + num(poisson) +
                   ", corotational (large), element mass";
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kNonuniformHexahedraComponents[] = {
    {.type = "NonUniformHexahedronFEMForceFieldAndMass",
     .family = F::mass,
     .summary = "hexahedral FEM and mass condensed from a sparse grid's finer levels",
     .attributes = kNonUniform,
     .build = build_nonuniform},
};

}  // namespace

std::span<const ComponentSpec> nonuniform_hexahedra_components() { return kNonuniformHexahedraComponents; }

}  // namespace penalty::scene::builder
