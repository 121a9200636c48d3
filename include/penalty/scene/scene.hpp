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
#include "penalty/io/scene_file.hpp"
#include "penalty/output/state_record.hpp"
#include "penalty/output/vtk_writer.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/tunnelling_guard.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::scene {

/// Options of build_scene (the command line's `penalty run` flags).
struct BuildOptions {
    std::vector<std::filesystem::path> data_dirs;  ///< `--data-dir`, searched after the scene's folder
    std::optional<double> dt;                      ///< overrides the root node's dt (s)
    int threads = 0;  ///< threads of the narrow phase and of independent solvers (0: TBB's default)
    /// Detection algorithm: BVH narrow phase (default) or SOFA's exhaustive pair loop; both give
    /// the same outputs in the same order.
    bool exhaustive_detection = false;
    /// SOFA HEAD's two summation and contact orders (on by default; `--no-sofa-head-orders`
    /// turns them off; docs/sofa-compatibility.md, "SOFA HEAD's orders"): the ODE solvers sum
    /// computeForce and addMBKv through SOFA's MappingGraph (OdeSolver::sofa_mapping_graph_order)
    /// and the contacts follow SOFA's stable-id maps (CollisionResponse::sofa_stable_id_order).
    /// Off: the visitors' summation order and contacts by the models' scene order.
    bool sofa_head_orders = true;
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
};

/// One collision model of the scene and where it comes from.
struct SceneCollisionModel {
    std::unique_ptr<CollisionModel> model;
    Node* node = nullptr;                            ///< node holding the model's state
    const io::SceneComponent* component = nullptr;   ///< its `<...CollisionModel>` element
};

/// One SOFA collision pipeline (CollisionPipeline, or a SubCollisionPipeline of a
/// CompositeCollisionPipeline) as built.
struct ScenePipeline {
    std::string name;                              ///< component name or type
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
    /// Σ m·|g|·length over the masses (J): the energy of dropping every body by `length`.
    [[nodiscard]] double gravity_energy_scale(double length) const;
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
    std::unique_ptr<TunnellingGuard> guard_;
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
/// collision pipeline, every model pair its broad phase keeps with the pair's support by the
/// intersection method, its response and where the contact goes (implicit in a solver's
/// subtree, explicit, or nowhere), the model pairs SOFA's rules exclude, and the build notes.
[[nodiscard]] std::string describe_scene(const Scene& scene);

}  // namespace penalty::scene
