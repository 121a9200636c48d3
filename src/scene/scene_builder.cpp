// Builds a Simulation from a parsed SOFA scene (see include/penalty/scene/scene.hpp).
#include "penalty/scene/scene.hpp"

#include "penalty/collision/models.hpp"
#include "penalty/io/components.hpp"
#include "penalty/io/data_path.hpp"
#include "penalty/io/overrides.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "scene/attributes.hpp"
#include "scene/display.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace penalty::scene {

using io::SceneComponent;
using io::SceneNode;

namespace {

/// What the builder knows about one scene node while it builds it and its children.
struct NodeInfo {
    Node* node = nullptr;
    const SceneComponent* state_component = nullptr;
    const MeshTopology* topology = nullptr;      ///< MeshTopology, or the grid's element lists
    std::vector<Vec3> topology_positions;        ///< points given to the topology (may be empty)
    std::optional<RegularGridTopology> grid;
    const SceneComponent* topology_component = nullptr;
    bool mapped = false;
    const SceneNode* solver_node = nullptr;      ///< first node from the root owning an ODE solver (null: none)
    int node_id = 0;                             ///< depth-first index (collision same-node rule)
};


bool is_collision_model_type(std::string_view t) {
    return t == "PointCollisionModel" || t == "LineCollisionModel" || t == "TriangleCollisionModel" ||
           t == "SphereCollisionModel" || t == "CylinderCollisionModel" || t == "TetrahedronCollisionModel";
}
bool is_intersection_type(std::string_view t) {
    return t == "MinProximityIntersection" || t == "NewProximityIntersection" || t == "DiscreteIntersection" ||
           t == "LocalMinDistance";
}

/// SOFA's class name of a component type (its ObjectFactory alias resolved), for default names.
std::string_view sofa_class_name(std::string_view type) {
    if (type == "FixedConstraint") return "FixedProjectiveConstraint";
    return type;
}

/// SOFA's name for an unnamed component of the XML loader (ObjectElement::initNode →
/// ComponentNameHelper::resolveName, xml convention): its class name followed by a counter of the
/// unnamed components of that class created so far in the same node (context), from 1; e.g. the
/// one unnamed MechanicalObject of a node is "MechanicalObject1".
std::string sofa_default_name(const SceneComponent& c) {
    const std::string_view cls = sofa_class_name(c.type);
    int count = 0;
    for (const auto& other : c.node->components) {
        if (other->name.empty() && sofa_class_name(other->type) == cls) ++count;
        if (other.get() == &c) break;
    }
    return std::string(cls) + std::to_string(count);
}

/// "none", or the names of the fixes that are on, and the zero-distance policy when not the default.
std::string quirk_summary(const SofaQuirkFixes& q) {
    std::string out;
    for (const std::string& name : enabled_sofa_quirk_fixes(q)) out += (out.empty() ? "" : " ") + name;
    if (q.zero_distance_normal != ZeroDistanceNormal::FallbackX)
        out += (out.empty() ? "" : " ") + std::string("zeroDistanceNormal=") + zero_distance_normal_name(q.zero_distance_normal);
    return out.empty() ? "none" : out;
}

/// The accepted quirk names, for error messages.
std::string quirk_choices() {
    std::string out = "known: all";
    for (const SofaQuirkInfo& q : sofa_quirk_table()) out += ", " + std::string(q.name);
    return out;
}

bool is_rigid_template(const SceneComponent& c, std::string_view name) {
    if (name.empty() || name == "Vec3d" || name == "Vec3" || name == "Vec3f") return false;
    if (name == "Rigid3d" || name == "Rigid3" || name == "Rigid" || name == "Rigid3f") return true;
    io::throw_element_error(c, "template '" + std::string(name) + "' is not supported (Vec3d or Rigid3d)");
}

double nonnegative(const SceneComponent& c, std::string_view attr, double fallback) {
    const double v = io::get_double_or(c, attr, fallback);
    if (v < 0) io::throw_attribute_error(c, attr, "must be >= 0, found '" + io::get_string(c, attr).value_or("") + "'");
    return v;
}
double positive(const SceneComponent& c, std::string_view attr, double fallback) {
    const double v = io::get_double_or(c, attr, fallback);
    if (!(v > 0)) io::throw_attribute_error(c, attr, "must be > 0, found '" + io::get_string(c, attr).value_or("") + "'");
    return v;
}

// ---- one-line descriptions for `penalty info` -----------------------------------------------------
using display::node_path;
std::string num(double v) { return display::number(v); }
std::string vec(const Vec3& v) { return display::vector(v); }
std::string counted(std::size_t n, std::string_view singular, std::string_view plural) {
    return std::to_string(n) + " " + std::string(n == 1 ? singular : plural);
}
/// "81 points, 208 edges, 128 triangles": the non-zero element counts.
std::string element_counts(std::size_t points, std::size_t edges, std::size_t triangles, std::size_t quads,
                           std::size_t tetrahedra, std::size_t hexahedra) {
    std::string out = counted(points, "point", "points");
    auto add = [&](std::size_t n, std::string_view one, std::string_view many) {
        if (n > 0) out += ", " + counted(n, one, many);
    };
    add(edges, "edge", "edges");
    add(triangles, "triangle", "triangles");
    add(quads, "quad", "quads");
    add(tetrahedra, "tetrahedron", "tetrahedra");
    add(hexahedra, "hexahedron", "hexahedra");
    return out;
}
std::string element_counts(std::size_t points, const MeshTopology& t) {
    return element_counts(points, t.edges().size(), t.triangles().size(), t.quads().size(), t.tetrahedra().size(),
                          t.hexahedra().size());
}
std::string mesh_counts(const io::MeshData& m) {
    return element_counts(m.positions.size(), m.edges.size(), m.triangles.size(), m.quads.size(), m.tetrahedra.size(),
                          m.hexahedra.size()) +
           (m.radii.empty() ? "" : ", radii");
}
std::string element_words(ModelType t, std::size_t n) {
    switch (t) {
        case ModelType::Point: return counted(n, "point", "points");
        case ModelType::Line: return counted(n, "edge", "edges");
        case ModelType::Triangle: return counted(n, "triangle", "triangles");
        case ModelType::Sphere: return counted(n, "sphere", "spheres");
        case ModelType::RigidSphere: return counted(n, "rigid sphere", "rigid spheres");
        case ModelType::Cylinder: return counted(n, "cylinder", "cylinders");
        case ModelType::Tetrahedron: return counted(n, "tetrahedron", "tetrahedra");
    }
    return counted(n, "element", "elements");
}

}  // namespace

class SceneBuilder {
public:
    SceneBuilder(const io::SceneFile& file, const BuildOptions& options, Scene& scene)
        : file_(file), options_(options), scene_(scene), scene_dir_(file.directory()) {}

    void build() {
        if (!file_.root) throw io::SceneError(file_.path.string() + ": empty scene");
        check_ = io::validate(file_);
        for (const SceneComponent* c : check_.ignored) ignored_.insert(c);
        if (!check_.ignored.empty()) scene_.build_warnings_.push_back(check_.summary);

        Simulation& sim = *scene_.simulation_;
        build_node(*file_.root, sim.root());
        if (options_.dt) {
            if (!(*options_.dt > 0) || !std::isfinite(*options_.dt))
                throw io::SceneError("--dt must be a positive number of seconds");
            sim.root().set_dt(*options_.dt);
        }
        for (auto& m : scene_.models_) guarded(*m.component, [&] { m.model->validate(); });
        // Initialise every component once here, in Simulation::init's order (states and mappings
        // top-down, then masses, force fields, constraints, solvers), so that an error names its
        // component and line; Simulation::init then repeats it (idempotent).
        for (int phase : {0, 1})
            for (const InitStep& step : init_steps_)
                if (step.phase == phase) guarded(*step.component, step.init);
        build_pipelines();
        for (const auto& w : attribute_warnings_) scene_.build_warnings_.push_back(w);
        try {
            sim.init();
        } catch (const std::exception& e) {
            throw io::SceneError(file_.path.string() + ": " + e.what());
        }
        // Again once every mapped state has its size (a model over a mapped state was checked
        // against an empty state above): an element that indexes past its state is a scene error.
        for (auto& m : scene_.models_) guarded(*m.component, [&] { m.model->validate(); });
        record_sphere_radii();
        warn_degenerate_triangles();
        for (const auto& [c, describe] : roles_) scene_.roles_[c] = describe();
        for (const auto& [sn, info] : infos_) scene_.nodes_[sn] = info.node;
    }

private:
    // ---- helpers ------------------------------------------------------------------------------
    /// StateRecord::radius (VTK point scalars) of every state a sphere model covers, once the
    /// scene is initialised (a mapped state gets its size from its mapping's init).
    void record_sphere_radii() {
        for (output::StateRecord& r : scene_.states_) {
            for (const SceneCollisionModel& m : scene_.models_) {
                if (m.node->state() != r.state) continue;
                if (const auto* sphere = dynamic_cast<const SphereModel*>(m.model.get())) {
                    for (std::size_t i = 0; i < sphere->size(); ++i) r.radius.push_back(sphere->radius(Index(i)));
                } else if (const auto* rigid = dynamic_cast<const RigidSphereModel*>(m.model.get())) {
                    for (std::size_t i = 0; i < rigid->size(); ++i) r.radius.push_back(rigid->radius(Index(i)));
                }
                if (!r.radius.empty()) break;
            }
        }
    }

