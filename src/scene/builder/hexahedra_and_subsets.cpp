// Hexahedral FEM with SOFA's HexahedralFEMForceField stiffness, the "AndMass" variants
// (HexahedralFEMForceFieldAndMass, HexahedronFEMForceFieldAndMass: FEM + element mass in one
// component), and the SubsetTopology engine (points and elements inside / outside a region).
// Formulas and quirks: docs/components/hexahedra_and_subsets.md.
#include "penalty/mechanics/hexahedral_fem.hpp"
#include "penalty/mechanics/subset_topology.hpp"
#include "scene/builder/element_topology.hpp"
#include "scene/builder/families.hpp"

#include <utility>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- hexahedral FEM ----------------------------------------------------------------------------
// BaseLinearElasticityFEMForceField's defaults: youngModulus 5000, poissonRatio 0.45.
#define PENALTY_HEXA_FEM_ATTRIBUTES(methods)                                                                    \
    {"youngModulus", K::real, "5000", "Pa", ValueCheck::positive, ""},                                          \
        {"poissonRatio", K::real, "0.45", "", ValueCheck::none, "in (-1, 0.5)"},                                \
        {"method", K::text, "large", "", ValueCheck::none, methods}, {                                          \
        "topology", K::link, "(the node's topology)", "", ValueCheck::none, "its hexahedra (SOFA vertex order)" \
    }
#define PENALTY_ELEMENT_MASS_ATTRIBUTES                                                                        \
    {"density", K::real, "1", "kg/m^3", ValueCheck::positive, "per hexahedron volume |e01|·|e03|·|e04|"}, {    \
        "lumpedMass", K::boolean, "0", "", ValueCheck::none, "diagonal mass: row sums of the element matrices" \
    }

constexpr AttributeSpec kHexahedralFem[] = {
    PENALTY_HEXA_FEM_ATTRIBUTES("large (frame from the mean edges) or polar (polar factor of the mean edges)")};
constexpr AttributeSpec kHexahedralFemAndMass[] = {
    PENALTY_HEXA_FEM_ATTRIBUTES("large (frame from the mean edges) or polar (polar factor of the mean edges)"),
    PENALTY_ELEMENT_MASS_ATTRIBUTES};
constexpr AttributeSpec kHexahedronFemAndMass[] = {
    PENALTY_HEXA_FEM_ATTRIBUTES("large (corotational) or small (linear)"),
    PENALTY_ELEMENT_MASS_ATTRIBUTES,
    {"updateStiffnessMatrix", K::boolean, "0", "", ValueCheck::none, "storage only: no effect"},
};
#undef PENALTY_HEXA_FEM_ATTRIBUTES
#undef PENALTY_ELEMENT_MASS_ATTRIBUTES

struct HexaLaw {
    double young;
    double poisson;
    FemMethod method;
};

/// The material and method of a hexahedral FEM component; `small` is accepted by
/// HexahedronFEMForceField(AndMass), `polar` by HexahedralFEMForceField(AndMass).
HexaLaw hexa_law(const Attributes& a, bool hexahedral) {
    HexaLaw law{a.real("youngModulus"), a.real("poissonRatio"), FemMethod::Large};
    if (!(law.poisson > -1.0 && law.poisson < 0.5)) a.fail("poissonRatio", "must be in (-1, 0.5)");
    const std::string method = a.text("method");
    if (method == "polar" && hexahedral) law.method = FemMethod::Polar;
    else if (method == "small" && !hexahedral) law.method = FemMethod::Small;
    else if (method != "large")
        a.fail("method", "'" + method + "' is not supported (" + (hexahedral ? "large or polar)" : "large or small)"));
    return law;
}

std::string hexa_text(std::size_t count, const HexaLaw& law) {
    return counted(count, "hexahedron", "hexahedra") + ", E = " + num(law.young) + " Pa, nu = " + num(law.poisson) +
           ", " +
           (law.method == FemMethod::Large   ? "corotational (large)"
            : law.method == FemMethod::Polar ? "corotational (polar)"
                                             : "linear (small)");
}

const MeshTopology& hexahedral_topology(SceneBuilder& b, const Attributes& a, const NodeBuild& info) {
    const MeshTopology& topology = b.topology_of(a, info);
    if (topology.hexahedra().empty()) io::throw_element_error(a.component(), "needs a topology with hexahedra");
    return topology;
}

