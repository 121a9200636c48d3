// The mass matrix of a mesh and the springs to a rest shape: MeshMatrixMass,
// RestShapeSpringsForceField.
#include "penalty/mechanics/mesh_matrix_mass.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/mechanics/scalar_mesh_matrix_mass.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- MeshMatrixMass ---------------------------------------------------------------------------
// SOFA's MeshMatrixMass data; totalMass defaults to 1 and is used when nothing else is given
// (MeshMatrixMass::massInitialization).
constexpr AttributeSpec kMeshMatrixMass[] = {
    {"massDensity", K::numbers, "", "kg/m^3", ValueCheck::none, "one value, or one per element"},
    {"totalMass", K::real, "1", "kg", ValueCheck::nonnegative, "shared by the elements' measures; wins"},
    {"vertexMass", K::numbers, "", "kg", ValueCheck::none, "mass of each point (with lumping or edgeMass)"},
    {"edgeMass", K::numbers, "", "kg", ValueCheck::none, "mass of each edge of the topology"},
    {"lumping", K::boolean, "0", "", ValueCheck::none, "diagonal matrix: the row sums"},
    {"computeMassOnRest", K::boolean, "0", "", ValueCheck::none, "measures on the rest positions (else the positions)"},
    {"printMass", K::boolean, "0", "", ValueCheck::none, "logging only"},
    {"showGravityCenter", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"separateGravity", K::boolean, "0", "", ValueCheck::none, "1 is refused"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "the elements"},
    {"geometryState", K::link, "(the node's state)", "", ValueCheck::none,
     "the mass's own state; a Vec1d mass: the Vec3d state whose positions measure the elements"},
    // beyond SOFA
    {"edgeElements", K::boolean, "0", "", ValueCheck::none,
     "beyond SOFA: the bar's masses on an edge-only topology (SOFA gives it none)"},
};

void build_mesh_matrix_mass(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    MeshMatrixMass* mass = nullptr;
    BaseMass* built = nullptr;
    b.guarded(c, [&] {
        auto* v = dynamic_cast<Vec3Object*>(&s);
        auto* scalar = dynamic_cast<Vec1Object*>(&s);
        if (v == nullptr && scalar == nullptr)
            io::throw_element_error(
                c, "penalty's MeshMatrixMass supports Vec3d states, and Vec1d states with a Vec3d geometryState");
        if (a.boolean("separateGravity")) a.fail("separateGravity", "1 is not supported");
        const MeshTopology& topology = b.topology_of(a, info);
        if (scalar != nullptr) {  // MeshMatrixMass<Vec1d, Vec3d>: measured on geometryState
            if (!a.has("geometryState")) a.fail("geometryState", "a Vec1d mass needs the Vec3d state of its geometry");
            auto* geometry = dynamic_cast<Vec3Object*>(b.linked_state(a, "geometryState"));
            if (geometry == nullptr)
                a.fail("geometryState", "must link a Vec3d MechanicalObject built before this node");
            auto& m = info.node->set_mass<ScalarMeshMatrixMass>(*scalar, *geometry, topology);
            mass = &m.masses();
            built = &m;
        } else {
            if (a.has("geometryState")) {
                const io::LinkTarget g = a.link("geometryState");
                if (g.component != info.state_component) a.fail("geometryState", "must be the mass's own state");
            }
            mass = &info.node->set_mass<MeshMatrixMass>(*v, topology);
            built = mass;
        }
        const auto nonnegative = [&](std::string_view name) {
            std::vector<double> values = a.numbers(name);
            for (double x : values)
                if (!(x >= 0) || !std::isfinite(x)) a.fail(name, "must be finite and >= 0, found '" + num(x) + "'");
            if (values.empty()) a.fail(name, "is empty");
            return values;
        };
        if (a.has("totalMass")) mass->set_total_mass(a.real("totalMass"));
        if (a.has("massDensity")) mass->set_mass_density(nonnegative("massDensity"));
        if (a.has("vertexMass")) mass->set_vertex_masses(nonnegative("vertexMass"));
        if (a.has("edgeMass")) mass->set_edge_masses(nonnegative("edgeMass"));
        mass->set_lumping(a.boolean("lumping"));
        mass->set_compute_mass_on_rest(a.boolean("computeMassOnRest"));
        mass->set_edge_elements(a.boolean("edgeElements"));
    });
    b.record_mass(*built, *info.node, c);
    b.role(c, [mass] {
        std::string out = std::string(mass->lumping() ? "lumped" : "consistent") + " mass matrix of the " +
                          lumped_element_name(mass->element_kind()) + ", " + num(mass->total_mass()) + " kg in all";
        if (mass->element_kind() == LumpedElementKind::edge && mass->lumping_coefficient() == 0.0)
            out += " (SOFA gives edges no mass: every mass is 0; edgeElements=\"1\" gives them the bar's)";
        return out;
    });
    b.add_init(1, c, [built] { built->init(); });
    b.note_unread_attributes(c);
}