    /// A note per triangle collision model with zero-area triangles (coincident or collinear
    /// corners at init): they have no normal, so SOFA's kernels skip or mis-orient them and a
    /// body can pass through. Zero area: |(b − a) × (c − a)| ≤ 1e-12 · (longest edge)².
    void warn_degenerate_triangles() {
        for (const SceneCollisionModel& m : scene_.models_) {
            const auto* tri = dynamic_cast<const TriangleModel*>(m.model.get());
            if (tri == nullptr) continue;
            std::size_t count = 0;
            std::size_t first = 0;
            for (std::size_t i = 0; i < tri->size(); ++i) {
                const Vec3 &a = tri->p(Index(i), 0), &b = tri->p(Index(i), 1), &c = tri->p(Index(i), 2);
                const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
                if ((b - a).cross(c - a).norm() <= 1e-12 * longest || longest == 0.0) {
                    if (count++ == 0) first = i;
                }
            }
            if (count == 0) continue;
            const io::SceneComponent& c = *m.component;
            scene_.build_warnings_.push_back(c.file + ":" + std::to_string(c.line) + ": " + c.describe() + ": " +
                                             std::to_string(count) + " of " + std::to_string(tri->size()) +
                                             " triangles have zero area (first: triangle " + std::to_string(first) +
                                             "); they make no reliable contact");
        }
    }

    /// Records how to describe what `c` became; evaluated once the scene is initialised.
    void role(const SceneComponent& c, std::function<std::string()> describe) {
        roles_.emplace_back(&c, std::move(describe));
    }

    template <class F>
    auto guarded(const io::SceneElement& c, F&& f) -> decltype(f()) {
        try {
            return f();
        } catch (const io::LoadError&) {
            throw;
        } catch (const std::exception& e) {  // the library's own checks (invalid_argument, ...)
            // The library names its class ("UniformMass: ..."); the element is named already.
            std::string_view what = e.what();
            const std::string own_prefix = c.type + ": ";
            if (what.substr(0, own_prefix.size()) == own_prefix) what.remove_prefix(own_prefix.size());
            io::throw_element_error(c, std::string(what));
        }
    }

    void note_unread_attributes(const io::SceneElement& c) {
        for (const std::string& a : unread_attributes(c))
            attribute_warnings_.push_back(c.file + ":" + std::to_string(c.find(a)->line) + ": " + c.describe() +
                                          ": attribute '" + a + "' is not read by penalty (ignored)");
    }

    const io::MeshData& mesh_of(const SceneComponent& loader) {
        auto it = meshes_.find(&loader);
        if (it == meshes_.end()) {
            it = meshes_.emplace(&loader, io::load_scene_mesh(loader, scene_dir_, options_.data_dirs)).first;
            std::string file;
            if (const auto name = io::get_string(loader, "filename"))
                file = io::resolve_data_file(*name, scene_dir_, options_.data_dirs).string() + ": ";
            role(loader, [file, counts = mesh_counts(it->second)] { return "reads " + file + counts; });
        }
        return it->second;
    }

    /// Positions named by a data link (`@loader.position`, `@[-1].position`, `@../dofs.position`).
    std::vector<Vec3> linked_positions(const SceneComponent& c, std::string_view attr) {
        const io::LinkTarget t = io::resolve_link(c, attr);
        if (t.component == nullptr)
            io::throw_attribute_error(c, attr, "link must name a loader, a topology or a MechanicalObject");
        const SceneComponent& src = *t.component;
        if (!t.data.empty() && t.data != "position" && t.data != "rest_position")
            io::throw_attribute_error(c, attr, "cannot read positions from data '" + t.data + "'");
        if (io::component_category(src.type) == io::ComponentCategory::loader) return mesh_of(src).positions;
        if (src.type == "MechanicalObject") {
            auto it = vec3_states_.find(&src);
            if (it == vec3_states_.end())
                io::throw_attribute_error(c, attr, "links to " + src.describe() + ", which is not a built Vec3d state");
            return it->second->position;
        }
        if (src.type == "MeshTopology") {
            for (const auto& [node, info] : infos_)
                if (info.topology_component == &src) return info.topology_positions;
        }
        io::throw_attribute_error(c, attr, "cannot read positions from " + src.describe());
    }

    // ---- nodes --------------------------------------------------------------------------------
    /// SOFA keeps one component of each of these kinds per node (a second one replaces or
    /// shadows the first in SOFA's context); penalty refuses the second, naming both lines.
    static void check_once_per_node(const std::vector<const SceneComponent*>& physics) {
        struct Kind {
            std::string_view what;
            bool (*is)(std::string_view);
        };
        static constexpr std::array kinds{
            Kind{"mechanical state", [](std::string_view t) { return t == "MechanicalObject"; }},
            Kind{"topology", [](std::string_view t) { return t == "MeshTopology" || t == "RegularGridTopology"; }},
            Kind{"mass", [](std::string_view t) { return t == "UniformMass"; }},
            Kind{"mapping", [](std::string_view t) { return io::is_mapping_type(t); }},
            Kind{"ODE solver", [](std::string_view t) { return t == "EulerImplicitSolver" || t == "EulerExplicitSolver"; }},
            Kind{"linear solver", [](std::string_view t) { return t == "CGLinearSolver"; }},
            Kind{"animation loop", [](std::string_view t) { return t == "DefaultAnimationLoop"; }},
        };
        for (const Kind& kind : kinds) {
            const SceneComponent* first = nullptr;
            for (const SceneComponent* c : physics) {
                if (!kind.is(c->type)) continue;
                if (first == nullptr) {
                    first = c;
                    continue;
                }
                io::throw_element_error(*c, "a node holds one " + std::string(kind.what) + ", and this node already has " +
                                                first->describe() + " at line " + std::to_string(first->line));
            }
        }
    }

    void build_node(const SceneNode& sn, Node& node) {
        NodeInfo& info = infos_[&sn];
        info.node = &node;
        info.node_id = node_count_++;
        node_of_[&sn] = &node;
        guarded(sn, [&] {
            if (auto dt = io::get_double(sn, "dt")) {
                if (!(*dt > 0)) io::throw_attribute_error(sn, "dt", "must be > 0");
                node.set_dt(*dt);
            }
            if (auto g = io::get_vec3(sn, "gravity")) node.set_gravity(*g);
        });
        note_unread_attributes(sn);

        std::vector<const SceneComponent*> physics;
        for (const auto& c : sn.components)
            if (!ignored_.count(c.get())) physics.push_back(c.get());
        auto of_type = [&](auto pred) {
            std::vector<const SceneComponent*> out;
            for (const SceneComponent* c : physics)
                if (pred(c->type)) out.push_back(c);
            return out;
        };

        for (const SceneComponent* c : of_type([](std::string_view t) { return t == "Gravity"; })) {
            guarded(*c, [&] { node.set_gravity(io::get_vec3_or(*c, "gravity", Vec3(0, -9.81, 0))); });
            role(*c, [n = &node] { return "gravity " + vec(n->gravity()) + " m/s^2 in this node and below"; });
            note_unread_attributes(*c);
        }
        check_once_per_node(physics);
        const auto solvers = of_type([](std::string_view t) { return t == "EulerImplicitSolver" || t == "EulerExplicitSolver"; });
        const SceneNode* parent_solver = sn.parent ? infos_[sn.parent].solver_node : nullptr;
        info.solver_node = parent_solver ? parent_solver : (solvers.empty() ? nullptr : &sn);

        const auto topologies = of_type([](std::string_view t) { return t == "MeshTopology" || t == "RegularGridTopology"; });
        if (!topologies.empty()) build_topology(*topologies.front(), info);

        const auto states = of_type([](std::string_view t) { return t == "MechanicalObject"; });
        const auto mappings = of_type([](std::string_view t) { return io::is_mapping_type(t); });
        info.mapped = !mappings.empty();
        if (!states.empty()) build_state(*states.front(), info);
        if (!mappings.empty()) build_mapping(*mappings.front(), sn, info);

        for (const SceneComponent* c : physics) {
            const std::string& t = c->type;
            if (t == "UniformMass") build_mass(*c, info);
            else if (t == "MeshSpringForceField" || t == "RegularGridSpringForceField") build_springs(*c, info);
            else if (t == "TetrahedronFEMForceField" || t == "HexahedronFEMForceField") build_fem(*c, info);
            else if (t == "FixedProjectiveConstraint" || t == "FixedConstraint") build_fixed(*c, info);
        }
        if (!solvers.empty()) build_solver(*solvers.front(), physics, node);
        for (const SceneComponent* c : physics)
            if (is_collision_model_type(c->type)) build_collision_model(*c, info);
        for (const SceneComponent* c : physics) {
            if (c->type == "CollisionPipeline" || c->type == "CompositeCollisionPipeline") pipeline_components_.push_back(c);
            if (c->type == "DefaultAnimationLoop" || c->type == "BruteForceBroadPhase" || c->type == "BVHNarrowPhase" ||
                c->type == "CGLinearSolver" || c->type == "CollisionResponse" || is_intersection_type(c->type) ||
                c->type == "SubCollisionPipeline" || c->type == "CollisionPipeline" || c->type == "CompositeCollisionPipeline")
                note_unread_attributes(*c);
        }

        if (info.state_component) {
            output::StateRecord r;
            r.name = std::string(node.state()->state_name());
            r.node_path = sn.path();
            r.state = node.state();
            r.topology = info.topology;
            r.mapped = info.mapped;
            r.in_solver_subtree = info.solver_node != nullptr;
            r.mass = node.mass();
            scene_.states_.push_back(std::move(r));
        }
        for (const auto& child : sn.children) build_node(*child, node.add_child(child->name));
    }