void build_hexahedral_fem(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const HexaLaw law = hexa_law(a, /*hexahedral=*/true);
        auto* ff = &info.node->add_force_field<HexahedralFEMForceField>(s, hexahedral_topology(b, a, info), law.young,
                                                                        law.poisson, law.method);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, law] { return hexa_text(ff->hexahedra().size(), law); });
    });
    b.note_unread_attributes(c);
}

/// The element mass of an "AndMass" component, on the hexahedra of `topology`.
void add_element_mass(SceneBuilder& b, const SceneComponent& c, const Attributes& a, NodeBuild& info, Vec3Object& s,
                      const MeshTopology& topology, std::vector<double> mass_factors, HexahedronMassFormula formula,
                      const HexahedronFEMForceField* rotated_rest_source) {
    auto* mass = &info.node->set_mass<HexahedronElementMass>(s, topology.hexahedra(), a.real("density"),
                                                             a.boolean("lumpedMass"), "HexahedronElementMass", formula);
    mass->set_mass_factors(std::move(mass_factors));
    mass->set_rotated_rest_source(rotated_rest_source);
    b.record_mass(*mass, *info.node, c);
    b.add_init(1, c, [mass] { mass->init(); });
}

template <bool Hexahedral>
void build_fem_and_mass(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const HexaLaw law = hexa_law(a, Hexahedral);
        const MeshTopology& topology = hexahedral_topology(b, a, info);
        const bool sparse = info.sparse_grid && !a.has("topology");
        std::size_t count = topology.hexahedra().size();
        std::vector<double> mass_factors;
        const HexahedronFEMForceField* rotated_rest_source = nullptr;
        // SOFA's …AndMass::init: the force field first, then the masses (from the rest positions;
        // HexahedronFEMForceFieldAndMass's element matrices from its rotated rest corners)
        if constexpr (Hexahedral) {
            auto* ff =
                &info.node->add_force_field<HexahedralFEMForceField>(s, topology, law.young, law.poisson, law.method);
            b.record_origin(ff, c);
            b.add_init(1, c, [ff] { ff->init(); });
        } else {
            auto* ff =
                &info.node->add_force_field<HexahedronFEMForceField>(s, topology, law.young, law.poisson, law.method);
            // on a sparse grid SOFA weights a cell's stiffness and mass alike (SparseGridTopology's
            // getStiffnessCoef and getMassCoef, both 0.5 for a boundary cell when fillWeighted)
            if (sparse) sparse_grid_stiffness_factors(*ff, info);
            if (!ff->stiffness_factors().empty()) mass_factors = sparse_grid_mass_factors(info);
            rotated_rest_source = ff;
            b.record_origin(ff, c);
            b.add_init(1, c, [ff] { ff->init(); });
        }
        add_element_mass(b, c, a, info, s, topology, std::move(mass_factors),
                         Hexahedral ? HexahedronMassFormula::hexahedral : HexahedronMassFormula::hexahedron,
                         rotated_rest_source);
        b.role(c, [count, law, density = a.real("density"), lumped = a.boolean("lumpedMass")] {
            return hexa_text(count, law) + "; element mass, density " + num(density) + (lumped ? " (lumped)" : "");
        });
    });
    b.note_unread_attributes(c);
}

