#pragma once
/// @file
/// A runnable scene built from a parsed SOFA `.scn` file (io::SceneFile): the Simulation graph,
/// the collision models, one ContactPipeline per SOFA collision pipeline, and the list of states
/// the writers see. See docs/scene-format.md ("Building the simulation") and
/// docs/sofa-compatibility.md for the components and attributes, and what each becomes.
///
/// Build order (SOFA's, where it changes numbers): nodes depth first, file order; in a node, the
/// topology, then the MechanicalObject (positions from `position`, `src`, the node's topology, in
/// that priority; then `translation`/`rotation`/`scale3d`), mass, force fields, constraints,
/// mapping, solver, collision models. Collision models are registered with their pipelines in
/// depth-first order, which is the model order SOFA's broad phase uses.

#include "penalty/collision/collision_model.hpp"
#include "penalty/core/pointer_index.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/io/scene_mesh.hpp"
#include "penalty/mechanics/topology_container.hpp"
#include "penalty/output/state_record.hpp"
#include "penalty/output/vtk_writer.hpp"
#include "penalty/scene/live_data.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/tunnelling_guard.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::scene {

/// Options of build_scene (the command line's `penalty run` flags).
/// The range of a time step given outside the scene (`--dt`, `load_scene(dt=)`, BuildOptions::dt):
/// [1e-100 s, a day]. The lower end is the scene files' smallest nonzero magnitude (io); a day
/// is beyond any step a contact simulation takes (larger is a typo).
inline constexpr double kMinTimeStep = 1e-100;
inline constexpr double kMaxTimeStep = 86400.0;

struct BuildOptions {
    std::vector<std::filesystem::path> data_dirs;  ///< `--data-dir`, searched after the scene's folder
    /// Overrides the root node's dt (s); std::invalid_argument outside [kMinTimeStep, kMaxTimeStep].
    std::optional<double> dt;
    int threads = 0;  ///< threads of the narrow phase and of independent solvers (0: TBB's default)
    /// Detection algorithm: BVH narrow phase (default) or SOFA's exhaustive pair loop; both give
    /// the same outputs in the same order.
    bool exhaustive_detection = kFidelityDefaults.exhaustive_detection;
    /// SOFA HEAD's two summation and contact orders (on by default; `--no-sofa-head-orders`
    /// turns them off; docs/sofa-compatibility.md, "SOFA HEAD's orders"): the ODE solvers sum
    /// computeForce and addMBKv through SOFA's MappingGraph (OdeSolver::sofa_mapping_graph_order)
    /// and the contacts follow SOFA's stable-id maps (CollisionResponse::sofa_stable_id_order).
    /// Off: the visitors' summation order and contacts by the models' scene order.
    bool sofa_head_orders = kFidelityDefaults.sofa_head_orders;
    /// Largest number of DOFs of a state or points of a grid: 10⁷ by default (a step costs about
    /// 1.5 kB per DOF, so this keeps a run within a 24 GB machine). The fuzz targets lower it.
    std::uint64_t max_dofs = 10'000'000;
    /// Largest `iterations` of a CGLinearSolver: 10⁶ by default (a typo cannot hang a run).
    std::uint64_t max_cg_iterations = 1'000'000;
    /// Fixes of SOFA bugs turned on for every intersection method of the scene
    /// (`--fix-sofa-quirk NAME`), in addition to those its `fixSofaQuirks` attribute turns on.
    SofaQuirkFixes sofa_quirk_fixes;
    /// Attribute overrides `PATH.attribute=value` (`--set`, io/overrides.hpp), applied in order to
    /// the parsed tree before anything is built (see scene::apply_overrides).
    std::vector<std::string> overrides;
    /// `--no-tunnelling MODE` (beyond SOFA, docs/no-tunnelling.md): the tunnelling guard's mode
    /// for the whole scene, over the pipelines' noTunnelling attributes; unset: theirs.
    std::optional<TunnellingMode> no_tunnelling;
    /// `--reduction blocked` (beyond SOFA, docs/performance.md "Blocked reductions"): every
    /// EulerImplicitSolver's CG sums its dot products in fixed blocks on several threads (the same
    /// bits at any thread count; SOFA's for a solver of at most 4 096 DOFs). Off: SOFA's chains.
    bool blocked_reductions = false;
    /// Builds the components whose code is outside the library (SofaPython3's Python force fields
    /// and mappings, live_data.hpp); null: a scene with such components is an error.
    std::shared_ptr<ExternalComponents> external;
};