    // ---- topology -----------------------------------------------------------------------------
    void build_topology(const SceneComponent& c, NodeInfo& info) {
        info.topology_component = &c;
        guarded(c, [&] {
            if (c.type == "RegularGridTopology") {
                std::array<int, 3> n{2, 2, 2};
                if (c.has("n")) {
                    const std::vector<double> v = io::get_doubles(c, "n");
                    if (v.size() != 3) io::throw_attribute_error(c, "n", "expected 3 integers");
                    for (const double x : v)
                        if (!(x >= 1 && x <= 100000)) io::throw_attribute_error(c, "n", "each count must be between 1 and 100000");
                    n = {int(v[0]), int(v[1]), int(v[2])};
                }
                for (int k = 0; k < 3; ++k) {
                    const std::string axis = std::string("n") + char('x' + k);
                    const std::int64_t count = io::get_int_or(c, axis, n[std::size_t(k)]);
                    if (count < 1 || count > 100000) io::throw_attribute_error(c, axis, "must be between 1 and 100000");
                    n[std::size_t(k)] = int(count);  // checked before the narrowing cast
                }
                const auto points = std::uint64_t(n[0]) * std::uint64_t(n[1]) * std::uint64_t(n[2]);
                if (points > options_.max_dofs)
                    io::throw_element_error(c, std::to_string(points) + " grid points (more than " +
                                                   std::to_string(options_.max_dofs) + ")");
                Vec3 lo = io::get_vec3_or(c, "min", Vec3::Zero()), hi = io::get_vec3_or(c, "max", Vec3::Ones());
                lo = Vec3(io::get_double_or(c, "xmin", lo.x()), io::get_double_or(c, "ymin", lo.y()),
                          io::get_double_or(c, "zmin", lo.z()));
                hi = Vec3(io::get_double_or(c, "xmax", hi.x()), io::get_double_or(c, "ymax", hi.y()),
                          io::get_double_or(c, "zmax", hi.z()));
                info.grid.emplace(n, lo, hi);
                info.topology_positions = info.grid->points();
                auto t = std::make_unique<MeshTopology>(info.grid->mesh(false));
                info.topology = t.get();
                scene_.topologies_.push_back(std::move(t));
            } else {
                auto t = std::make_unique<MeshTopology>();
                io::MeshData mesh;
                if (c.has("src")) {
                    const io::LinkTarget src = io::resolve_link(c, "src");
                    if (src.component == nullptr || io::component_category(src.component->type) != io::ComponentCategory::loader)
                        io::throw_attribute_error(c, "src", "must link to a mesh loader");
                    mesh = mesh_of(*src.component);
                } else if (c.has("filename")) {
                    mesh = mesh_of(c);
                }
                if (c.has("position")) mesh.positions = io::get_vec3_list(c, "position");
                if (c.has("edges")) mesh.edges = io::get_elements<2>(c, "edges");
                if (c.has("triangles")) mesh.triangles = io::get_elements<3>(c, "triangles");
                if (c.has("quads")) mesh.quads = io::get_elements<4>(c, "quads");
                for (const char* a : {"tetrahedra", "tetras"})
                    if (c.has(a)) mesh.tetrahedra = io::get_elements<4>(c, a);
                for (const char* a : {"hexahedra", "hexas"})
                    if (c.has(a)) mesh.hexahedra = io::get_elements<8>(c, a);
                if (!mesh.positions.empty()) t->set_num_points(mesh.positions.size());
                t->set_edges(mesh.edges);
                t->set_triangles(mesh.triangles);
                t->set_quads(mesh.quads);
                t->set_tetrahedra(mesh.tetrahedra);
                t->set_hexahedra(mesh.hexahedra);
                (void)t->edges();  // checks indices against the point count now
                info.topology_positions = mesh.positions;
                info.topology = t.get();
                scene_.topologies_.push_back(std::move(t));
            }
        });
        if (info.grid) {
            role(c, [g = &*info.grid, t = info.topology] {
                return "grid " + std::to_string(g->n()[0]) + " x " + std::to_string(g->n()[1]) + " x " +
                       std::to_string(g->n()[2]) + " from " + vec(g->min()) + " to " + vec(g->max()) + ": " +
                       element_counts(g->num_points(), *t);
            });
        } else {
            role(c, [t = info.topology] { return element_counts(t->num_points(), *t); });
        }
        note_unread_attributes(c);
    }

    // ---- states -------------------------------------------------------------------------------
    /// `size` (default 1), bounded so that a typo cannot allocate the machine's memory.
    std::size_t dof_count(const SceneComponent& c) const {
        const auto n = io::get_int_or(c, "size", 1);
        if (n < 0 || std::uint64_t(n) > options_.max_dofs)
            io::throw_attribute_error(c, "size", "must be between 0 and " + std::to_string(options_.max_dofs));
        return std::size_t(n);
    }

    static InitialTransform read_transform(const SceneComponent& c) {
        InitialTransform tr;
        tr.translation = io::get_vec3_or(c, "translation", Vec3::Zero());
        tr.rotation_deg = io::get_vec3_or(c, "rotation", Vec3::Zero());
        tr.scale3d = io::get_vec3_or(c, "scale3d", Vec3::Ones());
        // SOFA's short forms: dx dy dz (translation), rx ry rz (degrees), scale (uniform).
        for (int k = 0; k < 3; ++k) {
            const std::string axis(1, char('x' + k));
            tr.translation[k] = io::get_double_or(c, "d" + axis, tr.translation[k]);
            tr.rotation_deg[k] = io::get_double_or(c, "r" + axis, tr.rotation_deg[k]);
        }
        if (auto s = io::get_double(c, "scale")) tr.scale3d *= *s;
        return tr;
    }

    void build_state(const SceneComponent& c, NodeInfo& info) {
        info.state_component = &c;
        const bool rigid = is_rigid_template(c, c.template_name);
        const std::string name = c.name.empty() ? sofa_default_name(c) : c.name;
        Node& node = *info.node;
        guarded(c, [&] {
            const InitialTransform tr = read_transform(c);
            if (rigid) {
                auto& s = node.add_state<Rigid3Types>(name);
                if (c.has("position")) s.position = io::get_rigid_list(c, "position");
                if (c.has("rest_position")) s.rest_position = io::get_rigid_list(c, "rest_position");
                if (c.has("velocity")) {
                    const std::vector<double> v = io::get_doubles(c, "velocity");
                    if (v.size() % 6 != 0) io::throw_attribute_error(c, "velocity", "expected a multiple of 6 numbers");
                    for (std::size_t i = 0; i < v.size(); i += 6)
                        s.velocity.push_back(RigidDeriv{Vec3(v[i], v[i + 1], v[i + 2]), Vec3(v[i + 3], v[i + 4], v[i + 5])});
                }
                if (s.position.empty() && s.rest_position.empty() && !info.mapped)
                    s.position.assign(dof_count(c), RigidFrame{});
                s.transform = tr;
                if (!info.mapped) s.init();
            } else {
                auto& s = node.add_state<Vec3Types>(name);
                if (c.has("position")) {
                    s.position = io::is_link(c.find("position")->value) ? linked_positions(c, "position")
                                                                         : io::get_vec3_list(c, "position");
                } else if (c.has("src")) {
                    const io::LinkTarget src = io::resolve_link(c, "src");
                    if (src.component == nullptr || io::component_category(src.component->type) != io::ComponentCategory::loader)
                        io::throw_attribute_error(c, "src", "must link to a mesh loader");
                    s.position = mesh_of(*src.component).positions;
                } else if (!info.topology_positions.empty()) {
                    s.position = info.topology_positions;  // SOFA: a state without positions takes its topology's
                } else if (c.has("size")) {
                    s.position.assign(dof_count(c), Vec3::Zero());
                } else if (!info.mapped) {
                    s.position.assign(1, Vec3::Zero());  // SOFA's default size 1
                }
                if (c.has("rest_position")) s.rest_position = io::get_vec3_list(c, "rest_position");
                if (c.has("velocity")) s.velocity = io::get_vec3_list(c, "velocity");
                if (s.position.size() > options_.max_dofs)  // from a mesh file or a linked state
                    io::throw_element_error(c, std::to_string(s.position.size()) + " DOFs (more than " +
                                                   std::to_string(options_.max_dofs) + ")");
                s.transform = tr;
                s.init();
                vec3_states_[&c] = &s;
            }
        });
        std::string where;
        if (info.mapped) where = "mapped: positions and velocities from its mapping";
        else if (info.solver_node) where = "integrated by the ODE solver of " + node_path(*info.solver_node);
        else where = "static: in no solver's subtree, never moves";
        const InitialTransform tr = read_transform(c);
        std::string moved;
        if (!tr.scale3d.isOnes(0)) moved += ", scaled " + vec(tr.scale3d);
        if (!tr.rotation_deg.isZero(0)) moved += ", rotated " + vec(tr.rotation_deg) + " deg";
        if (!tr.translation.isZero(0)) moved += ", translated " + vec(tr.translation);
        role(c, [st = info.node->state(), rigid, where, moved] {
            return std::string(rigid ? "Rigid3d" : "Vec3d") + " state, " + counted(st->num_dofs(), "DOF", "DOFs") + moved +
                   "; " + where;
        });
        note_unread_attributes(c);
    }