// ---- SubsetTopology ----------------------------------------------------------------------------
// SubsetTopology's Data (SubsetTopology::SubsetTopology): box default 0 0 0 1 1 1; spheres when
// `centers` is set; inputs linked from the context's state/loader and topology when unset
// (SubsetTopology::init).
constexpr AttributeSpec kSubsetTopology[] = {
    {"box", K::numbers, "0 0 0 1 1 1", "m", ValueCheck::none, "boxes: xmin ymin zmin xmax ymax zmax each"},
    {"centers", K::points, "", "m", ValueCheck::none, "sphere centers (spheres replace the boxes)"},
    {"radii", K::numbers, "", "m", ValueCheck::none, "one radius per center"},
    {"direction", K::vector3, "0 0 0", "", ValueCheck::none, "no effect (as SOFA)"},
    {"normal", K::vector3, "0 0 0", "", ValueCheck::none, "no effect (as SOFA)"},
    {"edgeAngle", K::real, "0", "", ValueCheck::none, "no effect (as SOFA)"},
    {"triAngle", K::real, "0", "", ValueCheck::none, "no effect (as SOFA)"},
    {"src", K::link, "", "", ValueCheck::none, "loader whose element lists it takes"},
    {"rest_position", K::points, "(the node's state, else its loader)", "m", ValueCheck::none,
     "points tested, or a link"},
    {"edges", K::elements, "(src, else the node's topology)", "", ValueCheck::none, "or a link"},
    {"triangles", K::elements, "(src, else the node's topology)", "", ValueCheck::none, "or a link"},
    {"quads", K::elements, "(src)", "", ValueCheck::none, "or a link"},
    {"tetrahedra", K::elements, "(src, else the node's topology)", "", ValueCheck::none, "or a link"},
    {"hexahedra", K::elements, "(src)", "", ValueCheck::none, "or a link"},
    {"tetrahedraInput", K::indices, "", "", ValueCheck::none, "tetrahedra taken as inside, whatever the region"},
    {"localIndices", K::boolean, "0", "", ValueCheck::none, "renumber the output elements into the output point lists"},
    {"indices", K::indices, "", "", ValueCheck::none, "output (a written value is replaced)"},
    {"drawROI", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawPoints", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawEdges", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawTriangle", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawTetrahedra", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"drawSize", K::real, "1", "", ValueCheck::none, "drawing only"},
};

/// SubsetTopology's outputs by SOFA's Data names, each named once: `indices(name, list)` for the
/// index lists, `mesh(name, member of io::MeshData, list)` for the point and element lists.
template <class Out, class Indices, class Mesh>
void visit_subset_outputs(Out& out, Indices&& indices, Mesh&& mesh) {
    indices("indices", out.indices);
    indices("edgeIndices", out.edge_indices);
    indices("triangleIndices", out.triangle_indices);
    indices("quadIndices", out.quad_indices);
    indices("tetrahedronIndices", out.tetrahedron_indices);
    indices("hexahedronIndices", out.hexahedron_indices);
    mesh("pointsInROI", &io::MeshData::positions, out.points_in);
    mesh("pointsOutROI", &io::MeshData::positions, out.points_out);
    mesh("edgesInROI", &io::MeshData::edges, out.edges_in);
    mesh("edgesOutROI", &io::MeshData::edges, out.edges_out);
    mesh("trianglesInROI", &io::MeshData::triangles, out.triangles_in);
    mesh("trianglesOutROI", &io::MeshData::triangles, out.triangles_out);
    mesh("quadsInROI", &io::MeshData::quads, out.quads_in);
    mesh("quadsOutROI", &io::MeshData::quads, out.quads_out);
    mesh("tetrahedraInROI", &io::MeshData::tetrahedra, out.tetrahedra_in);
    mesh("tetrahedraOutROI", &io::MeshData::tetrahedra, out.tetrahedra_out);
    mesh("hexahedraInROI", &io::MeshData::hexahedra, out.hexahedra_in);
    mesh("hexahedraOutROI", &io::MeshData::hexahedra, out.hexahedra_out);
}

/// A live SubsetTopology's outputs (live_engines.hpp), under the names the build records.
void record_subset(SubsetOutput out, LiveEngine& engine) {
    visit_subset_outputs(
        out, [&engine](const char* name, auto& list) { engine.indices[name] = std::move(list); },
        [&engine](const char* name, auto member, auto& list) { engine.meshes[name].*member = std::move(list); });
}

/// SubsetTopology::init: rest_position from the scene, else the node's state, else its loader.
std::vector<Vec3> subset_rest_positions(SceneBuilder& b, const Attributes& a, const NodeBuild& info) {
    if (a.has("rest_position")) return b.point_data(a, "rest_position");
    if (const auto* v = dynamic_cast<const Vec3Object*>(info.node->state())) return v->rest_position;
    for (const auto& component : info.scene_node->components)
        if (component_category(component->type) == ComponentCategory::loader) return b.mesh_of(*component).positions;
    io::throw_element_error(a.component(), "needs rest_position, a Vec3d state or a mesh loader in its node");
}

