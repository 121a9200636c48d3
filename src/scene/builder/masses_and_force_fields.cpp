// Masses, gravity and force fields: UniformMass, Gravity, MeshSpringForceField,
// RegularGridSpringForceField, TetrahedronFEMForceField, HexahedronFEMForceField.
#include "penalty/io/data_path.hpp"
#include "penalty/io/rigid_mass_file.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- Gravity --------------------------------------------------------------------------------
constexpr AttributeSpec kGravity[] = {
    {"gravity", K::vector3, "0 0 0", "m/s^2", ValueCheck::none,
     "of its node and below (SOFA's Gravity: 0 0 0 when not given)"},
};

void build_gravity(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    b.guarded(c, [&] { info.node->set_gravity(a.vector3("gravity")); });
    b.role(c, [n = info.node] { return "gravity " + vec(n->gravity()) + " m/s^2 in this node and below"; });
    b.note_unread_attributes(c);
}

// ---- UniformMass ----------------------------------------------------------------------------
constexpr AttributeSpec kUniformMass[] = {
    {"vertexMass", K::text, "", "kg", ValueCheck::none,
     "mass of each DOF (or totalMass), > 0; Rigid3d: `m` or SOFA's Rigid3Mass `m volume [3x3 inertia per unit mass]`"},
    {"totalMass", K::real, "", "kg", ValueCheck::positive, "shared equally by the DOFs; wins over vertexMass"},
    {"inertiaMatrix", K::numbers, "(identity)", "kg m^2", ValueCheck::none, "Rigid3d: 9 numbers, per unit mass"},
    {"filename", K::text, "", "", ValueCheck::none,
     "Rigid3d: .rigid file whose vertexMass and inrt (inertia per unit mass) replace the attributes"},
};

double positive_vertex_mass(const Attributes& a) {
    const double m = a.real_or("vertexMass", 1.0);
    if (!(m > 0)) a.fail("vertexMass", "must be > 0, found '" + a.text("vertexMass") + "'");
    return m;
}

/// A Rigid3d vertexMass written as SOFA's Rigid3Mass (RigidMass<3>::operator>>): the mass, the
/// volume (not used by the dynamics), then the inertia per unit mass as a 3×3 matrix
/// ("[a b c,d e f,g h i]"); nullopt for a single number (read as the mass).
struct RigidVertexMass {
    double mass = 1;
    std::optional<Mat3> inertia;
};
std::optional<RigidVertexMass> rigid_vertex_mass(const Attributes& a) {
    if (!a.has("vertexMass")) return std::nullopt;
    std::string text = a.text("vertexMass");
    for (char& ch : text)
        if (ch == '[' || ch == ']' || ch == ',') ch = ' ';
    std::istringstream in(text);
    std::vector<double> v;
    for (std::string word; in >> word;) {
        char* end = nullptr;
        const double x = std::strtod(word.c_str(), &end);
        if (end == word.c_str() || *end != '\0' || !std::isfinite(x))
            a.fail("vertexMass", "expected numbers (mass volume [inertia]), found '" + word + "'");
        v.push_back(x);
    }
    if (v.size() == 1) return std::nullopt;
    if (v.size() != 2 && v.size() != 11)
        a.fail("vertexMass", "expected a mass, or mass volume and a 3x3 inertia matrix (11 numbers), found " +
                                 std::to_string(v.size()) + " numbers");
    if (!(v[0] > 0)) a.fail("vertexMass", "the mass must be > 0, found " + num(v[0]));
    RigidVertexMass m;
    m.mass = v[0];
    if (v.size() == 11) m.inertia = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(v.data() + 2);
    return m;
}