    Vec3Object& vec3_state(const SceneComponent& c, const NodeInfo& info) {
        auto* s = dynamic_cast<Vec3Object*>(info.node->state());
        if (s == nullptr) {
            io::throw_element_error(c, info.node->state() ? "needs a Vec3d MechanicalObject in its node (found Rigid3d)"
                                                          : "needs a MechanicalObject in its node");
        }
        return *s;
    }
    const MeshTopology& topology_of(const SceneComponent& c, const NodeInfo& info) {
        if (c.has("topology")) {
            const io::LinkTarget t = io::resolve_link(c, "topology");
            if (t.component != nullptr) {
                for (const auto& [sn, i] : infos_)
                    if (i.topology_component == t.component) return *i.topology;
            }
            io::throw_attribute_error(c, "topology", "must link to a MeshTopology or RegularGridTopology already built");
        }
        if (info.topology == nullptr) io::throw_element_error(c, "needs a topology (MeshTopology or RegularGridTopology) in its node");
        return *info.topology;
    }

    // ---- mappings -----------------------------------------------------------------------------
    /// The state a mapping's `input` / `output` link names (default: parent's / own node's).
    BaseState* mapping_end(const SceneComponent& c, std::string_view attr, const SceneNode* fallback) {
        const SceneNode* target_node = fallback;
        if (c.has(attr)) {
            const io::LinkTarget t = io::resolve_link(c, attr);
            if (t.node != nullptr) {
                target_node = t.node;
            } else if (t.component != nullptr && t.component->type == "MechanicalObject") {
                target_node = t.component->node;
                if (infos_[target_node].state_component != t.component)
                    io::throw_attribute_error(c, attr, "links to a MechanicalObject that was not built");
            } else {
                io::throw_attribute_error(c, attr, "must link to a node or a MechanicalObject");
            }
        }
        if (target_node == nullptr || infos_.count(target_node) == 0 || infos_[target_node].node == nullptr ||
            infos_[target_node].node->state() == nullptr)
            io::throw_attribute_error(c, attr, "no MechanicalObject to map " + std::string(attr == "input" ? "from" : "to"));
        return infos_[target_node].node->state();
    }

    void build_mapping(const SceneComponent& c, const SceneNode& sn, NodeInfo& info) {
        if (info.state_component == nullptr) io::throw_element_error(c, "needs a MechanicalObject in its node (its output)");
        BaseState* in = mapping_end(c, "input", sn.parent);
        BaseState* out = mapping_end(c, "output", &sn);
        if (out != info.node->state())
            io::throw_attribute_error(c, "output", "must be the MechanicalObject of the mapping's own node");
        const NodeInfo* in_info = nullptr;
        for (const auto& [n, i] : infos_)
            if (i.node && i.node->state() == in) in_info = &i;
        auto* out3 = dynamic_cast<Vec3Object*>(out);
        if (out3 == nullptr) io::throw_attribute_error(c, "output", "must be a Vec3d MechanicalObject");
        auto* in3 = dynamic_cast<Vec3Object*>(in);
        auto* inr = dynamic_cast<Rigid3Object*>(in);
        Node& node = *info.node;
        guarded(c, [&] {
            if (c.type == "IdentityMapping") {
                if (in3) node.set_mapping<IdentityMapping>(*in3, *out3);
                else node.set_mapping<RigidCenterIdentityMapping>(*inr, *out3);
            } else if (c.type == "RigidMapping") {
                if (!inr) io::throw_attribute_error(c, "input", "RigidMapping needs a Rigid3d input");
                auto& m = node.set_mapping<RigidMapping>(*inr, *out3);
                std::vector<Index> frames;
                for (const char* a : {"rigidIndexPerPoint", "index"})
                    if (c.has(a))
                        for (PointId i : io::get_indices(c, a)) frames.push_back(i);
                if (frames.size() == 1) frames.assign(out3->position.size(), frames.front());
                std::vector<Vec3> pts = c.has("points") ? io::get_vec3_list(c, "points") : out3->position;
                if (io::get_bool_or(c, "globalToLocalCoords", false)) m.set_points_from_world(pts, frames);
                else m.set_points(pts, frames);
            } else if (c.type == "SubsetMapping") {
                if (!in3) io::throw_attribute_error(c, "input", "SubsetMapping needs a Vec3d input");
                auto& m = node.set_mapping<BarycentricMapping>(*in3, *out3);
                std::vector<std::vector<BarycentricMapping::Entry>> rows;
                for (PointId i : io::get_indices(c, "indices")) rows.push_back({{Index(i), 1.0}});
                m.set_weights(std::move(rows));
            } else {  // BarycentricMapping
                if (!in3) io::throw_attribute_error(c, "input", "BarycentricMapping needs a Vec3d input");
                if (in_info == nullptr || in_info->topology == nullptr)
                    io::throw_attribute_error(c, "input", "the input's node has no topology to map onto");
                auto& m = node.set_mapping<BarycentricMapping>(*in3, *out3);
                map_barycentric(c, m, *in_info, *in3, out3->position);
            }
        });
        BaseMapping* mapping = node.mapping();
        init_steps_.push_back({0, [mapping] { mapping->init(); }, &c});
        std::string from = "?";
        for (const auto& [n, i] : infos_)
            if (i.node && i.node->state() == in) from = node_path(*n);
        std::string how;
        if (c.type == "IdentityMapping") how = inr ? "identity: the frames' centres" : "identity";
        else if (c.type == "RigidMapping") how = "rigid: points fixed in the frames";
        else if (c.type == "SubsetMapping") how = "subset: one input point per output point";
        else if (in_info && in_info->grid) how = "barycentric: trilinear in the grid's cells";
        else if (in_info && !in_info->topology->tetrahedra().empty()) how = "barycentric: in the input's tetrahedra";
        else how = "barycentric: trilinear in the input's hexahedra";
        role(c, [out3, from, how] { return "maps " + from + " onto this node's " + counted(out3->num_dofs(), "point", "points") + " (" + how + ")"; });
        note_unread_attributes(c);
    }

    /// Weights of `points` (the output's positions after its own transform) in the input's
    /// volume elements. A RegularGridTopology is searched as SOFA's regular-grid mapper does
    /// (RegularGridTopology::findCube, then findNearestCube): in the grid's written coordinates
    /// (min, max, n), whatever translation, rotation or scale the input state applied to its
    /// positions; a point outside the grid takes the nearest cell with unclamped (extrapolated)
    /// trilinear coordinates. Mesh topologies use the input's rest positions.
    void map_barycentric(const SceneComponent& c, BarycentricMapping& m, const NodeInfo& in_info, const Vec3Object& in,
                         std::span<const Vec3> points) {
        if (in_info.grid) {
            map_on_regular_grid(m, *in_info.grid, points);
            return;
        }
        if (!in_info.topology->tetrahedra().empty()) {
            m.map_on_tetrahedra(*in_info.topology, in.rest_position, points);
        } else if (!in_info.topology->hexahedra().empty()) {
            m.map_on_hexahedra(*in_info.topology, in.rest_position, points);
        } else {
            io::throw_element_error(c, "the input topology has no tetrahedra or hexahedra (penalty maps onto volumes only)");
        }
    }