// ---- RestShapeSpringsForceField ---------------------------------------------------------------
constexpr AttributeSpec kRestShapeSprings[] = {
    {"points", K::indices, "(all points)", "", ValueCheck::none, "points held (inline or @engine.indices)"},
    {"stiffness", K::numbers, "100", "N/m", ValueCheck::none, "one per point (the first for the others)"},
    {"angularStiffness", K::numbers, "(100 per stiffness value)", "N m/rad", ValueCheck::none,
     "Rigid3d: one per point"},
    {"activeDirections", K::numbers, "1 1 1 (Rigid3d: 1 1 1 1 1 1 1)", "", ValueCheck::none,
     "0/1 per direction: x y z (then rotations about x y z)"},
    {"external_rest_shape", K::link, "(the state's rest positions)", "", ValueCheck::none,
     "a MechanicalObject whose current positions are the anchors"},
    {"external_points", K::indices, "(all points of the external state)", "", ValueCheck::none,
     "anchor of each point, in the external state"},
    {"pivot_points", K::numbers, "", "m", ValueCheck::none, "SOFA HEAD never reads it: ignored"},
    {"recompute_indices", K::boolean, "1", "", ValueCheck::none,
     "the springs are resolved again at each step (0: init's springs stay, by index, through a topological change)"},
    {"drawSpring", K::boolean, "0", "", ValueCheck::none, "drawing only"},
    {"springColor", K::numbers, "0 1 0 1", "", ValueCheck::none, "drawing only"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "whose point removals `points` follows"},
    // beyond SOFA
    {"assembleAsAddDForce", K::boolean, "0", "", ValueCheck::none,
     "beyond SOFA: the assembled matrix of direct solvers is addDForce's (SOFA HEAD's buildStiffnessMatrix takes "
     "stiffness[point] and ignores inactive translations)"},
};

/// The state built from a MechanicalObject component (searched once the graph is built).
BaseState* state_built_from(SceneBuilder& b, const SceneComponent* component) {
    for (const auto& [sn, info] : b.node_builds())
        if (info.state_component == component && info.node != nullptr) return info.node->state();
    return nullptr;
}