void build_uniform_mass(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    BaseState& s = b.state(c, info);
    b.guarded(c, [&] {
        auto set = [&](auto& mass) {
            if (a.has("totalMass")) mass.set_total_mass(a.real_or("totalMass", 1.0));
            else if (a.has("vertexMass")) mass.set_vertex_mass(positive_vertex_mass(a));
            else io::throw_element_error(c, "needs vertexMass or totalMass (SOFA refuses a UniformMass without them)");
        };
        if (auto* v = dynamic_cast<Vec3Object*>(&s)) {
            set(info.node->set_mass<UniformMass<Vec3Types>>(*v));
            if (a.has("filename"))
                b.warn(c.describe() + ": filename is read for Rigid3d states only (SOFA ignores it here too)");
        } else {
            auto& mass = info.node->set_mass<UniformMass<Rigid3Types>>(dynamic_cast<Rigid3Object&>(s));
            // UniformMass<Rigid3>::loadRigidMass (at init, before vertexMass/totalMass are chosen):
            // the file's vertexMass replaces the mass and makes vertexMass the one used.
            io::RigidMassFile file;
            if (a.has("filename"))
                file = io::load_rigid_mass_file(
                    io::resolve_data_file(a.text("filename"), b.scene_dir(), b.options().data_dirs));
            const std::optional<RigidVertexMass> rigid_mass = rigid_vertex_mass(a);
            if (file.vertex_mass) mass.set_vertex_mass(*file.vertex_mass);
            else if (rigid_mass && !a.has("totalMass")) mass.set_vertex_mass(rigid_mass->mass);
            else set(mass);
            if (rigid_mass && rigid_mass->inertia) mass.set_inertia(*rigid_mass->inertia);
            if (a.has("inertiaMatrix")) {
                const std::vector<double> j = a.numbers("inertiaMatrix");
                if (j.size() != 9) a.fail("inertiaMatrix", "expected 9 numbers");
                mass.set_inertia(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(j.data()));
            }
            if (file.inertia) mass.set_inertia(*file.inertia);
        }
    });
    BaseMass* mass = info.node->mass();
    b.record_mass(*mass, *info.node, c);
    b.role(c, [mass, st = &s] {
        double m = 0.0;
        if (auto* v = dynamic_cast<const UniformMass<Vec3Types>*>(mass)) m = v->vertex_mass();
        if (auto* r = dynamic_cast<const UniformMass<Rigid3Types>*>(mass)) m = r->vertex_mass();
        return "mass " + num(m) + " kg per DOF, " + num(m * double(st->num_dofs())) + " kg in all";
    });
    b.add_init(1, c, [mass] { mass->init(); });
    b.note_unread_attributes(c);
}

// ---- springs --------------------------------------------------------------------------------
/// The per-element-kind stiffness and damping both spring fields read; `stiffness` and `damping`
/// set all of them (SOFA's MeshSpringForceField: ks = stiffness / rest length per spring).
constexpr AttributeSpec kSpringKinds[] = {
    {"linesStiffness", K::real, "(stiffness)", "N/m", ValueCheck::nonnegative, "springs of the edges"},
    {"linesDamping", K::real, "(damping)", "N s/m", ValueCheck::nonnegative, ""},
    {"trianglesStiffness", K::real, "(stiffness)", "N/m", ValueCheck::nonnegative, "springs of the triangles' edges"},
    {"trianglesDamping", K::real, "(damping)", "N s/m", ValueCheck::nonnegative, ""},
    {"quadsStiffness", K::real, "(stiffness)", "N/m", ValueCheck::nonnegative, "quads' edges and diagonals"},
    {"quadsDamping", K::real, "(damping)", "N s/m", ValueCheck::nonnegative, ""},
    {"tetrahedraStiffness", K::real, "(stiffness)", "N/m", ValueCheck::nonnegative, "tetrahedra's edges"},
    {"tetrahedraDamping", K::real, "(damping)", "N s/m", ValueCheck::nonnegative, ""},
    {"tetrasStiffness", K::real, "(stiffness)", "N/m", ValueCheck::nonnegative, "alias of tetrahedraStiffness"},
    {"tetrasDamping", K::real, "(damping)", "N s/m", ValueCheck::nonnegative, "alias of tetrahedraDamping"},
    {"cubesStiffness", K::real, "(stiffness)", "N/m", ValueCheck::nonnegative, "hexahedra's edges and diagonals"},
    {"cubesDamping", K::real, "(damping)", "N s/m", ValueCheck::nonnegative, ""},
};
constexpr AttributeSpec kMeshSprings[] = {
    {"stiffness", K::real, "0", "N/m", ValueCheck::nonnegative, "every kind's stiffness"},
    {"damping", K::real, "0", "N s/m", ValueCheck::nonnegative, "every kind's damping"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "MeshTopology or RegularGridTopology"},
};
// SOFA's RegularGridSpringForceField defaults: stiffness 100, damping 5 (its Data linesStiffness …
// cubesDamping, which `stiffness` and `damping` alias).
constexpr AttributeSpec kGridSprings[] = {
    {"stiffness", K::real, "100", "N/m", ValueCheck::nonnegative, "every kind's stiffness"},
    {"damping", K::real, "5", "N s/m", ValueCheck::nonnegative, "every kind's damping"},
};