    // ---- mass, force fields, constraints, solvers ---------------------------------------------
    void build_mass(const SceneComponent& c, NodeInfo& info) {
        BaseState* s = info.node->state();
        if (s == nullptr) io::throw_element_error(c, "needs a MechanicalObject in its node");
        guarded(c, [&] {
            auto set = [&](auto& mass) {
                if (c.has("totalMass")) mass.set_total_mass(positive(c, "totalMass", 1.0));
                else if (c.has("vertexMass")) mass.set_vertex_mass(positive(c, "vertexMass", 1.0));
                else io::throw_element_error(c, "needs vertexMass or totalMass (SOFA refuses a UniformMass without them)");
            };
            if (auto* v = dynamic_cast<Vec3Object*>(s)) {
                auto& mass = info.node->set_mass<UniformMass<Vec3Types>>(*v);
                set(mass);
            } else {
                auto& mass = info.node->set_mass<UniformMass<Rigid3Types>>(*dynamic_cast<Rigid3Object*>(s));
                set(mass);
                if (c.has("inertiaMatrix")) {
                    const std::vector<double> j = io::get_doubles(c, "inertiaMatrix");
                    if (j.size() != 9) io::throw_attribute_error(c, "inertiaMatrix", "expected 9 numbers");
                    mass.set_inertia(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(j.data()));
                }
            }
        });
        BaseMass* mass = info.node->mass();
        scene_.masses_.push_back(mass);
        scene_.mass_nodes_.push_back(info.node);
        scene_.built_from_[mass] = &c;
        role(c, [mass, st = s] {
            double m = 0.0;
            if (auto* v = dynamic_cast<const UniformMass<Vec3Types>*>(mass)) m = v->vertex_mass();
            if (auto* r = dynamic_cast<const UniformMass<Rigid3Types>*>(mass)) m = r->vertex_mass();
            return "mass " + num(m) + " kg per DOF, " + num(m * double(st->num_dofs())) + " kg in all";
        });
        init_steps_.push_back({1, [mass] { mass->init(); }, &c});
        note_unread_attributes(c);
    }

    void build_springs(const SceneComponent& c, NodeInfo& info) {
        Vec3Object& s = vec3_state(c, info);
        guarded(c, [&] {
            MeshSpringParameters p = MeshSpringParameters::uniform(nonnegative(c, "stiffness", 0.0), nonnegative(c, "damping", 0.0));
            // SOFA's RegularGridSpringForceField defaults: stiffness 100, damping 5 (its Data
            // linesStiffness … cubesDamping, which `stiffness` and `damping` alias).
            if (c.type == "RegularGridSpringForceField")
                p = MeshSpringParameters::uniform(nonnegative(c, "stiffness", 100.0), nonnegative(c, "damping", 5.0));
            auto pick = [&](const char* k, const char* d, double& ks, double& kd) {
                ks = nonnegative(c, k, ks);
                kd = nonnegative(c, d, kd);
            };
            pick("linesStiffness", "linesDamping", p.lines_stiffness, p.lines_damping);
            pick("trianglesStiffness", "trianglesDamping", p.triangles_stiffness, p.triangles_damping);
            pick("quadsStiffness", "quadsDamping", p.quads_stiffness, p.quads_damping);
            pick("tetrasStiffness", "tetrasDamping", p.tetras_stiffness, p.tetras_damping);
            pick("cubesStiffness", "cubesDamping", p.cubes_stiffness, p.cubes_damping);
            std::vector<Spring> springs;
            if (c.type == "RegularGridSpringForceField") {
                if (!info.grid) io::throw_element_error(c, "needs a RegularGridTopology in its node");
                springs = regular_grid_springs(*info.grid, p);  // SOFA's order and rest lengths
            } else {
                springs = mesh_springs(topology_of(c, info), s.rest_position, p);
            }
            auto& ff = info.node->add_force_field<SpringForceField>(s);
            scene_.built_from_[&ff] = &c;
            for (const Spring& sp : springs) ff.add_spring(sp);
            init_steps_.push_back({1, [f = &ff] { f->init(); }, &c});
            role(c, [f = &ff] {
                return counted(f->springs().size(), "spring", "springs") + " between the topology's vertex pairs " +
                       "(ks = stiffness / rest length, kd = damping / rest length)";
            });
        });
        note_unread_attributes(c);
    }

    void build_fem(const SceneComponent& c, NodeInfo& info) {
        Vec3Object& s = vec3_state(c, info);
        guarded(c, [&] {
            const double young = positive(c, "youngModulus", 5000.0);
            const double poisson = io::get_double_or(c, "poissonRatio", 0.45);
            if (!(poisson > -1.0 && poisson < 0.5)) io::throw_attribute_error(c, "poissonRatio", "must be in (-1, 0.5)");
            const std::string method = io::get_string(c, "method").value_or("large");
            FemMethod m = FemMethod::Large;
            if (method == "small") m = FemMethod::Small;
            else if (method != "large")
                io::throw_attribute_error(c, "method", "'" + method + "' is not supported (small or large)");
            BaseForceField* ff = nullptr;
            if (c.type == "TetrahedronFEMForceField") {
                if (info.grid) ff = &info.node->add_force_field<TetrahedronFEMForceField>(s, *info.grid, young, poisson, m);
                else ff = &info.node->add_force_field<TetrahedronFEMForceField>(s, topology_of(c, info), young, poisson, m);
            } else {
                ff = &info.node->add_force_field<HexahedronFEMForceField>(s, topology_of(c, info), young, poisson, m);
            }
            scene_.built_from_[ff] = &c;
            init_steps_.push_back({1, [ff] { ff->init(); }, &c});
            const std::string law = ", E = " + num(young) + " Pa, nu = " + num(poisson) + ", " +
                                    (m == FemMethod::Large ? "corotational (large)" : "linear (small)");
            if (const auto* tet = dynamic_cast<const TetrahedronFEMForceField*>(ff)) {
                role(c, [tet, law] { return counted(tet->tetrahedra().size(), "tetrahedron", "tetrahedra") + law; });
            } else if (const auto* hex = dynamic_cast<const HexahedronFEMForceField*>(ff)) {
                role(c, [hex, law] { return counted(hex->element_stiffness().size(), "hexahedron", "hexahedra") + law; });
            }
        });
        note_unread_attributes(c);
    }

    void build_fixed(const SceneComponent& c, NodeInfo& info) {
        BaseState* s = info.node->state();
        if (s == nullptr) io::throw_element_error(c, "needs a MechanicalObject in its node");
        guarded(c, [&] {
            auto& f = info.node->add_constraint<FixedProjectiveConstraint>(*s);
            std::vector<Index> idx;
            for (PointId i : io::get_indices(c, "indices")) idx.push_back(i);
            for (Index i : idx)
                if (std::size_t(i) >= s->num_dofs())
                    io::throw_attribute_error(c, "indices", "index " + std::to_string(i) + " out of range (" +
                                                                std::to_string(s->num_dofs()) + " DOFs)");
            f.set_indices(std::move(idx));
            f.set_fix_all(io::get_bool_or(c, "fixAll", false));
            init_steps_.push_back({1, [p = &f] { p->init(); }, &c});
            const bool all = io::get_bool_or(c, "fixAll", false);
            role(c, [p = &f, s, all] {
                return all ? "fixes all " + counted(s->num_dofs(), "DOF", "DOFs")
                           : "fixes " + std::to_string(p->indices().size()) + " of " + counted(s->num_dofs(), "DOF", "DOFs");
            });
        });
        note_unread_attributes(c);
    }

    void build_solver(const SceneComponent& c, const std::vector<const SceneComponent*>& physics, Node& node) {
        guarded(c, [&] {
            if (c.type == "EulerExplicitSolver") {
                if (io::get_bool_or(c, "symplectic", true) == false)
                    io::throw_attribute_error(c, "symplectic", "only the symplectic scheme is supported");
                auto& explicit_solver = node.set_ode_solver<EulerExplicitSolver>();
                init_steps_.push_back({1, [p = &explicit_solver, n = &node] { p->init(*n); }, &c});
                role(c, [n = &node] { return "symplectic explicit Euler over this subtree (" + subtree_dofs(*n) + ")"; });
                return;
            }
            auto& s = node.set_ode_solver<EulerImplicitSolver>();
            init_steps_.push_back({1, [p = &s, n = &node] { p->init(*n); }, &c});
            scene_.implicit_solvers_.push_back(&s);
            scene_.implicit_solver_paths_.push_back(node_path(node));
            s.rayleigh_stiffness = io::get_double_or(c, "rayleighStiffness", 0.0);
            s.rayleigh_mass = io::get_double_or(c, "rayleighMass", 0.0);
            s.vdamping = nonnegative(c, "vdamping", 0.0);
            s.first_order = io::get_bool_or(c, "firstOrder", false);
            s.trapezoidal_scheme = io::get_bool_or(c, "trapezoidalScheme", false);
            s.newton.enabled = io::get_bool_or(c, "newton", false);  // beyond SOFA
            if (s.newton.enabled) newton_solvers_.emplace_back(&s, &node);
            const auto newton_iterations = io::get_int_or(c, "newtonIterations", s.newton.max_iterations);
            if (newton_iterations < 1 || newton_iterations > 1000)
                io::throw_attribute_error(c, "newtonIterations", "must be between 1 and 1000");
            s.newton.max_iterations = int(newton_iterations);
            s.newton.tolerance = nonnegative(c, "newtonTolerance", s.newton.tolerance);
            const SceneComponent* linear = nullptr;
            for (const SceneComponent* l : physics) {
                if (l->type != "CGLinearSolver") continue;
                const auto it = io::get_int_or(*l, "iterations", 25);
                if (it < 1 || std::uint64_t(it) > options_.max_cg_iterations)
                    io::throw_attribute_error(*l, "iterations",
                                              "must be between 1 and " + std::to_string(options_.max_cg_iterations));
                s.cg.iterations = int(it);
                s.cg.tolerance = nonnegative(*l, "tolerance", 1e-5);
                s.cg.threshold = nonnegative(*l, "threshold", 1e-5);
                linear = l;
                role(*l, [p = &s] {
                    return "conjugate gradient of the implicit Euler solver: at most " + std::to_string(p->cg.iterations) +
                           " iterations, tolerance " + num(p->cg.tolerance) + ", threshold " + num(p->cg.threshold);
                });
                break;
            }
            role(c, [p = &s, n = &node, linear] {
                std::string out = "implicit Euler over this subtree (" + subtree_dofs(*n) + ")";
                if (p->rayleigh_stiffness != 0 || p->rayleigh_mass != 0)
                    out += ", Rayleigh stiffness " + num(p->rayleigh_stiffness) + " mass " + num(p->rayleigh_mass);
                if (p->vdamping != 0) out += ", vdamping " + num(p->vdamping);
                if (p->first_order) out += ", first order";
                if (p->trapezoidal_scheme) out += ", trapezoidal";
                if (p->newton.enabled)
                    out += ", Newton (at most " + std::to_string(p->newton.max_iterations) + " iterations, contact geometry re-detected)";
                if (linear == nullptr) out += "; no CGLinearSolver in its node: CG with SOFA's defaults";
                return out;
            });
        });
        note_unread_attributes(c);
    }