void build_subset_topology(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    SubsetOutput out;
    SubsetInput in;
    b.guarded(c, [&] {
        SubsetRegion region;
        if (a.has("centers")) {
            region.centers = a.points("centers");
            region.radii = a.numbers("radii");
        } else {
            const std::vector<double> v = a.numbers("box");
            if (v.size() % 6 != 0) a.fail("box", "expected 6 numbers per box, found " + std::to_string(v.size()));
            for (std::size_t i = 0; i < v.size(); i += 6)
                region.boxes.push_back(
                    AlignedBox::from_corners(Vec3(v[i], v[i + 1], v[i + 2]), Vec3(v[i + 3], v[i + 4], v[i + 5])));
        }
        in.positions = subset_rest_positions(b, a, info);
        // `src` copies the lists of the same names; the edges, triangles and tetrahedra left unset
        // come from the node's topology (SubsetTopology::init)
        if (a.has("src")) {
            const io::MeshData& mesh = b.linked_mesh(a, "src");
            in.edges = mesh.edges;
            in.triangles = mesh.triangles;
            in.quads = mesh.quads;
            in.tetrahedra = mesh.tetrahedra;
            in.hexahedra = mesh.hexahedra;
        } else if (info.topology != nullptr) {
            if (!a.has("edges")) in.edges = info.topology->edges();
            if (!a.has("triangles")) in.triangles = info.topology->triangles();
            if (!a.has("tetrahedra")) in.tetrahedra = info.topology->tetrahedra();
        }
        read_element_list(b, a, "edges", in.edges, &io::MeshData::edges, &MeshTopology::edges);
        read_element_list(b, a, "triangles", in.triangles, &io::MeshData::triangles, &MeshTopology::triangles);
        read_element_list(b, a, "quads", in.quads, &io::MeshData::quads, &MeshTopology::quads);
        read_element_list(b, a, "tetrahedra", in.tetrahedra, &io::MeshData::tetrahedra, &MeshTopology::tetrahedra);
        read_element_list(b, a, "hexahedra", in.hexahedra, &io::MeshData::hexahedra, &MeshTopology::hexahedra);
        if (a.has("tetrahedraInput")) in.tetrahedra_input = b.indices(a, "tetrahedraInput");
        in.local_indices = a.boolean("localIndices");
        out = select_subset(in, region);
        // over moving positions: run again on read (live_engines.cpp; SubsetTopology::doUpdate always)
        SubsetInput elements = in;
        elements.positions.clear();
        b.add_live_engine(a, in.positions, [elements, region](const std::vector<Vec3>& x, LiveEngine& engine) {
            SubsetInput now = elements;
            now.positions = x;
            record_subset(select_subset(now, region), engine);
        });
    });
    // outputs, read through links (@subset.pointsInROI, @subset.trianglesInROI, @subset.indices, ...)
    visit_subset_outputs(
        std::as_const(out), [&](const char* name, const auto& list) { b.record_engine_indices(c, name, list); },
        [&](const char* name, auto member, const auto& list) {
            io::MeshData mesh;
            mesh.*member = list;
            b.record_engine_mesh(c, name, std::move(mesh));
        });
    b.role(c, [n = in.positions.size(), in_points = out.points_in.size(), border = out.border_count,
               elements = out.edges_in.size() + out.triangles_in.size() + out.quads_in.size() +
                          out.tetrahedra_in.size() + out.hexahedra_in.size()] {
        return "selects " + std::to_string(in_points) + " of " + counted(n, "point", "points") + " and " +
               counted(elements, "element", "elements") + " inside" +
               (border > 0 ? " (" + std::to_string(border) + " border points first, local indices)" : std::string());
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kHexahedraAndSubsetComponents[] = {
    {.type = "HexahedralFEMForceField",
     .family = F::force_field,
     .summary = "corotational hexahedral FEM (SOFA's box stiffness, methods large and polar)",
     .attributes = kHexahedralFem,
     .build = build_hexahedral_fem},
    {.type = "HexahedralFEMForceFieldAndMass",
     .family = F::mass,
     .summary = "HexahedralFEMForceField with its element mass",
     .attributes = kHexahedralFemAndMass,
     .build = build_fem_and_mass<true>},
    {.type = "HexahedronFEMForceFieldAndMass",
     .family = F::mass,
     .summary = "HexahedronFEMForceField with its element mass",
     .attributes = kHexahedronFemAndMass,
     .build = build_fem_and_mass<false>},
    {.type = "SubsetTopology",
     .family = F::engine,
     .summary = "points and elements inside / outside boxes or spheres, and their sub-topologies",
     .attributes = kSubsetTopology,
     .build = build_subset_topology},
};

}  // namespace

std::span<const ComponentSpec> hexahedra_and_subset_components() { return kHexahedraAndSubsetComponents; }

}  // namespace penalty::scene::builder