/// The value a Data with several names gets: SOFA's Base::parse sets the Data once per written
/// name, in the order of the names (BaseObjectDescription's attributes are a std::map), so the
/// last written name in alphabetical order wins; `fallback` when none is written.
double last_written(const Attributes& a, std::initializer_list<std::string_view> names, double fallback) {
    std::string_view winner;
    for (const std::string_view name : names)
        if (!name.empty() && a.has(name) && name > winner) winner = name;
    return winner.empty() ? fallback : a.real_or(winner, fallback);
}

MeshSpringParameters spring_parameters(const Attributes& a, double default_stiffness, double default_damping) {
    MeshSpringParameters p;
    const auto kind = [&](std::string_view stiffness, std::string_view damping, std::string_view alias_stiffness,
                          std::string_view alias_damping, double& ks, double& kd) {
        const std::initializer_list<std::string_view> k_names = {stiffness, alias_stiffness, "stiffness"};
        const std::initializer_list<std::string_view> d_names = {damping, alias_damping, "damping"};
        ks = last_written(a, k_names, default_stiffness);
        kd = last_written(a, d_names, default_damping);
    };
    kind("linesStiffness", "linesDamping", "", "", p.lines_stiffness, p.lines_damping);
    kind("trianglesStiffness", "trianglesDamping", "", "", p.triangles_stiffness, p.triangles_damping);
    kind("quadsStiffness", "quadsDamping", "", "", p.quads_stiffness, p.quads_damping);
    kind("tetrahedraStiffness", "tetrahedraDamping", "tetrasStiffness", "tetrasDamping", p.tetras_stiffness,
         p.tetras_damping);
    kind("cubesStiffness", "cubesDamping", "", "", p.cubes_stiffness, p.cubes_damping);
    return p;
}

void add_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info, Vec3Object& s,
                 const std::vector<Spring>& springs) {
    auto& ff = info.node->add_force_field<SpringForceField>(s);
    b.record_origin(&ff, c);
    for (const Spring& sp : springs) ff.add_spring(sp);
    b.add_init(1, c, [f = &ff] { f->init(); });
    b.role(c, [f = &ff] {
        return counted(f->springs().size(), "spring", "springs") + " between the topology's vertex pairs " +
               "(ks = stiffness / rest length, kd = damping / rest length)";
    });
}

/// True when `t` is a SparseGridTopology's mesh: SOFA's SparseGridTopology never fills its edges,
/// triangles or quads (its init calls neither MeshTopology::init nor updateEdges/updateQuads), so
/// the springs SOFA reads from its lines, triangles and quads are none.
bool is_sparse_grid_mesh(SceneBuilder& b, const MeshTopology* t) {
    for (const auto& [node, info] : b.node_builds())
        if (info.sparse_grid && info.topology == t) return true;
    return false;
}

void build_mesh_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        MeshSpringParameters p = spring_parameters(a, 0.0, 0.0);
        const MeshTopology& topology = b.topology_of(a, info);
        if (is_sparse_grid_mesh(b, &topology)) {
            p.lines_stiffness = p.lines_damping = 0.0;
            p.triangles_stiffness = p.triangles_damping = 0.0;
            p.quads_stiffness = p.quads_damping = 0.0;
        }
        add_springs(b, c, info, s, mesh_springs(topology, s.rest_position, p));
    });
    b.note_unread_attributes(c);
}

void build_grid_springs(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const MeshSpringParameters p = spring_parameters(a, 100.0, 5.0);
        if (!info.grid) io::throw_element_error(c, "needs a RegularGridTopology in its node");
        add_springs(b, c, info, s, regular_grid_springs(*info.grid, p));  // SOFA's order and rest lengths
    });
    b.note_unread_attributes(c);
}