/// One collision model of the scene and where it comes from.
struct SceneCollisionModel {
    std::unique_ptr<CollisionModel> model;
    Node* node = nullptr;                           ///< node holding the model's state
    const io::SceneComponent* component = nullptr;  ///< its `<...CollisionModel>` element
};

/// One SOFA collision pipeline (CollisionPipeline, or a SubCollisionPipeline of a
/// CompositeCollisionPipeline) as built.
struct ScenePipeline {
    std::string name;                                                    ///< component name or type
    IntersectionMethod intersection = IntersectionMethod::NewProximity;  ///< named by intersection_method_short_name
    std::unique_ptr<ContactPipeline> pipeline;
    std::vector<const SceneCollisionModel*> models;  ///< the models it detects, registration order
};

/// Wall-clock time of the phases of the last step (s).
struct StepTimings {
    double detection_seconds = 0.0;  ///< broad + narrow phase
    double response_seconds = 0.0;   ///< contact creation/update and scene-graph update
    double solve_seconds = 0.0;      ///< explicit forces, ODE solvers, propagation
    double guard_seconds = 0.0;      ///< the tunnelling guard's continuous detection, snapshots, restores
};

/// What the implicit solvers did in the last step (summed over every EulerImplicitSolver).
struct StepSolverStats {
    int cg_iterations = 0;            ///< CG iterations, all linear solves of the step
    bool cg_limit_reached = false;    ///< a linear solve stopped on its `iterations` limit
    int newton_iterations = 0;        ///< Newton iterates (solvers with newton="1")
    bool newton_unconverged = false;  ///< a Newton solve stopped on newtonIterations
};

class Scene;
class TopologyRuntime;
std::unique_ptr<Scene> build_scene(io::SceneFile file, const BuildOptions& options);

class Scene {
public:
    Scene();
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    /// The parsed scene file this scene was built from.
    [[nodiscard]] const io::SceneFile& file() const { return file_; }
    [[nodiscard]] Simulation& simulation() { return *simulation_; }
    [[nodiscard]] const Simulation& simulation() const { return *simulation_; }
    /// Time step of the root node (s).
    [[nodiscard]] double dt() const;
    /// Runs one step (collision at the start, then the solvers) and records its timings.
    void step();
    [[nodiscard]] const StepTimings& last_timings() const { return timings_; }
    [[nodiscard]] const StepSolverStats& last_solver_stats() const { return solver_stats_; }
    /// True if the scene has an implicit solver with Newton iterations (newton="1").
    [[nodiscard]] bool uses_newton() const;
    /// True if the scene has an implicit solver (CG statistics are meaningful).
    [[nodiscard]] bool uses_cg() const { return !implicit_solvers_.empty(); }
    /// `--reduction blocked` after the build (BuildOptions::blocked_reductions): every implicit
    /// solver's CG from the next step on, and the scene rebuilt from its text keeps it.
    void set_blocked_reductions(bool on);
    /// The implicit solvers with the path of their node, in build order (depth first).
    [[nodiscard]] std::vector<std::pair<std::string, const EulerImplicitSolver*>> implicit_solvers() const;

