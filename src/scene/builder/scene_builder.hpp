#pragma once
// The scene builder: turns a parsed scene (io::SceneFile) into a Scene, node by node, each
// component by the build function its ComponentSpec names (include/penalty/scene/components.hpp).
// This header is what the family files (states_and_topologies.cpp, masses_and_force_fields.cpp,
// mappings_and_constraints.cpp, solvers.cpp, collision.cpp) share: the record of a node being
// built, the attribute reader, and the builder's services (errors naming the component, mesh
// loading, links to built objects, `penalty info` roles, init order).
#include "penalty/collision/models.hpp"
#include "penalty/io/scene_mesh.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/sparse_grid_topology.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "scene/display.hpp"
#include "scene/live_engines.hpp"

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace penalty::scene {

/// What the builder knows about one scene node while it builds it and its children.
struct NodeBuild {
    Node* node = nullptr;
    const io::SceneNode* scene_node = nullptr;
    const io::SceneComponent* state_component = nullptr;
    const MeshTopology* topology = nullptr;  ///< MeshTopology, or the grid's element lists
    std::vector<Vec3> topology_positions;    ///< points given to the topology (may be empty)
    std::optional<RegularGridTopology> grid;
    std::optional<SparseGridTopology> sparse_grid;  ///< SparseGridTopology (src/scene/builder/sparse_grid.cpp)
    const io::SceneComponent* topology_component = nullptr;
    bool mapped = false;
    const io::SceneNode* solver_node = nullptr;      ///< first node from the root owning an ODE solver (null: none)
    int node_id = 0;                                 ///< depth-first index (collision same-node rule)
    std::vector<const io::SceneComponent*> physics;  ///< the node's physics components, file order
};

/// Typed reading of a component's attributes through its ComponentSpec: the default, unit and
/// check of each attribute are the spec's (one place for each); reading an attribute the spec
/// does not declare is a penalty bug (std::logic_error), so that the registry lists every
/// attribute the builder reads.
class Attributes {
public:
    explicit Attributes(const io::SceneComponent& component);

    [[nodiscard]] const io::SceneComponent& component() const { return component_; }
    [[nodiscard]] bool has(std::string_view name) const;
    /// The value, or the spec's default; ValueCheck applied.
    [[nodiscard]] double real(std::string_view name) const;
    /// The value, or `fallback` (a default that depends on the scene); ValueCheck applied.
    [[nodiscard]] double real_or(std::string_view name, double fallback) const;
    /// The value, or the spec's default / `fallback`; ValueCheck applied.
    [[nodiscard]] std::int64_t integer(std::string_view name) const;
    [[nodiscard]] std::int64_t integer_or(std::string_view name, std::int64_t fallback) const;
    [[nodiscard]] bool boolean(std::string_view name) const;
    [[nodiscard]] bool boolean_or(std::string_view name, bool fallback) const;
    [[nodiscard]] Vec3 vector3(std::string_view name) const;
    [[nodiscard]] Vec3 vector3_or(std::string_view name, const Vec3& fallback) const;
    [[nodiscard]] std::optional<Vec3> optional_vector3(std::string_view name) const;
    [[nodiscard]] std::optional<double> optional_real(std::string_view name) const;
    /// The text, or the spec's default ("" when none).
    [[nodiscard]] std::string text(std::string_view name) const;
    [[nodiscard]] std::optional<std::string> optional_text(std::string_view name) const;
    [[nodiscard]] std::vector<double> numbers(std::string_view name) const;
    /// `values` (read from attribute `name`) as ints: each an integer in int's range, else the
    /// attribute's error (no conversion out of range).
    [[nodiscard]] std::vector<int> as_ints(std::string_view name, const std::vector<double>& values) const;
    [[nodiscard]] std::vector<PointId> indices(std::string_view name) const;
    [[nodiscard]] std::vector<Vec3> points(std::string_view name) const;
    [[nodiscard]] std::vector<RigidFrame> frames(std::string_view name) const;
    template <std::size_t N>
    [[nodiscard]] std::vector<std::array<PointId, N>> elements(std::string_view name) const {
        return io::get_elements<N>(component_, declared(name).name);
    }
    [[nodiscard]] io::LinkTarget link(std::string_view name) const;
    [[nodiscard]] std::vector<io::LinkTarget> links(std::string_view name) const;
    /// True when the attribute holds a link (`@...`).
    [[nodiscard]] bool is_link(std::string_view name) const;

    [[noreturn]] void fail(std::string_view name, const std::string& what) const;

private:
    const AttributeSpec& declared(std::string_view name) const;
    /// When attribute `name` is a link to another component's Data (`@loader.translation`): a
    /// copy of this component whose attribute holds that Data's text (as written there, following
    /// links, else its ComponentSpec default); nullopt when the attribute is not a link.
    [[nodiscard]] std::optional<io::SceneComponent> linked_value(std::string_view name) const;
    /// The component the typed readers parse: this one, or linked_value's copy kept in `storage`.
    const io::SceneComponent& value_source(std::string_view name, std::optional<io::SceneComponent>& storage) const;
    void check(const AttributeSpec& spec, double value) const;
    const io::SceneComponent& component_;
    const ComponentSpec& spec_;
};

class SceneBuilder {
public:
    SceneBuilder(const io::SceneFile& file, const BuildOptions& options, Scene& scene);
    void build();
    /// Makes the scene's topologies that have a modifier changeable, and everything that uses them
    /// follow their changes (src/scene/topology/wiring.cpp).
    void wire_topological_changes();

    // ---- services for the family build functions ----------------------------------------------
    [[nodiscard]] const BuildOptions& options() const { return options_; }
    [[nodiscard]] const io::SceneFile& file() const { return file_; }
    /// The scene file's folder (data files resolve against it, then the data dirs).
    [[nodiscard]] const std::filesystem::path& scene_dir() const { return scene_dir_; }
    [[nodiscard]] Scene& scene() { return scene_; }
    [[nodiscard]] Simulation& simulation() { return *scene_.simulation_; }

    /// Runs `f`, turning the library's own exceptions (std::invalid_argument, ...) into a
    /// SceneError naming `element` (io::LoadError passes through).
    template <class F>
    auto guarded(const io::SceneElement& element, F&& f) -> decltype(f()) {
        try {
            return f();
        } catch (const io::LoadError&) {
            throw;
        } catch (const std::exception& e) {
            rethrow_naming(element, e);
        }
    }
    /// Records how `penalty info` describes what `c` became; evaluated once the scene is built.
    void role(const io::SceneComponent& c, std::function<std::string()> describe);
    /// Notes each attribute of `element` penalty does not read.
    void note_unread_attributes(const io::SceneElement& element);
    /// A build note for `penalty info` and `penalty run`.
    void warn(std::string note) { scene_.build_warnings_.push_back(std::move(note)); }
    /// Runs `init` once the graph is built: phase 0 (mappings, top-down), then phase 1 (masses,
    /// force fields, constraints, solvers), in build order; an error names `c`.
    void add_init(int phase, const io::SceneComponent& c, std::function<void()> init);
    /// Records that `built` (a mass, force field, ...) comes from `c` (Scene::component_of).
    void record_origin(const void* built, const io::SceneComponent& c) { scene_.built_from_[built] = &c; }

    /// The mesh of a loader (or of a MeshTopology/MechanicalObject `filename`), loaded once.
    const io::MeshData& mesh_of(const io::SceneComponent& loader);
    /// The mesh of the loader an attribute links to (`src="@loader"`).
    const io::MeshData& linked_mesh(const Attributes& a, std::string_view attr);
    /// Positions named by a data link (`@loader.position`, `@[-1].position`, `@../dofs.position`).
    std::vector<Vec3> linked_positions(const Attributes& a, std::string_view attr);
    /// The points of `attr` (which the scene sets): inline, or through a data link (linked_positions).
    std::vector<Vec3> point_data(const Attributes& a, std::string_view attr) {
        return a.is_link(attr) ? linked_positions(a, attr) : a.points(attr);
    }
    /// Records an index list an engine computed (BoxROI's `indices`), read through links `@engine.data`.
    void record_engine_indices(const io::SceneComponent& engine, const std::string& data,
                               std::vector<PointId> indices) {
        engine_indices_[{&engine, data}] = std::move(indices);
    }
    /// Records a list of index lists an engine computed (ClusteringEngine's `cluster`), read
    /// through a link `@engine.data` (engine_index_lists).
    void record_engine_index_lists(const io::SceneComponent& engine, const std::string& data,
                                   std::vector<std::vector<PointId>> lists) {
        engine_index_lists_[{&engine, data}] = std::move(lists);
    }
    /// The lists recorded by `record_engine_index_lists`, or null; the engine is built first.
    [[nodiscard]] const std::vector<std::vector<PointId>>* engine_index_lists(const io::SceneComponent& engine,
                                                                              const std::string& data) {
        build_data_engine(engine);
        const auto it = engine_index_lists_.find({&engine, data});
        return it == engine_index_lists_.end() ? nullptr : &it->second;
    }
    /// Records points and element lists an engine computed (SubsetTopology's `pointsInROI`,
    /// `trianglesInROI`, ...), read through links `@engine.data` to positions or element lists.
    void record_engine_mesh(const io::SceneComponent& engine, const std::string& data, io::MeshData mesh) {
        engine_meshes_[{&engine, data}] = std::move(mesh);
    }
    /// Records a list of reals an engine computed (ValuesFromPositions' `values`), read from the
    /// scene's Data (Scene::data).
    void record_engine_reals(const io::SceneComponent& engine, const std::string& data, std::vector<double> values);
    /// Makes a read of `engine`'s lists of reals raise `why` (SOFA computes them from what penalty
    /// does not reproduce).
    void refuse_engine_reals(const io::SceneComponent& engine, std::string why);
    /// The mesh data recorded by `record_engine_mesh`, or null; a data engine (ComponentFamily::
    /// data_engine) not built yet is built first.
    [[nodiscard]] const io::MeshData* engine_mesh(const io::SceneComponent& engine, const std::string& data);
    /// The first point of each element of an engine's element output (SOFA's conversion of a link
    /// between Data of different types), empty when `t` names none.
    [[nodiscard]] std::vector<PointId> first_points_of_elements(const io::LinkTarget& t);
    /// The moving points attribute `attr` links: a built Vec3d MechanicalObject's `position`
    /// (`@dofs.position`, which the solve writes) or a point output of an engine that runs on read
    /// (`@transform.output_position`); nullopt otherwise (src/scene/live_engines.cpp).
    [[nodiscard]] std::optional<LivePoints> moving_input(const Attributes& a, std::string_view attr);
    /// The written boxes of BoxROI `c` that its selection uses (Scene::note_box_roi_write), or null.
    [[nodiscard]] const BoxRoiWrite* box_roi_write(const io::SceneComponent& c) const;
    /// True when this build is the scene's build again after writes while it ran (Scene::rebuild).
    [[nodiscard]] bool rebuilding() const;
    /// Makes engine `a.component()` (a kind of kLiveEngineKinds) run `evaluate` again when a reader
    /// reads one of its outputs after its input points, or an input it follows, moved (SOFA's
    /// DDGNode::updateIfDirty); `points` are its input points at the build. Nothing when no such
    /// input links moving points or its `doUpdate` is 0; a warning names each other input that
    /// links data that changes while the scene runs (src/scene/live_engines.cpp).
    void add_live_engine(const Attributes& a, const std::vector<Vec3>& points, LiveEngine::Evaluate evaluate);
    /// Builds a data engine once: when a link first reads one of its outputs (SOFA evaluates
    /// engines on demand), else in its node's file order. Anything else: nothing.
    void build_data_engine(const io::SceneComponent& c);
    /// Attribute `attr` as indices: inline, or a link `@engine.data` to a list recorded by an engine
    /// built before (in file order).
    std::vector<PointId> indices(const Attributes& a, std::string_view attr);
    /// The node that holds the state a component of `node` acts on: `node` itself when it has a
    /// MechanicalObject, else its nearest ancestor with one (SOFA's Node::getMechanicalState
    /// searches the parents); null when none has.
    const NodeBuild* state_owner(const NodeBuild& node);
    /// The Vec3d state of the node (or of its nearest ancestor with a state), or an error naming `c`.
    Vec3Object& vec3_state(const io::SceneComponent& c, const NodeBuild& node);
    /// The state of the node (or of its nearest ancestor with a state), or an error naming `c`.
    BaseState& state(const io::SceneComponent& c, const NodeBuild& node);
    /// The state an attribute links to (`object1="@../dofs"`, `@node`: that node's state), or null
    /// when its node is not built yet; an error naming the attribute when the link names no state.
    BaseState* linked_state(const Attributes& a, std::string_view attr);
    /// The same for one target `t` of attribute `attr` (an attribute holding several links).
    BaseState* linked_state(const Attributes& a, std::string_view attr, const io::LinkTarget& t);
    /// Runs `build` once every node is built (a component linking states of nodes below its own,
    /// which SOFA resolves at init); an error names `c`.
    void after_nodes(const io::SceneComponent& c, std::function<void()> build);
    /// An interaction force field's build: now, or once every node is built when its `object1`
    /// or `object2` links a state not built yet (SOFA resolves both at init); an error names `c`.
    void build_when_ends_exist(const io::SceneComponent& c, const Attributes& a, const std::function<void()>& build);
    /// The topology `topology="@..."` links to, else the node's.
    const MeshTopology& topology_of(const Attributes& a, const NodeBuild& node);
    /// A topology component as built (kept when a later topology of its node replaces it as the
    /// node's topology, for links such as `src="@grid"`).
    struct BuiltTopology {
        const MeshTopology* topology = nullptr;
        std::vector<Vec3> positions;
        std::optional<RegularGridTopology> grid;  ///< a RegularGridTopology's grid
    };
    /// The topology built from `c`, or null (not a topology, or not built yet).
    [[nodiscard]] const BuiltTopology* built_topology(const io::SceneComponent& c) const {
        const auto it = built_topologies_.find(&c);
        return it == built_topologies_.end() ? nullptr : &it->second;
    }
    /// Records (again) what the topology component of `info` holds: after its build, and after a
    /// topological mapping replaced its elements (SOFA's links read the Data as they are then).
    void record_built_topology(const NodeBuild& info) {
        if (info.topology_component != nullptr)
            built_topologies_[info.topology_component] = {info.topology, info.topology_positions, info.grid};
    }
    /// The build record of a node of the file (built already: ancestors of the current node).
    NodeBuild& node_build(const io::SceneNode& n) { return nodes_[&n]; }
    const std::map<const io::SceneNode*, NodeBuild>& node_builds() const { return nodes_; }
    Node& node_of(const io::SceneNode& n) { return *node_of_.at(&n); }
    /// A Vec3d state built from `c` (for links to its positions).
    void record_vec3_state(const io::SceneComponent& c, Vec3Object& s) { vec3_states_[&c] = &s; }

    /// Keeps a topology alive for the scene's lifetime.
    const MeshTopology* add_topology(std::unique_ptr<MeshTopology> t) {
        scene_.topologies_.push_back(std::move(t));
        return scene_.topologies_.back().get();
    }
    /// A mass of node `n` (kinetic and gravity energies).
    void record_mass(BaseMass& m, const Node& n, const io::SceneComponent& c) {
        scene_.masses_.push_back(&m);
        scene_.mass_nodes_.push_back(&n);
        record_origin(&m, c);
    }

    // collision (src/scene/builder/collision.cpp)
    void add_collision_model(SceneCollisionModel model) { scene_.models_.push_back(std::move(model)); }
    [[nodiscard]] std::vector<SceneCollisionModel>& collision_models() { return scene_.models_; }
    [[nodiscard]] std::vector<ScenePipeline>& pipelines() { return scene_.pipelines_; }
    void add_pipeline_component(const io::SceneComponent& c) { pipeline_components_.push_back(&c); }
    void add_intersection(const io::SceneComponent& c, const IntersectionParams& p) { intersections_[&c] = p; }
    [[nodiscard]] const IntersectionParams& intersection_params(const io::SceneComponent& c) const {
        return intersections_.at(&c);
    }
    /// An implicit solver with newton="1" and its node (re-runs contact geometry per iterate).
    void add_newton_solver(EulerImplicitSolver& s, Node& n) { newton_solvers_.emplace_back(&s, &n); }
    void record_implicit_solver(EulerImplicitSolver& s, const Node& n);
    /// Components a collision pipeline uses (the others are described as unused).
    void mark_used(const io::SceneComponent* c) { used_pieces_.insert(c); }
    [[nodiscard]] bool is_used(const io::SceneComponent* c) const { return used_pieces_.count(c) != 0; }
    [[nodiscard]] const std::vector<const io::SceneComponent*>& pipeline_components() const {
        return pipeline_components_;
    }
    [[nodiscard]] const std::vector<std::pair<EulerImplicitSolver*, Node*>>& newton_solvers() const {
        return newton_solvers_;
    }
    [[nodiscard]] const SceneCheck& check() const { return check_; }
    /// True for a component the scene check ignored (visual).
    [[nodiscard]] bool is_ignored(const io::SceneComponent* c) const { return ignored_.count(c) != 0; }

private:
    [[noreturn]] static void rethrow_naming(const io::SceneElement& element, const std::exception& e);
    void build_node(const io::SceneNode& sn, Node& node);
    void record_state(const io::SceneNode& sn, const NodeBuild& info);
    /// The data engines no link has read, built after every node (a failure is a note).
    void build_unread_data_engines();
    void record_sphere_radii();
    void warn_degenerate_triangles();

    const io::SceneFile& file_;
    const BuildOptions& options_;
    Scene& scene_;
    std::filesystem::path scene_dir_;
    SceneCheck check_;
    std::set<const io::SceneComponent*> ignored_;
    std::map<const io::SceneNode*, NodeBuild> nodes_;
    std::unordered_map<const io::SceneNode*, Node*> node_of_;
    std::map<const io::SceneComponent*, io::MeshData> meshes_;
    std::unordered_map<const io::SceneComponent*, Vec3Object*> vec3_states_;
    std::map<std::pair<const io::SceneComponent*, std::string>, std::vector<PointId>> engine_indices_;
    std::map<std::pair<const io::SceneComponent*, std::string>, io::MeshData> engine_meshes_;
    std::map<std::pair<const io::SceneComponent*, std::string>, std::vector<std::vector<PointId>>> engine_index_lists_;
    std::set<const io::SceneComponent*> built_data_engines_;
    std::map<const io::SceneComponent*, BuiltTopology> built_topologies_;
    std::map<const io::SceneComponent*, IntersectionParams> intersections_;
    std::vector<const io::SceneComponent*> pipeline_components_;
    std::vector<std::string> attribute_warnings_;
    std::vector<std::pair<EulerImplicitSolver*, Node*>> newton_solvers_;
    std::vector<std::pair<const io::SceneComponent*, std::function<std::string()>>> roles_;
    std::set<const io::SceneComponent*> used_pieces_;
    struct InitStep {
        int phase;
        std::function<void()> init;
        const io::SceneComponent* component;
    };
    std::vector<InitStep> init_steps_;
    std::vector<InitStep> deferred_builds_;  ///< after_nodes (phase unused)
    int node_count_ = 0;
};

/// A component's build that only notes its attributes as unread (a component whose presence is
/// all penalty needs, or one it accepts without simulating).
inline void note_unread_attributes_only(SceneBuilder& b, const io::SceneComponent& c, NodeBuild&) {
    b.note_unread_attributes(c);
}

/// The collision pipelines, once every node is built (src/scene/builder/collision.cpp).
void build_collision_pipelines(SceneBuilder& builder);
/// The tunnelling guard the pipelines' noTunnelling attributes (or BuildOptions::no_tunnelling)
/// ask for, once the pipelines are built (src/scene/builder/tunnelling_guard.cpp).
void build_tunnelling_guard(SceneBuilder& builder);

// ---- helpers shared by the family files --------------------------------------------------------
/// SOFA's default name of an unnamed component (see scene_builder.cpp).
[[nodiscard]] std::string sofa_default_name(const io::SceneComponent& c);
/// True for Rigid3d templates, false for Vec3d ones (and none); an error for others.
[[nodiscard]] bool is_rigid_template(const io::SceneComponent& c, std::string_view name);
/// Refuses a Rigid3d template ("template 'Rigid3d' is not supported (Vec3d only)") for the
/// components penalty has on Vec3d points only.
void require_vec3_template(const io::SceneComponent& c);
/// `youngModulus` (poisson false: each > 0) or `poissonRatio` (each in [0, 0.5)): one value or one
/// per element, `fallback` when absent. SOFA replaces an out-of-range value by its default with a
/// warning (BaseLinearElasticityFEMForceField::checkYoungModulus / checkPoissonRatio); penalty
/// refuses it, naming the attribute.
[[nodiscard]] std::vector<double> elasticity_values(const Attributes& a, std::string_view name,
                                                    std::vector<double> fallback, bool poisson);
using display::counted;
using display::element_counts;
using display::mesh_counts;
inline std::string num(double v) { return display::number(v); }
inline std::string vec(const Vec3& v) { return display::vector(v); }
using display::node_path;

}  // namespace penalty::scene