// ---- FEM ------------------------------------------------------------------------------------
constexpr AttributeSpec kTetrahedronFem[] = {
    {"youngModulus", K::real, "5000", "Pa", ValueCheck::positive, ""},
    {"poissonRatio", K::real, "0.45", "", ValueCheck::none, "in (-1, 0.5)"},
    {"method", K::text, "large", "", ValueCheck::none,
     "large (corotational), polar (corotational, polar rotation), svd (polar; stable SVD rotation for inverted "
     "elements) or small (linear)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "MeshTopology or RegularGridTopology"},
    // computeGlobalMatrix / updateStiffnessMatrix only choose how SOFA stores the same matrices;
    // penalty always recomputes the corotational stiffness each step (method large).
    {"computeGlobalMatrix", K::boolean, "0", "", ValueCheck::none, "storage only: no effect"},
    {"updateStiffnessMatrix", K::boolean, "0", "", ValueCheck::none, "storage only: no effect"},
    {"plasticMaxThreshold", K::real, "0", "", ValueCheck::nonnegative,
     "largest norm of the plastic strain; 0: no plasticity (method large only)"},
    {"plasticYieldThreshold", K::real, "0.0001", "", ValueCheck::nonnegative,
     "elastic strain norm above which it creeps (SOFA's default: the float 0.0001f)"},
    {"plasticCreep", K::real, "0.9", "", ValueCheck::nonnegative,
     "fraction of the elastic strain made plastic per evaluation (SOFA's default: the float 0.9f)"},
    {"localStiffnessFactor", K::numbers, "", "", ValueCheck::none,
     "factors of E: element i takes value i*M/N of the M values (method large)"},
    {"updateStiffness", K::boolean, "0", "", ValueCheck::none,
     "1: youngModulus, poissonRatio, localStiffnessFactor written after init act at the next step (else at reinit)"},
};
constexpr AttributeSpec kHexahedronFem[] = {
    {"youngModulus", K::real, "5000", "Pa", ValueCheck::positive, ""},
    {"poissonRatio", K::real, "0.45", "", ValueCheck::none, "in (-1, 0.5)"},
    {"method", K::text, "large", "", ValueCheck::none,
     "large (corotational), polar (corotational, polar rotation of the mean edges) or small (linear)"},
    {"topology", K::link, "(the node's topology)", "", ValueCheck::none, "MeshTopology or RegularGridTopology"},
};

struct FemLaw {
    double young;
    double poisson;
    FemMethod method;
};

FemLaw fem_law(const Attributes& a, bool svd_supported) {
    FemLaw law{a.real("youngModulus"), a.real("poissonRatio"), FemMethod::Large};
    if (!(law.poisson > -1.0 && law.poisson < 0.5)) a.fail("poissonRatio", "must be in (-1, 0.5)");
    const std::string method = a.text("method");
    if (method == "small") law.method = FemMethod::Small;
    else if (method == "polar") law.method = FemMethod::Polar;
    else if (method == "svd" && svd_supported) law.method = FemMethod::Svd;
    else if (method != "large")
        a.fail("method", "'" + method + "' is not supported (" +
                             (svd_supported ? "small, large, polar or svd)" : "small, large or polar)"));
    return law;
}

std::string law_text(const FemLaw& law) {
    return ", E = " + num(law.young) + " Pa, nu = " + num(law.poisson) + ", " +
           (law.method == FemMethod::Large   ? "corotational (large)"
            : law.method == FemMethod::Polar ? "corotational (polar)"
            : law.method == FemMethod::Svd   ? "corotational (svd)"
                                             : "linear (small)");
}

void build_tetrahedron_fem(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const FemLaw law = fem_law(a, /*svd_supported=*/true);
        if ((law.method == FemMethod::Polar || law.method == FemMethod::Svd) && a.boolean("updateStiffnessMatrix"))
            a.fail(
                "updateStiffnessMatrix",
                "with method polar or svd is not supported (SOFA recomputes the strain-displacement matrix each step)");
        TetrahedronFEMForceField* ff = nullptr;
        if (info.grid)
            ff = &info.node->add_force_field<TetrahedronFEMForceField>(s, *info.grid, law.young, law.poisson,
                                                                       law.method);
        else
            ff = &info.node->add_force_field<TetrahedronFEMForceField>(s, b.topology_of(a, info), law.young,
                                                                       law.poisson, law.method);
        // SOFA's Data defaults are float literals (0.0001f, 0.9f): their float values, unless written
        TetrahedronFEMForceField::Plasticity plasticity;
        plasticity.max_threshold = a.real("plasticMaxThreshold");
        plasticity.yield_threshold = a.real_or("plasticYieldThreshold", plasticity.yield_threshold);
        plasticity.creep = a.real_or("plasticCreep", plasticity.creep);
        if (plasticity.max_threshold > 0 && law.method != FemMethod::Large)
            a.fail("plasticMaxThreshold", "plasticity is supported with method large only");
        ff->set_plasticity(plasticity);
        if (a.has("localStiffnessFactor")) {
            std::vector<double> factors = a.numbers("localStiffnessFactor");
            if (law.method != FemMethod::Large) a.fail("localStiffnessFactor", "is supported with method large only");
            for (double f : factors)  // any sign, as SOFA (thermoelasticity.py's 1/(1 + 50 T) with T < −0.02)
                if (!std::isfinite(f))
                    a.fail("localStiffnessFactor", "each factor must be finite, found '" + num(f) + "'");
            ff->set_young_factors(std::move(factors));
        }
        static_cast<void>(a.boolean("updateStiffness"));  // when writes take effect (live_writes.cpp)
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, text = law_text(law)] {
            return counted(ff->tetrahedra().size(), "tetrahedron", "tetrahedra") + text;
        });
    });
    b.note_unread_attributes(c);
}