    /// Every MechanicalObject of the scene file, depth first (parent before children, file
    /// order), with its topology, mapped flag and solver-subtree flag. Contact-point states the
    /// pipelines add are not in this list.
    [[nodiscard]] const std::vector<output::StateRecord>& states() const { return states_; }
    /// The live contact pairs of every pipeline (force field and its two point states) as of the
    /// end of the last step (or the build). step() rebuilds the list only when the live pairs
    /// changed (no per-step allocation while the pairs stay); the reference stays valid, and
    /// its contents are replaced at the next step.
    [[nodiscard]] const std::vector<output::ContactRecord>& contacts() const { return contacts_; }
    /// The tunnelling guard (beyond SOFA, docs/no-tunnelling.md) over every pipeline of the
    /// scene; mode off removes it (SOFA's step). std::invalid_argument for invalid options.
    void set_tunnelling(const TunnellingOptions& options);
    /// Its options (mode off without a guard).
    [[nodiscard]] TunnellingOptions tunnelling_options() const;
    /// What it saw in the last step; nullptr without a guard.
    [[nodiscard]] const TunnellingReport* tunnelling_report() const;
    [[nodiscard]] const std::vector<SceneCollisionModel>& collision_models() const { return models_; }
    [[nodiscard]] const std::vector<ScenePipeline>& pipelines() const { return pipelines_; }
    /// Σ ½ vᵀ M v over the states that have a mass (J).
    [[nodiscard]] double kinetic_energy() const;
    /// Potential energy (J): gravity (−Σ m·g·x, each mass with its node's gravity, origin at 0)
    /// plus every force field's stored energy (springs, FEM, contacts) as of its last force
    /// evaluation.
    [[nodiscard]] double potential_energy() const;
    /// The force fields' part of potential_energy() (J).
    [[nodiscard]] double stored_energy() const;
    /// potential_energy() from its stored_energy(): `stored` plus each mass's gravity potential,
    /// added in mass order (J; the same bits as potential_energy() when `stored` is
    /// stored_energy()).
    [[nodiscard]] double potential_energy_from(double stored) const;
    /// Σ m·|g|·h (J) over the masses of the states a step moves (in an ODE solver's subtree):
    /// the energy of dropping every moving body through the box [lo, hi] along its gravity, with
    /// h = Σ_j |ĝ_j|·(hi_j − lo_j) the box's extent along ĝ (or its diagonal when that extent is
    /// 0). A static obstacle's mass (a floor outside every solver) cannot fall and is not counted.
    [[nodiscard]] double gravity_energy_scale(const Vec3& lo, const Vec3& hi) const;
    /// Notes for the user: ignored visual components (one line), attributes penalty does not
    /// read, pairs the intersection method does not detect, response warnings.
    [[nodiscard]] std::vector<std::string> warnings() const;
    /// What the builder made of a component of the file, one line for `penalty info` (e.g.
    /// "Vec3d state, 81 DOFs, static: in no solver's subtree, never moves"); "" for a component
    /// that was not built (ignored, or a loader no physics component uses).
    [[nodiscard]] std::string role(const io::SceneComponent& component) const;
    /// The component of the file a built object (mass, force field, state) was made from, or
    /// nullptr (e.g. the contact force fields the collision pipelines add).
    [[nodiscard]] const io::SceneComponent* component_of(const void* built) const;
    /// The simulation node built for a node of the file (nullptr for a node of another file).
    [[nodiscard]] const Node* node_of(const io::SceneNode& node) const;

    // ---- topological changes (docs/topological-changes.md; src/scene/topology/scene_topology.cpp)
    /// The topologies that can change: each `*SetTopologyContainer` with a `*SetTopologyModifier`
    /// in its node (or above), as "node path/container name" ("/TT/Tetra_topo"), depth first.
    [[nodiscard]] std::vector<std::string> dynamic_topologies() const;
    /// A number that changes whenever an element of a dynamic topology is removed or added (the
    /// viewer starts a new layout then).
    [[nodiscard]] std::uint64_t topology_revision() const;
    /// The container `topology` names: a path of dynamic_topologies(), a container's name, or its
    /// node's path (unique ones). Throws std::invalid_argument naming the topologies otherwise.
    [[nodiscard]] const TopologyContainer& topology_container(std::string_view topology) const;
    /// Removes elements of `type` (SOFA's modifier remove...(): the elements, then the faces,
    /// edges and points no element uses any more; the states, masses, force fields, constraints,
    /// topological mappings and collision models follow). Between steps. Throws
    /// std::invalid_argument, changing nothing, for an index out of range or repeated, a type the
    /// topology does not hold, or a component that cannot follow (named).
    void remove_elements(std::string_view topology, ElementType type, std::vector<ElementId> indices);
    /// Appends elements of `type`: `vertices` holds vertices_per_element(type) indices per element
    /// (for points: `vertices` is empty and `count` points are added, each at the origin unless
    /// `ancestors` give its value as their mean). The missing faces and edges are created.
    void add_elements(std::string_view topology, ElementType type, const std::vector<PointId>& vertices,
                      std::size_t count = 0, const std::vector<std::vector<ElementId>>& ancestors = {});