    /// "N independent DOFs in K states" of a solver's subtree (mapped states not counted).
    static std::string subtree_dofs(const Node& n) {
        std::size_t dofs = 0, states = 0;
        std::function<void(const Node&)> visit = [&](const Node& x) {
            if (x.state() != nullptr && x.mapping() == nullptr) {
                dofs += x.state()->num_dofs();
                ++states;
            }
            for (const auto& child : x.children()) visit(*child);
        };
        visit(n);
        return counted(dofs, "DOF", "DOFs") + " in " + counted(states, "state", "states");
    }

    // ---- collision models ---------------------------------------------------------------------
    CollisionModelParams model_params(const SceneComponent& c, const NodeInfo& info) {
        CollisionModelParams p;
        p.name = c.name.empty() ? c.type : c.name;
        p.active = io::get_bool_or(c, "active", true);
        p.moving = io::get_bool_or(c, "moving", true);
        p.simulated = io::get_bool_or(c, "simulated", true);
        p.self_collision = io::get_bool_or(c, "selfCollision", false);
        p.contact_distance = nonnegative(c, "proximity", 0.0);
        p.contact_distance = nonnegative(c, "contactDistance", p.contact_distance);
        p.contact_stiffness = nonnegative(c, "contactStiffness", 10.0);
        p.contact_friction = nonnegative(c, "contactFriction", 0.0);
        p.contact_restitution = nonnegative(c, "contactRestitution", 0.0);
        p.contact_response = io::get_string(c, "contactResponse").value_or("");
        for (PointId g : io::get_indices(c, "group")) p.group.push_back(g);
        p.node = info.node_id;
        p.both_side = io::get_bool_or(c, "bothSide", false);
        return p;
    }

    std::vector<double> radii(const SceneComponent& c, std::string_view attr) {
        if (!c.has(attr)) return {};
        if (!io::is_link(c.find(attr)->value)) return io::get_doubles(c, attr);
        const io::LinkTarget t = io::resolve_link(c, attr);
        if (t.component == nullptr || io::component_category(t.component->type) != io::ComponentCategory::loader)
            io::throw_attribute_error(c, attr, "must link to a SphereLoader's listRadius");
        return mesh_of(*t.component).radii;
    }

    void build_collision_model(const SceneComponent& c, NodeInfo& info) {
        BaseState* state = info.node->state();
        if (state == nullptr) io::throw_element_error(c, "needs a MechanicalObject in its node");
        std::unique_ptr<CollisionModel> model;
        guarded(c, [&] {
            CollisionModelParams p = model_params(c, info);
            auto* v = dynamic_cast<Vec3Object*>(state);
            auto* r = dynamic_cast<Rigid3Object*>(state);
            const std::string& t = c.type;
            if (t == "SphereCollisionModel") {
                const double radius = positive(c, "radius", 1.0);
                std::vector<double> list = radii(c, "listRadius");
                for (double x : list)
                    if (!(x > 0)) io::throw_attribute_error(c, "listRadius", "radii must be > 0");
                const bool want_rigid = is_rigid_template(c, c.template_name) || (c.template_name.empty() && r != nullptr);
                if (want_rigid) {
                    if (!r) io::throw_element_error(c, "template Rigid3d needs a Rigid3d MechanicalObject");
                    model = std::make_unique<RigidSphereModel>(*r, radius, std::move(list), p);
                } else {
                    if (!v) io::throw_element_error(c, "needs a Vec3d MechanicalObject (or template=\"Rigid3d\")");
                    model = std::make_unique<SphereModel>(*v, radius, std::move(list), p);
                }
            } else if (t == "CylinderCollisionModel") {
                if (!r) io::throw_element_error(c, "needs a Rigid3d MechanicalObject");
                auto m = std::make_unique<CylinderModel>(*r, positive(c, "defaultRadius", 0.5), positive(c, "defaultHeight", 2.0),
                                                         io::get_vec3_or(c, "defaultLocalAxis", Vec3::UnitY()), p);
                m->radii = io::get_doubles(c, "radii");
                m->heights = io::get_doubles(c, "heights");
                m->local_axes = io::get_vec3_list(c, "localAxes");  // beyond SOFA (no scene name there)
                model = std::move(m);
            } else {
                if (!v) io::throw_element_error(c, "needs a Vec3d MechanicalObject");
                if (t == "PointCollisionModel") {
                    model = std::make_unique<PointModel>(*v, c.has("topology") ? &topology_of(c, info) : info.topology, p);
                } else if (t == "LineCollisionModel") {
                    model = std::make_unique<LineModel>(*v, topology_of(c, info), p);
                } else if (t == "TriangleCollisionModel") {
                    auto m = std::make_unique<TriangleModel>(*v, topology_of(c, info), p);
                    m->compute_normals = io::get_bool_or(c, "computeNormals", true);
                    model = std::move(m);
                } else {
                    model = std::make_unique<TetrahedronModel>(*v, topology_of(c, info), p);
                }
            }
        });
        note_unread_attributes(c);
        std::string shape;
        if (c.type == "SphereCollisionModel")
            shape = c.has("listRadius") ? ", radii from listRadius" : ", radius " + num(io::get_double_or(c, "radius", 1.0));
        role(c, [this, m = model.get(), shape] {
            const CollisionModelParams& p = m->params();
            std::string out = element_words(m->type(), m->size()) + shape;
            if (!p.simulated && !p.moving) out += ", static obstacle (simulated=0, moving=0)";
            else if (!p.simulated) out += ", not simulated";
            else if (!p.moving) out += ", simulated, not moving";
            else out += ", simulated";
            out += ", contactStiffness " + num(p.contact_stiffness);
            if (p.contact_distance > 0) out += ", contactDistance " + num(p.contact_distance);
            if (p.self_collision) out += ", self-collision";
            if (!p.active) out += ", inactive";
            if (!p.group.empty()) {
                out += ", group";
                for (int g : p.group) out += " " + std::to_string(g);
            }
            if (!p.contact_response.empty()) out += ", contactResponse " + p.contact_response;
            std::string in;
            for (const ScenePipeline& sp : scene_.pipelines_)
                for (const SceneCollisionModel* x : sp.models)
                    if (x->model.get() == m) in += (in.empty() ? "" : ", ") + sp.name;
            return out + (in.empty() ? "; in no collision pipeline: never collides" : "; pipeline " + in);
        });
        scene_.models_.push_back(SceneCollisionModel{std::move(model), info.node, &c});
    }

    // ---- collision pipelines ------------------------------------------------------------------
    static bool is_below(const SceneNode* n, const SceneNode* ancestor) {
        for (; n != nullptr; n = n->parent)
            if (n == ancestor) return true;
        return false;
    }
    /// First component of a type family in the subtree of `n` (its own components first).
    const SceneComponent* first_below(const SceneNode& n, bool (*pred)(std::string_view)) const {
        for (const auto& c : n.components)
            if (pred(c->type) && !ignored_.count(c.get())) return c.get();
        for (const auto& child : n.children)
            if (const SceneComponent* c = first_below(*child, pred)) return c;
        return nullptr;
    }

