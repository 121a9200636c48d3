// Builds a Simulation from a parsed SOFA scene (include/penalty/scene/scene.hpp): the node walk
// and SOFA's order inside a node; each component is built by the function its ComponentSpec
// names (src/scene/builder/<family>.cpp).
#include "scene/builder/scene_builder.hpp"
#include "scene/live_edits.hpp"

#include "penalty/io/data_path.hpp"
#include "penalty/io/overrides.hpp"
#include "penalty/output/format.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <sstream>
#include <stdexcept>

namespace penalty::scene {

using io::SceneComponent;
using io::SceneNode;

// ---- the builder ------------------------------------------------------------------------------

SceneBuilder::SceneBuilder(const io::SceneFile& file, const BuildOptions& options, Scene& scene)
    : file_(file), options_(options), scene_(scene), scene_dir_(file.directory()) {}

void SceneBuilder::build() {
    if (!file_.root) throw io::SceneError(file_.path.string() + ": empty scene");
    check_ = validate(file_);
    for (const SceneComponent* c : check_.ignored) ignored_.insert(c);
    if (!check_.ignored.empty()) warn(check_.summary);

    Simulation& sim = simulation();
    sim.set_threads(options_.threads);  // validated by the command line / the Python module
    build_node(*file_.root, sim.root());
    if (options_.dt) {
        if (!(*options_.dt >= kMinTimeStep && *options_.dt <= kMaxTimeStep))
            throw std::invalid_argument("dt: the time step given to the scene (" + output::format_number(*options_.dt) +
                                        ") is out of range [1e-100, 86400] s");
        sim.root().set_dt(*options_.dt);
    }
    for (std::size_t i = 0; i < deferred_builds_.size(); ++i) {  // (a deferred build may defer another)
        const std::function<void()> build = deferred_builds_[i].init;
        guarded(*deferred_builds_[i].component, build);
    }
    build_unread_data_engines();
    for (auto& m : scene_.models_) guarded(*m.component, [&] { m.model->validate(); });
    // Initialise every component once here, in Simulation::init's order (states and mappings
    // top-down, then masses, force fields, constraints, solvers), so that an error names its
    // component and line; Simulation::init then repeats it (idempotent).
    for (int phase : {0, 1})
        for (const InitStep& step : init_steps_)
            if (step.phase == phase) guarded(*step.component, step.init);
    build_collision_pipelines(*this);
    build_tunnelling_guard(*this);
    for (const auto& w : attribute_warnings_) warn(w);
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
    wire_topological_changes();
    for (const auto& [c, describe] : roles_) scene_.roles_[c] = describe();
    for (const BaseForceField* ff : sim.unevaluated_force_fields())
        if (const SceneComponent* c = scene_.component_of(ff); c != nullptr && scene_.roles_.count(c))
            scene_.roles_[c] +=
                "; never evaluated: no ODE solver above it (SOFA's solve visits only the interaction "
                "force fields of such a node)";
    for (const auto& [sn, info] : nodes_) scene_.nodes_[sn] = info.node;
    Scene::LiveEdits::wire_engines(scene_);  // engines over moving states (live_engines.cpp)
    // What the engines computed and the loaders read, for the scene's live Data (live_data.hpp).
    scene_.engine_indices_ = std::move(engine_indices_);
    scene_.engine_meshes_ = std::move(engine_meshes_);
    scene_.loader_meshes_ = std::move(meshes_);
}

void SceneBuilder::rethrow_naming(const io::SceneElement& c, const std::exception& e) {
    // The library names its class ("UniformMass: ..."); the element is named already.
    std::string_view what = e.what();
    const std::string own_prefix = c.type + ": ";
    if (what.substr(0, own_prefix.size()) == own_prefix) what.remove_prefix(own_prefix.size());
    io::throw_element_error(c, std::string(what));
}

void SceneBuilder::role(const SceneComponent& c, std::function<std::string()> describe) {
    roles_.emplace_back(&c, std::move(describe));
}

void SceneBuilder::note_unread_attributes(const io::SceneElement& c) {
    for (const std::string& a : unread_attributes(c))
        attribute_warnings_.push_back(c.file + ":" + std::to_string(c.find(a)->line) + ": " + c.describe() +
                                      ": attribute '" + a + "' is not read by penalty (ignored)");
}

void SceneBuilder::add_init(int phase, const SceneComponent& c, std::function<void()> init) {
    init_steps_.push_back({phase, std::move(init), &c});
}

void SceneBuilder::record_implicit_solver(EulerImplicitSolver& s, const Node& n) {
    scene_.implicit_solvers_.push_back(&s);
    scene_.implicit_solver_paths_.push_back(node_path(n));
}

const io::MeshData& SceneBuilder::mesh_of(const SceneComponent& loader) {
    auto it = meshes_.find(&loader);
    if (it == meshes_.end()) {
        it = meshes_
                 .emplace(&loader, io::load_scene_mesh(loader, scene_dir_, options_.data_dirs,
                                                       options_.sofa_quirk_fixes.fix_mesh_loader_float_scale))
                 .first;
        std::string file;
        // (GridMeshCreator reads no file: SOFA's scenes give it filename="nofile")
        if (const auto name = io::get_string(loader, "filename"); name && loader.type != "GridMeshCreator")
            file = io::resolve_data_file(*name, scene_dir_, options_.data_dirs).string() + ": ";
        role(loader, [file, counts = mesh_counts(it->second)] { return "reads " + file + counts; });
        bool scale_read_whole = true;
        static_cast<void>(io::mesh_loader_scale(loader, &scale_read_whole));
        if (!scale_read_whole)
            warn(loader.file + ":" + std::to_string(loader.find("scale")->line) + ": " + loader.describe() +
                 ": scale '" + *io::get_string(loader, "scale") +
                 "' is not one number: scale 1 (SOFA's MeshLoader::parse reads it so)");
    }
    return it->second;
}

const io::MeshData& SceneBuilder::linked_mesh(const Attributes& a, std::string_view attr) {
    const io::LinkTarget src = a.link(attr);
    if (src.component == nullptr || component_category(src.component->type) != ComponentCategory::loader)
        a.fail(attr, "must link to a mesh loader");
    return mesh_of(*src.component);
}

std::vector<Vec3> SceneBuilder::linked_positions(const Attributes& a, std::string_view attr) {
    const io::LinkTarget t = a.link(attr);
    if (t.component == nullptr) a.fail(attr, "link must name a loader, a topology or a MechanicalObject");
    const SceneComponent& src = *t.component;
    if (const io::MeshData* engine = engine_mesh(src, t.data)) return engine->positions;
    const ComponentSpec* spec = find_component(src.type);
    // a topology's `points` is its `position` (MeshTopology's alias)
    const bool topology_points = t.data == "points" && spec != nullptr && spec->family == ComponentFamily::topology;
    if (!t.data.empty() && t.data != "position" && t.data != "rest_position" && !topology_points)
        a.fail(attr, "cannot read positions from data '" + t.data + "'");
    if (component_category(src.type) == ComponentCategory::loader) return mesh_of(src).positions;
    if (spec != nullptr && spec->family == ComponentFamily::state) {
        const auto it = vec3_states_.find(&src);
        if (it != vec3_states_.end()) return it->second->position;
        // a state not built yet (a topology of the state's node links to it: topologies come
        // first): the positions its own `position` data gives, inline or from a non-state link
        const Attributes state_attributes(src);
        if (state_attributes.has("position")) {
            if (!state_attributes.is_link("position")) return state_attributes.points("position");
            const SceneComponent* inner = state_attributes.link("position").component;
            const ComponentSpec* inner_spec = inner != nullptr ? find_component(inner->type) : nullptr;
            if (inner_spec != nullptr && inner_spec->family != ComponentFamily::state)
                return linked_positions(state_attributes, "position");
        }
        a.fail(attr, "links to " + src.describe() + ", which is not a built Vec3d state");
    }
    if (spec != nullptr && spec->family == ComponentFamily::topology) {
        if (const BuiltTopology* built = built_topology(src); built != nullptr) {
            // a grid's `position`: GridTopology::computePointList at its init (getPoint(i))
            if (built->grid) return built->grid->points();
            return built->positions;
        }
    }
    a.fail(attr, "cannot read positions from " + src.describe());
}

void SceneBuilder::build_unread_data_engines() {
    // SOFA computes an engine only when something reads an output: one no simulation component
    // reads cannot change the numbers, so a failure here is a note, not an error (its inputs may
    // be a visual model's or a mapped state's, which penalty builds later or not at all).
    io::for_each_component(*file_.root, [&](const SceneComponent& c) {
        const ComponentSpec* spec = find_component(c.type);
        if (spec == nullptr || spec->family != ComponentFamily::data_engine || built_data_engines_.count(&c) != 0)
            return;
        try {
            build_data_engine(c);
        } catch (const std::exception& e) {
            warn(std::string(e.what()) + " (no simulation component reads this engine: ignored)");
        }
    });
}

void SceneBuilder::build_data_engine(const SceneComponent& c) {
    const ComponentSpec* spec = find_component(c.type);
    if (spec == nullptr || spec->family != ComponentFamily::data_engine || ignored_.count(&c) != 0) return;
    if (!built_data_engines_.insert(&c).second) return;  // built, or being built (a loop of links)
    const auto node = nodes_.find(c.node);
    if (node == nodes_.end())
        io::throw_element_error(c,
                                "is read through a link before its node is built (penalty builds nodes "
                                "depth first: put it in the reading node or an ancestor)");
    spec->build(*this, c, node->second);
}

bool SceneBuilder::rebuilding() const { return scene_.live_->rebuilt; }

void SceneBuilder::record_engine_reals(const SceneComponent& engine, const std::string& data,
                                       std::vector<double> values) {
    scene_.live_->engine_reals[{&engine, data}] = std::move(values);
}

void SceneBuilder::refuse_engine_reals(const SceneComponent& engine, std::string why) {
    scene_.live_->refused_reals[&engine] = std::move(why);
}

const io::MeshData* SceneBuilder::engine_mesh(const SceneComponent& engine, const std::string& data) {
    build_data_engine(engine);
    const auto it = engine_meshes_.find({&engine, data});
    return it == engine_meshes_.end() ? nullptr : &it->second;
}

/// A list of elements read into a list of indices, as SOFA's BaseData::genericCopyValueFrom copies
/// a parent of another type: per element, its first min(1, points per element) values, so each
/// element gives its first point (`quadList="@roi.quadsInROI"` reads the quads' first points).
std::vector<PointId> SceneBuilder::first_points_of_elements(const io::LinkTarget& t) {
    const io::MeshData* mesh = engine_mesh(*t.component, t.data);
    if (mesh == nullptr) return {};
    std::vector<PointId> out;
    const auto firsts = [&](const auto& list) {
        for (const auto& e : list) out.push_back(e[0]);
    };
    firsts(mesh->edges);
    firsts(mesh->triangles);
    firsts(mesh->quads);
    firsts(mesh->tetrahedra);
    firsts(mesh->hexahedra);
    return out;
}

std::vector<PointId> SceneBuilder::indices(const Attributes& a, std::string_view attr) {
    if (!a.is_link(attr)) return a.indices(attr);
    const io::LinkTarget t = a.link(attr);
    if (t.component == nullptr || t.data.empty()) a.fail(attr, "link must name an engine's data (@engine.indices)");
    build_data_engine(*t.component);
    const auto it = engine_indices_.find({t.component, t.data});
    if (it != engine_indices_.end()) return it->second;
    if (const io::MeshData* m = engine_mesh(*t.component, t.data); m != nullptr && m->positions.empty())
        return first_points_of_elements(t);  // an element output (edgesInROI, quadsInROI, ...)
    a.fail(attr, "cannot read indices from data '" + t.data + "' of " + t.component->describe() +
                     " (penalty reads the indices of a BoxROI built before this component)");
}

namespace {

/// SOFA's Node holds one component of each of these families (a NodeSingle link: adding a second
/// replaces the first, SingleLink::add). penalty refuses a second one, naming both lines, except
/// where the replacement is harmless and SOFA's examples rely on it: a second topology (the node's
/// topology is the last one, see build_node) and a second animation loop of the same type.
void check_once_per_node(const std::vector<const SceneComponent*>& physics) {
    static constexpr std::array<std::pair<ComponentFamily, std::string_view>, 6> kinds{{
        {ComponentFamily::state, "mechanical state"},
        {ComponentFamily::mass, "mass"},
        {ComponentFamily::mapping, "mapping"},
        {ComponentFamily::ode_solver, "ODE solver"},
        {ComponentFamily::linear_solver, "linear solver"},
        {ComponentFamily::animation_loop, "animation loop"},
    }};
    for (const auto& [family, what] : kinds) {
        const SceneComponent* first = nullptr;
        for (const SceneComponent* c : physics) {
            if (find_component(c->type)->family != family) continue;
            if (first == nullptr) {
                first = c;
                continue;
            }
            if (family == ComponentFamily::animation_loop && c->type == first->type) continue;
            io::throw_element_error(*c, "a node holds one " + std::string(what) + ", and this node already has " +
                                            first->describe() + " at line " + std::to_string(first->line));
        }
    }
}

}  // namespace

void SceneBuilder::build_node(const SceneNode& sn, Node& node) {
    NodeBuild& info = nodes_[&sn];
    info.node = &node;
    info.scene_node = &sn;
    info.node_id = node_count_++;
    node_of_[&sn] = &node;
    guarded(sn, [&] {
        if (auto dt = io::get_double(sn, "dt")) {
            if (!(*dt > 0)) io::throw_attribute_error(sn, "dt", "must be > 0");
            if (sn.parent == nullptr) node.set_dt(*dt);
        }
        if (auto g = io::get_vec3(sn, "gravity"); g && sn.parent == nullptr) node.set_gravity(*g);
    });
    // SOFA's Node::updateContext copies the parent's gravity and dt over a child node's own
    // (Context::copySimulationContext): only the root's attributes count (a Gravity component
    // still sets a subtree's gravity).
    if (sn.parent != nullptr)
        for (const char* attr : {"gravity", "dt"})
            if (sn.has(attr))
                warn(node_path(sn) + ": " + attr + " of a child node is ignored (SOFA copies the parent's over it)");
    note_unread_attributes(sn);

    for (const auto& c : sn.components)
        if (!ignored_.count(c.get())) info.physics.push_back(c.get());
    const auto has = [&](ComponentFamily family) {
        return std::any_of(info.physics.begin(), info.physics.end(),
                           [&](const SceneComponent* c) { return find_component(c->type)->family == family; });
    };
    // SOFA's order in a node (where it changes numbers): context, topology, state (positions from
    // the topology), mapping, masses/force fields/constraints in file order, solver, collision
    // models in file order (the broad phase's model order), then the collision pipelines' parts.
    const auto build_family = [&](std::initializer_list<ComponentFamily> families) {
        for (const SceneComponent* c : info.physics) {
            const ComponentSpec& spec = *find_component(c->type);
            if (std::find(families.begin(), families.end(), spec.family) != families.end()) spec.build(*this, *c, info);
        }
    };
    using F = ComponentFamily;
    build_family({F::gravity});
    check_once_per_node(info.physics);
    const SceneNode* parent_solver = sn.parent ? nodes_[sn.parent].solver_node : nullptr;
    info.solver_node = parent_solver ? parent_solver : (has(F::ode_solver) ? &sn : nullptr);
    info.mapped = has(F::mapping);
    // Topologies in file order; SOFA's node keeps the last one (NodeSingle), so each one starts
    // from a clean slate and the last one built is the node's topology. An earlier one is still
    // built (a link `@name` to it is refused: penalty resolves links to a node's topology).
    const SceneComponent* previous_topology = nullptr;
    for (const SceneComponent* c : info.physics) {
        const ComponentSpec& spec = *find_component(c->type);
        if (spec.family != F::topology) continue;
        if (previous_topology != nullptr)
            warn(c->file + ":" + std::to_string(c->line) + ": " + c->describe() + " replaces " +
                 previous_topology->describe() + " (line " + std::to_string(previous_topology->line) +
                 ") as the node's topology: a SOFA node keeps its last topology");
        previous_topology = c;
        info.topology = nullptr;
        info.topology_positions.clear();
        info.grid.reset();
        info.sparse_grid.reset();
        info.topology_component = nullptr;
        spec.build(*this, *c, info);
        built_topologies_[c] = {info.topology, info.topology_positions, info.grid};
    }
    build_family({F::topology_helper});
    build_family({F::state});
    build_family({F::mapping});
    // (data engines: built when a link reads them, or after every node when none does)
    build_family({F::mass, F::force_field, F::constraint, F::engine});
    build_family({F::ode_solver});
    build_family({F::collision_model});
    build_family({F::animation_loop, F::linear_solver, F::solver_part, F::collision_pipeline, F::composite_pipeline,
                  F::sub_pipeline, F::broad_phase, F::narrow_phase, F::intersection, F::contact_manager});

    if (info.state_component) record_state(sn, info);
    for (const auto& child : sn.children) build_node(*child, node.add_child(child->name));
}

void SceneBuilder::record_state(const SceneNode& sn, const NodeBuild& info) {
    output::StateRecord r;
    r.name = std::string(info.node->state()->state_name());
    r.node_path = sn.path();
    r.state = info.node->state();
    r.topology = info.topology;
    r.mapped = info.mapped;
    r.in_solver_subtree = info.solver_node != nullptr;
    r.mass = info.node->mass();
    scene_.states_.push_back(std::move(r));
}

/// StateRecord::radius (VTK point scalars) of every state a sphere model covers, once the scene
/// is initialised (a mapped state gets its size from its mapping's init).
void SceneBuilder::record_sphere_radii() {
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

/// A note per triangle collision model with zero-area triangles (coincident or collinear corners
/// at init): they have no normal, so SOFA's kernels skip or mis-orient them and a body can pass
/// through. Zero area: |(b − a) × (c − a)| ≤ 1e-12 · (longest edge)².
void SceneBuilder::warn_degenerate_triangles() {
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
        const SceneComponent& c = *m.component;
        warn(c.file + ":" + std::to_string(c.line) + ": " + c.describe() + ": " + std::to_string(count) + " of " +
             std::to_string(tri->size()) + " triangles have zero area (first: triangle " + std::to_string(first) +
             "); they make no reliable contact");
    }
}

}  // namespace penalty::scene