    // ---- live Data: SofaPython3's object model (live_data.hpp; src/scene/live_data.cpp,
    // live_writes.cpp) ----------------------------------------------------------------------------
    /// Every Data and link of the component or node at `owner`: SOFA's (its catalog) then those
    /// only penalty declares (the registry). @throws std::invalid_argument when `owner` names none.
    [[nodiscard]] std::vector<DataField> data_fields(const DataOwner& owner) const;
    /// The current value of Data `name` of `owner`, with SOFA's type (see live_data.hpp).
    /// @throws std::invalid_argument naming the owner and the Data when it has none such.
    [[nodiscard]] DataValue data(const DataOwner& owner, std::string_view name);
    /// Writes Data `name` of `owner` from SOFA's text form, with the effect SOFA gives the write
    /// after init (LiveWrite): a state at once, the others at the next step or at reinit().
    /// @throws io::SceneError for a value the attribute refuses (kind, check), naming the file,
    ///         line, component and attribute; std::invalid_argument for a refused write, saying why.
    void set_data(const DataOwner& owner, std::string_view name, std::string_view text);
    /// Writes state vector `name` (position, velocity, force, rest_position, externalForce) of `s`
    /// from numbers: 3 per Vec3d DOF, 7 per Rigid3d frame (quaternions as written, as SOFA's;
    /// normalized with the fix `rigid_orientation_as_written`), 6 per Rigid3d derivative.
    /// @throws std::invalid_argument naming `what` for another count (a state keeps its size after
    /// init).
    void write_state(BaseState& s, std::string_view name, const std::vector<double>& values,
                     const std::string& what) const;
    /// SOFA's reinit() of a component (a node: init() of every component below it): the writes of
    /// its Data that wait for it take effect (the scene is built again, states kept).
    void reinit(const DataOwner& owner);
    /// Adds a component (a node when `component` is null, named `node_name`) to the node at
    /// `node_path` after init, as SOFA's addObject/addChild then init(): built before the next
    /// step. Returns the path of what was added.
    std::string add_to_node(std::string_view node_path, std::unique_ptr<io::SceneComponent> component,
                            std::string_view node_name = {});
    /// Removes the component or node at `owner` (built again before the next step).
    void remove(const DataOwner& owner);
    /// Builds the scene again from its text when writes or additions wait for it (step() calls
    /// it first): the new scene takes every state's values and memory (views stay valid), the
    /// time and the event listener of this one. @throws io::SceneError (the old scene stands and
    /// the writes are undone) for a text the builder refuses, or a write that would change the
    /// number of DOFs of a state.
    void apply_pending_writes();
    /// SOFA's reset: the scene built again from its text (written Data stay written) with every
    /// state back to its values at init, time 0; the states keep their memory.
    void reset();
    /// SOFA's delay of a root gravity written after init (on by default): the root's masses take
    /// it at the next step, the other nodes' one step later (SOFA copies the root's context down
    /// at the end of a step). false: every node takes it at the next step.
    void set_gravity_write_delay(bool delay);
    /// Counts the rebuilds (pointers to built objects other than states are stale after one).
    [[nodiscard]] std::uint64_t generation() const;
    /// Called during step() with SOFA's events of the collision phase: "CollisionBeginEvent",
    /// "CollisionEndEvent" (around detection and response), "IntegrateBeginEvent" (then the
    /// solvers run). Set it before the first step (SofaPython3's controllers).
    void set_event_listener(std::function<void(std::string_view)> listener);
    /// The options the scene was built with.
    [[nodiscard]] const BuildOptions& build_options() const { return options_; }
    /// The SOFA path of a component of the file (node path + its name, SOFA's default name when
    /// unnamed).
    [[nodiscard]] static std::string component_path(const io::SceneComponent& c);
    /// The component or node of the file at `owner`, or null.
    [[nodiscard]] const io::SceneElement* find_element(const DataOwner& owner) const;
    /// The mesh a loader read (null when no physics component used it).
    [[nodiscard]] const io::MeshData* loader_mesh(const io::SceneComponent& loader) const;
    /// The outputs an engine computed (BoxROI's `indices`, ...), or null.
    [[nodiscard]] const std::vector<PointId>* engine_indices(const io::SceneComponent& engine,
                                                             const std::string& data) const;
    [[nodiscard]] const io::MeshData* engine_mesh(const io::SceneComponent& engine, const std::string& data) const;

private:
    friend class SceneBuilder;
    friend std::unique_ptr<Scene> build_scene(io::SceneFile file, const BuildOptions& options);
    /// The contact records of the pipelines' live pairs (see contacts()).
    void refresh_contacts();
    io::SceneFile file_;
    std::unique_ptr<Simulation> simulation_;
    std::vector<std::unique_ptr<MeshTopology>> topologies_;
    std::vector<output::StateRecord> states_;
    std::vector<SceneCollisionModel> models_;
    std::vector<ScenePipeline> pipelines_;
    std::vector<std::string> build_warnings_;
    std::vector<BaseMass*> masses_;
    std::vector<const Node*> mass_nodes_;  ///< the node of each mass (its gravity)
    std::map<const io::SceneComponent*, std::string> roles_;
    std::map<const io::SceneNode*, const Node*> nodes_;
    std::map<const void*, const io::SceneComponent*> built_from_;
    StepTimings timings_;
    StepSolverStats solver_stats_;
    std::vector<EulerImplicitSolver*> implicit_solvers_;
    std::vector<std::string> implicit_solver_paths_;  ///< node path of each implicit solver
    std::vector<output::ContactRecord> contacts_;
    /// refresh_contacts' scratch: the last records, each field's among them (a pair that stays
    /// keeps its name: no string made again)
    std::vector<output::ContactRecord> previous_contacts_;
    PointerIndex<PenaltyForceField> previous_contact_of_;
    std::unique_ptr<TunnellingGuard> guard_;
    // live Data (live_writes.cpp)
    struct LiveEdits;
    friend struct LiveEdits;
    std::unique_ptr<LiveEdits> live_;
    BuildOptions options_;
    std::function<void(std::string_view)> event_listener_;
    std::map<std::pair<const io::SceneComponent*, std::string>, std::vector<PointId>> engine_indices_;
    std::map<std::pair<const io::SceneComponent*, std::string>, io::MeshData> engine_meshes_;
    std::map<const io::SceneComponent*, io::MeshData> loader_meshes_;
    /// The Data of the component or node at `owner` (data_fields_of_type's, cached).
    [[nodiscard]] const std::vector<DataField>& fields_of(const DataOwner& owner) const;
    /// The value of a Data the built scene holds (states, engine and loader outputs, masses), or
    /// nullopt (the scene's text or the default then).
    [[nodiscard]] std::optional<DataValue> live_value(const io::SceneComponent& c, const DataField& f) const;
    // SOFA HEAD's quirks of writes after init (live_quirks.cpp; SofaQuirkFixes::fix_uniform_mass_lazy_write,
    // fix_mesh_spring_stiffness_write): true when the write is taken so, false for the usual path.
    bool write_uniform_mass_quirk(io::SceneElement& element, const DataOwner& owner, std::string_view name,
                                  std::string_view text, const std::string& what);
    bool write_spring_list_quirk(const io::SceneElement& element, const DataOwner& owner, std::string_view name,
                                 std::string_view text, const std::string& what);
    /// BoxROI's `box` / `orientedBox` written after init (SofaQuirkFixes::fix_box_roi_write):
    /// notes what the next builds select with (LiveEdits::box_roi_writes); the write goes on.
    void note_box_roi_write(const io::SceneElement& element, const DataOwner& owner, std::string_view name);
    /// build_scene, with what the writes of `carried` (a scene being built again) keep for the
    /// builder (BoxROI's written boxes).
    static std::unique_ptr<Scene> build_from(io::SceneFile file, const BuildOptions& options, const LiveEdits* carried);
    /// What the quirks keep goes on in a rebuilt scene: a lagging weight, written spring lists.
    void carry_live_quirks(Scene& fresh) const;
    /// A Data's value as a quirk holds it (a written spring list, a lagging vertexMass), or nullopt.
    [[nodiscard]] std::optional<DataValue> quirk_value(const io::SceneComponent& c, const DataField& f) const;
    /// ConstantForceField's `forces`, `totalForce` and (none given) `indices` as SOFA's init and
    /// update callbacks leave them, or nullopt (live_quirks.cpp).
    [[nodiscard]] std::optional<DataValue> constant_force_data(const io::SceneComponent& c, const DataField& f) const;
    /// The mass built from the component at SOFA path `component`, or null.
    [[nodiscard]] BaseMass* built_mass_of(const std::string& component) const;
    /// The points and elements of a topology component as built (its node's topology), or nullopt.
    [[nodiscard]] std::optional<DataValue> topology_value(const io::SceneComponent& c, const DataField& f) const;
    /// A state vector as numbers (3 or 7 per DOF for positions, 3 or 6 for derivatives).
    [[nodiscard]] static std::vector<double> state_vector_numbers(const BaseState& s, StateVector which);
    /// Gives the states of `fresh` (built again from this scene's text) this scene's values and
    /// memory, matched by path. @throws io::SceneError when a state's size or template differs.
    void carry_states(Scene& fresh, bool reset) const;
    /// The vectors of `fresh`'s states whose Data is linked to a Data the pending writes made
    /// dirty (an engine's output whose input was written: SOFA's Data links, live_links.cpp).
    [[nodiscard]] std::vector<std::pair<const BaseState*, StateVector>> states_linked_to_writes(
        const Scene& fresh) const;
    /// `carried`'s vector `which` takes the values of `rebuilt` (same size: the memory stays).
    static void take_linked_vectors(const BaseState& rebuilt, BaseState& carried, StateVector which);
    /// Builds the scene again from its text; `reset`: states back to their values at init.
    void rebuild(bool reset);
    /// The root's child nodes keep their gravity until the end of the next step, and then take the
    /// root's (set_gravity_write_delay).
    void hold_gravity_of_children();
    void release_held_gravity();
    /// The simulation's one contact stage: the scene's pipelines, in SOFA's pipeline order,
    /// between SOFA's collision events (CollisionBegin before the detections; CollisionEnd and
    /// IntegrateBegin after the responses), with their timings added to the step's.
    class ContactPhase final : public ContactStage {
    public:
        explicit ContactPhase(Scene& scene) : scene_(scene) {}
        void detect() override;
        void respond() override;