template <class DataTypes>
void configure_rest_springs(SceneBuilder& b, const SceneComponent& c, const Attributes& a,
                            RestShapeSpringsForceField<DataTypes>& ff) {
    constexpr int n = RestShapeSpringsForceField<DataTypes>::kDirections;
    const auto to_index = [](const std::vector<PointId>& ids) { return std::vector<Index>(ids.begin(), ids.end()); };
    if (a.has("points")) ff.set_points(to_index(b.indices(a, "points")));
    const auto stiffness = [&](std::string_view name) {
        std::vector<double> values = a.numbers(name);
        for (double x : values)
            if (!(x >= 0) || !std::isfinite(x)) a.fail(name, "must be finite and >= 0, found '" + num(x) + "'");
        return values;
    };
    if (a.has("stiffness")) ff.set_stiffness(stiffness("stiffness"));
    if (a.has("angularStiffness")) {
        if constexpr (std::is_same_v<DataTypes, Vec3Types>)
            a.fail("angularStiffness", "applies to Rigid3d states only");
        ff.set_angular_stiffness(stiffness("angularStiffness"));
    }
    if (a.has("activeDirections")) {
        const std::vector<double> d = a.numbers("activeDirections");
        // SOFA's Data is one flag per Coord component: 3 (Vec3d) or 7 (Rigid3d; the 7th unused)
        const std::size_t written = std::is_same_v<DataTypes, Vec3Types> ? 3 : 7;
        if (d.size() != written && d.size() != std::size_t(n))
            a.fail("activeDirections",
                   "expected " + std::to_string(written) + " flags, found " + std::to_string(d.size()));
        std::array<bool, n> active{};
        for (int i = 0; i < n; ++i) {
            if (d[std::size_t(i)] != 0.0 && d[std::size_t(i)] != 1.0)
                a.fail("activeDirections", "flags must be 0 or 1, found '" + num(d[std::size_t(i)]) + "'");
            active[std::size_t(i)] = d[std::size_t(i)] != 0.0;
        }
        ff.set_active_directions(active);
    }
    ff.set_sofa_assembly(!a.boolean("assembleAsAddDForce"));
    ff.set_recompute_indices(a.boolean("recompute_indices"));
    if (a.has("pivot_points"))
        b.warn(c.file + ":" + std::to_string(c.line) + ": " + c.describe() +
               ": pivot_points is ignored (SOFA HEAD stores it but never reads it)");
    const SceneComponent* external = nullptr;
    if (a.has("external_rest_shape")) {
        external = a.link("external_rest_shape").component;
        if (external == nullptr || external->type != "MechanicalObject")
            a.fail("external_rest_shape", "must link to a MechanicalObject");
    }
    std::vector<Index> external_points;
    if (a.has("external_points")) external_points = to_index(b.indices(a, "external_points"));
    b.add_init(1, c, [&b, &c, external, external_points, p = &ff] {
        MechanicalObject<DataTypes>* state = nullptr;
        if (external != nullptr) {
            state = dynamic_cast<MechanicalObject<DataTypes>*>(state_built_from(b, external));
            if (state == nullptr)
                io::throw_attribute_error(c, "external_rest_shape",
                                          "links to " + external->describe() + ", not a " + DataTypes::kName +
                                              " state penalty built (a mapped or unbuilt state?)");
        }
        // without an external state SOFA still checks external_points against the rest positions
        p->set_external_rest_shape(state, external_points);
        p->init();
    });
}

void build_rest_shape_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    b.guarded(c, [&] {
        BaseForceField* built = nullptr;
        if (auto* v = dynamic_cast<Vec3Object*>(&s)) {
            auto& ff = info.node->add_force_field<RestShapeSpringsForceField<Vec3Types>>(*v);
            configure_rest_springs(b, c, a, ff);
            built = &ff;
            b.role(c, [p = &ff] {
                return counted(p->points().size(), "spring", "springs") + " to the " +
                       (p->external_rest_shape() ? "external state's positions" : "rest positions");
            });
        } else {
            auto& ff =
                info.node->add_force_field<RestShapeSpringsForceField<Rigid3Types>>(dynamic_cast<Rigid3Object&>(s));
            configure_rest_springs(b, c, a, ff);
            built = &ff;
            b.role(c, [p = &ff] {
                return counted(p->points().size(), "spring", "springs") + " (translation and rotation) to the " +
                       (p->external_rest_shape() ? "external state's frames" : "rest frames");
            });
        }
        b.record_origin(built, c);
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kMatrixMassAndRestSpringComponents[] = {
    {.type = "MeshMatrixMass",
     .family = F::mass,
     .summary = "mass matrix of a mesh (consistent or lumped)",
     .attributes = kMeshMatrixMass,
     .build = build_mesh_matrix_mass},
    {.type = "RestShapeSpringsForceField",
     .family = F::force_field,
     .summary = "springs from points (and frames) to their rest shape",
     .attributes = kRestShapeSprings,
     .build = build_rest_shape_springs},
};

}  // namespace

std::span<const ComponentSpec> matrix_mass_and_rest_spring_components() { return kMatrixMassAndRestSpringComponents; }

}  // namespace penalty::scene::builder