    IntersectionParams intersection_params(const SceneComponent& c) {
        return guarded(c, [&] {
            IntersectionParams p;
            if (c.type == "DiscreteIntersection") {
                p = IntersectionParams::discrete();
            } else {
                p = c.type == "MinProximityIntersection" ? IntersectionParams::min_proximity()
                    : c.type == "LocalMinDistance"       ? IntersectionParams::local_min_distance()
                                                         : IntersectionParams::new_proximity();
                p.alarm_distance = nonnegative(c, "alarmDistance", 1.0);
                p.contact_distance = nonnegative(c, "contactDistance", 0.5);
                if (p.contact_distance > p.alarm_distance)
                    io::throw_attribute_error(c, "contactDistance", "must not exceed alarmDistance");
                if (c.type != "LocalMinDistance") p.use_line_line = io::get_bool_or(c, "useLineLine", p.use_line_line);
                if (c.type == "MinProximityIntersection") {
                    p.use_sphere_triangle = io::get_bool_or(c, "useSphereTriangle", p.use_sphere_triangle);
                    p.use_point_point = io::get_bool_or(c, "usePointPoint", p.use_point_point);
                    p.use_line_point = io::get_bool_or(c, "useLinePoint", p.use_line_point);
                    p.use_surface_normals = io::get_bool_or(c, "useSurfaceNormals", p.use_surface_normals);
                }
                if (c.type == "LocalMinDistance") {  // SOFA's LocalMinDistance Data and defaults
                    p.filter_intersection = io::get_bool_or(c, "filterIntersection", p.filter_intersection);
                    p.angle_cone = nonnegative(c, "angleCone", p.angle_cone);
                    p.cone_factor = nonnegative(c, "coneFactor", p.cone_factor);
                    p.use_lmd_filters = io::get_bool_or(c, "useLMDFilters", p.use_lmd_filters);
                }
            }
            p.enable_beyond_sofa_pairs = io::get_bool_or(c, "beyondSofaPairs", false);  // beyond SOFA
            // Beyond SOFA: fixes of SOFA bugs (default: reproduce SOFA), then the command line's.
            if (const auto names = io::get_string(c, "fixSofaQuirks")) {
                std::istringstream words(*names);
                for (std::string w; words >> w;)
                    if (!enable_sofa_quirk_fix(p.quirks, w))
                        io::throw_attribute_error(c, "fixSofaQuirks", "unknown SOFA quirk '" + w + "' (" + quirk_choices() + ")");
            }
            if (const auto policy = io::get_string(c, "zeroDistanceNormal")) {
                if (*policy == "fallbackX") p.quirks.zero_distance_normal = ZeroDistanceNormal::FallbackX;
                else if (*policy == "drop") p.quirks.zero_distance_normal = ZeroDistanceNormal::Drop;
                else if (*policy == "sofaNaN") p.quirks.zero_distance_normal = ZeroDistanceNormal::SofaNaN;
                else io::throw_attribute_error(c, "zeroDistanceNormal", "expected fallbackX, drop or sofaNaN");
            }
            p.quirks = merge_sofa_quirk_fixes(p.quirks, options_.sofa_quirk_fixes);
            p.validate();
            return p;
        });
    }

    /// The response; the friction spring's time step defaults to the scene's dt (responseParams
    /// `timeStep` overrides it).
    CollisionResponse response_of(const SceneComponent& c, double dt) {
        return guarded(c, [&] {
            const std::string response = io::get_string(c, "response").value_or(std::string(kPenaltyResponseName));
            ContactResponseParameters base;
            base.penalty.time_step = dt;
            return CollisionResponse(response, io::get_string(c, "responseParams").value_or(""), base);
        });
    }

    void add_pipeline(const SceneComponent* pipeline_component, const std::string& name, const SceneComponent* intersection,
                      const SceneComponent* response, const std::vector<const SceneCollisionModel*>& models, Node& host) {
        Simulation& sim = *scene_.simulation_;
        ScenePipeline sp;
        sp.name = name;
        const IntersectionParams params = intersection_params(*intersection);
        sp.intersection = params.method;
        ContactPipelineOptions options;
        options.detection = options_.exhaustive_detection ? ContactDetection::exhaustive : ContactDetection::bvh;
        options.threads = options_.threads;
        options.attach_hook = false;  // the scene's hook runs every pipeline (SOFA's composite)
        const double dt = options_.dt ? *options_.dt : sim.root().dt();
        sp.pipeline = std::make_unique<ContactPipeline>(sim, params, response_of(*response, dt), &host, options);
        for (const SceneCollisionModel* m : models) sp.pipeline->add_model(*m->model, *m->node);
        sp.models = models;
        std::string summary = intersection_method_short_name(sp.intersection);
        if (sp.intersection != IntersectionMethod::Discrete)
            summary += " (alarm " + num(params.alarm_distance) + " m, contact " + num(params.contact_distance) + " m)";
        summary += ", " + counted(models.size(), "collision model", "collision models") + ", response " +
                   (sp.pipeline->response().base_response_name().empty() ? std::string("none")
                                                                          : sp.pipeline->response().base_response_name());
        role(*pipeline_component, [summary] { return "collision pipeline: " + summary; });
        used_pieces_.insert({intersection, response});
        scene_.pipelines_.push_back(std::move(sp));
    }

    void build_pipelines() {
        for (const SceneComponent* p : pipeline_components_) {
            Node& host = *node_of_.at(p->node);
            if (p->type == "CollisionPipeline") {
                const SceneComponent* inter = first_below(*p->node, is_intersection_type);
                const SceneComponent* resp = first_below(*p->node, [](std::string_view t) { return t == "CollisionResponse"; });
                const SceneComponent* broad = first_below(*p->node, [](std::string_view t) { return t == "BruteForceBroadPhase"; });
                const SceneComponent* narrow = first_below(*p->node, [](std::string_view t) { return t == "BVHNarrowPhase"; });
                if (!inter || !resp || !broad || !narrow) {
                    role(*p, [] { return "incomplete: no contact will be detected (see the notes)"; });
                    scene_.build_warnings_.push_back(
                        p->file + ":" + std::to_string(p->line) + ": " + p->describe() +
                        ": no contact will be detected: SOFA needs an intersection method, a CollisionResponse, "
                        "a BruteForceBroadPhase and a BVHNarrowPhase below the pipeline's node");
                    continue;
                }
                std::vector<const SceneCollisionModel*> models;
                for (const auto& m : scene_.models_)
                    if (is_below(m.component->node, p->node)) models.push_back(&m);
                used_pieces_.insert({broad, narrow});
                add_pipeline(p, p->name.empty() ? p->type : p->name, inter, resp, models, host);
            } else {  // CompositeCollisionPipeline
                std::string subs;
                for (const io::LinkTarget& t : io::resolve_links(*p, "subCollisionPipelines")) {
                    if (t.component == nullptr || t.component->type != "SubCollisionPipeline")
                        io::throw_attribute_error(*p, "subCollisionPipelines", "must link to SubCollisionPipeline components");
                    const SceneComponent& sub = *t.component;
                    auto linked = [&](const char* attr, bool (*pred)(std::string_view)) {
                        const io::LinkTarget l = io::resolve_link(sub, attr);
                        if (l.component == nullptr || !pred(l.component->type))
                            io::throw_attribute_error(sub, attr, "links to the wrong kind of component");
                        return l.component;
                    };
                    const SceneComponent* inter = linked("intersectionMethod", is_intersection_type);
                    const SceneComponent* resp = linked("contactManager", [](std::string_view x) { return x == "CollisionResponse"; });
                    used_pieces_.insert(linked("broadPhaseDetection", [](std::string_view x) { return x == "BruteForceBroadPhase"; }));
                    used_pieces_.insert(linked("narrowPhaseDetection", [](std::string_view x) { return x == "BVHNarrowPhase"; }));
                    std::vector<const SceneCollisionModel*> models;
                    for (const io::LinkTarget& m : io::resolve_links(sub, "collisionModels")) {
                        const auto it = std::find_if(scene_.models_.begin(), scene_.models_.end(),
                                                     [&](const SceneCollisionModel& x) { return x.component == m.component; });
                        if (it == scene_.models_.end())
                            io::throw_attribute_error(sub, "collisionModels", "links to something that is not a collision model");
                        models.push_back(&*it);
                    }
                    add_pipeline(&sub, sub.name.empty() ? sub.type : sub.name, inter, resp, models, *node_of_.at(sub.node));
                    subs += (subs.empty() ? "" : ", ") + (sub.name.empty() ? sub.type : sub.name);
                }
                role(*p, [subs] { return "composite: runs the sub-pipelines " + subs + " each step"; });
            }
        }
        describe_pipeline_pieces();
        Simulation& sim = *scene_.simulation_;
        // Beyond SOFA: a solver with newton="1" re-runs the contact geometry at each iterate.
        for (auto [solver, solver_node] : newton_solvers_) {
            for (ScenePipeline& p : scene_.pipelines_) p.pipeline->attach_newton(*solver);
            std::vector<ContactPipeline*> all;
            for (ScenePipeline& p : scene_.pipelines_) all.push_back(p.pipeline.get());
            const Node* subtree = solver_node;
            solver->newton.update_geometry = [all, subtree] {
                for (ContactPipeline* p : all) p->update_geometry(*subtree);
            };
        }
        if (!scene_.pipelines_.empty()) {
            Scene* scene = &scene_;
            sim.collision_hook = [scene](Simulation&) {
                for (ScenePipeline& p : scene->pipelines_) {
                    p.pipeline->update();
                    scene->timings_.detection_seconds += p.pipeline->last_timings().detection_seconds;
                    scene->timings_.response_seconds += p.pipeline->last_timings().response_seconds;
                }
            };
        }
    }