    private:
        Scene& scene_;
    };
    std::unique_ptr<ContactPhase> contact_phase_;
    /// Registers contact_phase_ as the only contact stage of the simulation (when the scene has
    /// pipelines or an event listener).
    void install_contact_stage();
    /// Writes `text` into attribute `name` of `element` (adds it when absent); returns the old
    /// text (nullopt: absent).
    static std::optional<std::string> write_attribute(io::SceneElement& element, std::string_view name,
                                                      std::string_view text);
    /// The topologies that change and what follows them (last: destroyed first).
    std::unique_ptr<TopologyRuntime> topology_runtime_;
};

/// Builds a scene. Every error is an io::SceneError naming the file, the line, the component
/// and, when one attribute is at fault, the attribute (errors thrown by the library's
/// constructors, std::invalid_argument, are wrapped the same way).
/// The scene keeps `file` (its components are referenced by the built objects).
[[nodiscard]] std::unique_ptr<Scene> build_scene(io::SceneFile file, const BuildOptions& options = {});

/// Applies overrides `PATH.attribute=value` to a parsed scene (io::apply_overrides): an attribute
/// the file lacks may be added when the builder reads it for that component type; any other
/// unknown attribute, and a path that names nothing, is a SceneError naming it.
/// @throws io::OverrideSyntaxError for a malformed override text.
void apply_overrides(io::SceneFile& file, const std::vector<std::string>& overrides);

/// Parses and builds a scene file.
[[nodiscard]] std::unique_ptr<Scene> load_scene(const std::filesystem::path& file, const BuildOptions& options = {});

/// The built-in scene of `penalty run` without a scene file (SOFA XML; see
/// src/scene/default_scene.cpp for what it shows).
[[nodiscard]] std::string_view default_scene_xml();

/// `penalty info`: the component tree of a built scene, one line per node (effective dt and
/// gravity) and per component (what it became: Scene::role, or why it is ignored), then, per
/// collision pipeline, the model pairs its broad phase keeps with the pair's support by the
/// intersection method, its response and where the contact goes (implicit in a solver's
/// subtree, explicit, or nowhere), the model pairs SOFA's rules exclude, and the build notes.
/// A pipeline's first `pair_lines` kept pairs get a line each; the others are counted by their
/// types and outcome (a pile of n bodies keeps n²/2 pairs).
inline constexpr std::size_t kDescribedPairLines = 200;
[[nodiscard]] std::string describe_scene(const Scene& scene, std::size_t pair_lines = kDescribedPairLines);

}  // namespace penalty::scene