void build_hexahedron_fem(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Vec3Object& s = b.vec3_state(c, info);
    b.guarded(c, [&] {
        const FemLaw law = fem_law(a, /*svd_supported=*/false);
        auto* ff = &info.node->add_force_field<HexahedronFEMForceField>(s, b.topology_of(a, info), law.young,
                                                                        law.poisson, law.method);
        if (info.sparse_grid && !a.has("topology")) sparse_grid_stiffness_factors(*ff, info);
        b.record_origin(ff, c);
        b.add_init(1, c, [ff] { ff->init(); });
        b.role(c, [ff, text = law_text(law)] {
            return counted(ff->element_stiffness().size(), "hexahedron", "hexahedra") + text;
        });
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kMassAndForceFieldComponents[] = {
    {.type = "Gravity",
     .family = F::gravity,
     .summary = "gravity of its node's context",
     .attributes = kGravity,
     .build = build_gravity},
    {.type = "UniformMass",
     .family = F::mass,
     .summary = "uniform mass",
     .attributes = kUniformMass,
     .build = build_uniform_mass},
    {.type = "MeshSpringForceField",
     .family = F::force_field,
     .summary = "springs on the mesh edges",
     .attributes = kMeshSprings,
     .shared_attributes = kSpringKinds,
     .build = build_mesh_springs},
    {.type = "RegularGridSpringForceField",
     .family = F::force_field,
     .summary = "springs on a regular grid",
     .attributes = kGridSprings,
     .shared_attributes = kSpringKinds,
     .build = build_grid_springs},
    {.type = "TetrahedronFEMForceField",
     .family = F::force_field,
     .summary = "linear tetrahedral FEM",
     .attributes = kTetrahedronFem,
     .build = build_tetrahedron_fem},
    {.type = "HexahedronFEMForceField",
     .family = F::force_field,
     .summary = "linear hexahedral FEM",
     .attributes = kHexahedronFem,
     .build = build_hexahedron_fem},
    // SOFA's MultiThreading plugin: HexahedronFEMForceField with addForce and addDForce run over
    // the elements in parallel (ParallelHexahedronFEMForceField::addForce, addDForce), the same
    // element forces; penalty runs HexahedronFEMForceField.
    {.type = "ParallelHexahedronFEMForceField",
     .family = F::force_field,
     .summary = "HexahedronFEMForceField of SOFA's MultiThreading plugin (run as HexahedronFEMForceField)",
     .attributes = kHexahedronFem,
     .build = build_hexahedron_fem},
};

}  // namespace

std::span<const ComponentSpec> mass_and_force_field_components() { return kMassAndForceFieldComponents; }

}  // namespace penalty::scene::builder