    /// Roles of the animation loop, intersection methods, responses, broad and narrow phases.
    void describe_pipeline_pieces() {
        for (const SceneComponent* c : check_.physics) {
            const std::string& t = c->type;
            const bool used = used_pieces_.count(c) != 0;
            std::string d;
            if (t == "DefaultAnimationLoop") {
                d = "each step: collision with the positions of the previous step's end, then the solvers";
            } else if (!used && (is_intersection_type(t) || t == "CollisionResponse" || t == "BruteForceBroadPhase" ||
                                 t == "BVHNarrowPhase")) {
                d = "not used by any collision pipeline";
            } else if (is_intersection_type(t)) {
                const IntersectionParams p = intersection_params(*c);
                d = t == "DiscreteIntersection" ? "contact only where elements overlap"
                                                : "alarm distance " + num(p.alarm_distance) + " m, contact distance " +
                                                      num(p.contact_distance) + " m";
                if (p.enable_beyond_sofa_pairs) d += ", beyond-SOFA pairs on";
                d += ", SOFA quirk fixes: " + quirk_summary(p.quirks);
            } else if (t == "CollisionResponse") {
                const std::string r = io::get_string(*c, "response").value_or(std::string(kPenaltyResponseName));
                const std::string params = io::get_string(*c, "responseParams").value_or("");
                d = "response " + (r.empty() ? std::string("none: no contact is created") : r) +
                    (params.empty() ? "" : ", parameters " + params);
            } else if (t == "BruteForceBroadPhase") {
                d = "model pairs kept by SOFA's rules (active, not both non-simulated, self-collision, groups)";
            } else if (t == "BVHNarrowPhase") {
                d = options_.exhaustive_detection ? "element pairs by SOFA's exhaustive loop (--exhaustive)"
                                                  : "element pairs from one BVH per model (the same outputs as SOFA's loop)";
            } else {
                continue;
            }
            role(*c, [d] { return d; });
        }
    }

    const io::SceneFile& file_;
    const BuildOptions& options_;
    Scene& scene_;
    std::filesystem::path scene_dir_;
    io::SceneCheck check_;
    std::set<const SceneComponent*> ignored_;
    std::map<const SceneNode*, NodeInfo> infos_;
    std::unordered_map<const SceneNode*, Node*> node_of_;
    std::map<const SceneComponent*, io::MeshData> meshes_;
    std::unordered_map<const SceneComponent*, Vec3Object*> vec3_states_;
    std::vector<const SceneComponent*> pipeline_components_;
    std::vector<std::string> attribute_warnings_;
    std::vector<std::pair<EulerImplicitSolver*, Node*>> newton_solvers_;
    std::vector<std::pair<const SceneComponent*, std::function<std::string()>>> roles_;
    std::set<const SceneComponent*> used_pieces_;  ///< intersection, response, broad and narrow phases in use
    struct InitStep {
        int phase;  ///< 0: mappings (top-down), 1: masses, force fields, constraints, solvers
        std::function<void()> init;
        const SceneComponent* component;
    };
    std::vector<InitStep> init_steps_;
    int node_count_ = 0;
};

// ---- Scene ----------------------------------------------------------------------------------------
Scene::Scene() : simulation_(std::make_unique<Simulation>()) {}
Scene::~Scene() {
    pipelines_.clear();  // they remove what they added to the graph
}

double Scene::dt() const { return const_cast<Simulation&>(*simulation_).root().dt(); }

void Scene::step() {
    timings_ = StepTimings{};
    const auto t0 = std::chrono::steady_clock::now();
    simulation_->step();
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timings_.solve_seconds = std::max(0.0, total - timings_.detection_seconds - timings_.response_seconds);
    solver_stats_ = StepSolverStats{};
    for (const EulerImplicitSolver* s : implicit_solvers_) {
        solver_stats_.cg_iterations += s->last_step_cg_iterations();
        solver_stats_.cg_limit_reached = solver_stats_.cg_limit_reached || s->last_step_cg_limit_reached();
        if (s->newton.enabled) {
            solver_stats_.newton_iterations += s->last_newton_iterations();
            solver_stats_.newton_unconverged = solver_stats_.newton_unconverged || !s->last_newton_converged();
        }
    }
}

std::vector<std::pair<std::string, const EulerImplicitSolver*>> Scene::implicit_solvers() const {
    std::vector<std::pair<std::string, const EulerImplicitSolver*>> out;
    for (std::size_t i = 0; i < implicit_solvers_.size(); ++i) out.emplace_back(implicit_solver_paths_[i], implicit_solvers_[i]);
    return out;
}

bool Scene::uses_newton() const {
    return std::any_of(implicit_solvers_.begin(), implicit_solvers_.end(),
                       [](const EulerImplicitSolver* s) { return s->newton.enabled; });
}

const std::vector<output::ContactRecord>& Scene::contacts() const {
    // Same live pairs as the cached list (same force fields and point states, same order)?
    std::size_t n = 0;
    bool same = true;
    for (const ScenePipeline& p : pipelines_) {
        for (const ContactGraphEntry& e : p.pipeline->graph_entries()) {
            if (e.contact == nullptr || e.force_field == nullptr) continue;
            same = same && n < contacts_cache_.size() && contacts_cache_[n].field == &e.force_field->field() &&
                   contacts_cache_[n].state1 == e.point_states[0] && contacts_cache_[n].state2 == e.point_states[1];
            ++n;
        }
    }
    if (same && n == contacts_cache_.size()) return contacts_cache_;
    contacts_cache_.clear();
    for (const ScenePipeline& p : pipelines_) {
        for (const ContactGraphEntry& e : p.pipeline->graph_entries()) {
            if (e.contact == nullptr || e.force_field == nullptr) continue;
            output::ContactRecord r;
            r.name = e.contact->model1().name() + "-" + e.contact->model2().name();
            r.field = &e.force_field->field();
            r.state1 = e.point_states[0];
            r.state2 = e.point_states[1];
            contacts_cache_.push_back(std::move(r));
        }
    }
    return contacts_cache_;
}

std::string Scene::role(const io::SceneComponent& component) const {
    const auto it = roles_.find(&component);
    return it == roles_.end() ? std::string() : it->second;
}

const io::SceneComponent* Scene::component_of(const void* built) const {
    const auto it = built_from_.find(built);
    return it == built_from_.end() ? nullptr : it->second;
}

const Node* Scene::node_of(const io::SceneNode& node) const {
    const auto it = nodes_.find(&node);
    return it == nodes_.end() ? nullptr : it->second;
}

double Scene::kinetic_energy() const {
    double e = 0.0;
    for (const BaseMass* m : masses_) e += m->kinetic_energy();
    return e;
}

namespace {
double force_field_energy(const Node& node) {
    double e = 0.0;
    for (const auto& ff : node.force_fields()) e += ff->potential_energy();
    for (const auto& child : node.children()) e += force_field_energy(*child);
    return e;
}
}  // namespace

double Scene::potential_energy() const {
    double e = stored_energy();
    for (std::size_t i = 0; i < masses_.size(); ++i) e += masses_[i]->gravity_potential_energy(mass_nodes_[i]->gravity());
    return e;
}

double Scene::stored_energy() const { return force_field_energy(simulation_->root()); }

double Scene::gravity_energy_scale(double length) const {
    double e = 0.0;
    for (std::size_t i = 0; i < masses_.size(); ++i) {
        const double m = masses_[i]->total_mass();
        e += m * mass_nodes_[i]->gravity().norm() * length;
    }
    return e;
}

std::vector<std::string> Scene::warnings() const {
    std::vector<std::string> out = build_warnings_;
    for (const ScenePipeline& p : pipelines_) {
        for (const std::string& s : p.pipeline->skipped_pairs()) out.push_back(p.name + ": " + s);
        for (const std::string& s : p.pipeline->response().warnings()) out.push_back(p.name + ": " + s);
    }
    return out;
}

void apply_overrides(io::SceneFile& file, const std::vector<std::string>& overrides) {
    std::vector<io::Override> parsed;
    parsed.reserve(overrides.size());
    for (const std::string& o : overrides) parsed.push_back(io::parse_override(o));
    const auto reads = [](const io::SceneElement& e, std::string_view attribute) {
        const std::vector<std::string> known = read_attributes(e.type);
        return std::find(known.begin(), known.end(), attribute) != known.end();
    };
    const auto known = [](const io::SceneElement& e) {
        const std::vector<std::string> names = read_attributes(e.type);
        if (names.empty()) return std::string("it reads none");
        std::string out = "it reads:";
        for (const std::string& n : names) out += " " + n;
        return out;
    };
    io::apply_overrides(file, parsed, reads, known);
}

std::unique_ptr<Scene> build_scene(io::SceneFile file, const BuildOptions& options) {
    if (!options.overrides.empty()) apply_overrides(file, options.overrides);
    auto scene = std::make_unique<Scene>();
    scene->file_ = std::move(file);
    SceneBuilder(scene->file_, options, *scene).build();
    return scene;
}

std::unique_ptr<Scene> load_scene(const std::filesystem::path& file, const BuildOptions& options) {
    return build_scene(io::parse_scene_file(file), options);
}

}  // namespace penalty::scene
