#pragma once
/// @file
/// ContactPipeline: puts penalty contacts into a Simulation (spec §2, §2.1). It is SOFA's
/// CollisionPipeline + CollisionResponse + the scene-graph part of BarycentricPenalityContact:
///
/// update() = detect() then respond() — once per step; by default run by Simulation::step as one
/// of its contact stages (Simulation::add_contact_stage), i.e. with the positions of the end of
/// the previous step, as SOFA's DefaultAnimationLoop (options.register_stage = false: the caller
/// runs update() itself) — does:
///   1. detection by its CollisionPipeline (collision_pipeline.hpp, the one detection driver):
///      every model pair of broad_phase() (i ≤ j in registration order; SOFA's filter
///      keep_model_pair; pairs the method does not support are skipped and listed in
///      skipped_pairs()), each pair in the intersector's registered order, either
///      - ContactDetection::exhaustive: exhaustive_narrow_phase, all element pairs, or
///      - ContactDetection::bvh (default, kFidelityDefaults): one Bvh per model (refitted each update for moving
///      models,
///        built once for static ones), root-box pruning with SOFA's §3.8 margin, then
///        bvh_narrow_phase (parallel, TBB, `threads`: the pairs in parallel, and within a
///        pair). The outputs are bit-identical to the exhaustive path, pairs in the same order
///        (tested), so everything downstream is too;
///   2. hands the outputs to its CollisionResponse (create / feed / destroy pairs; the
///      contacts fed in parallel, in the same arena);
///   3. keeps the scene graph in step with the live pairs:
///      - contact points of side s: an Identity mapper (Point, Sphere<Vec3>) uses the model's own
///        state; a Barycentric (Line, Triangle, Tetrahedron on Vec3) or Rigid (RigidSphere,
///        Cylinder on Rigid3) mapper gets a child node of the model's node holding a Vec3 state
///        mapped by a ContactPointMapping (J of the mapper: weights, or v_c + ω × (R·L) with
///        force and torque (R·L) × f on the way back). Models on mapped states (e.g. spheres
///        carried by a RigidMapping) chain through the existing mappings;
///      - the pair's PenaltyForceField, wrapped in a PenaltyInteraction, is stored in the node
///        chosen by §2.1: model1 not simulated → model2's node; else model2 not simulated →
///        model1's node; else the pipeline's node (default: the root). So a contact between a
///        static and a simulated object is integrated implicitly by the simulated object's
///        solver, and a contact between two objects with one solver each is explicit (forces
///        from the start-of-step x, v added as external forces) unless the pipeline node owns a
///        solver;
///      - a pair destroyed by the response (no output for one step) has its force field and its
///        contact-point nodes removed from the graph; it is rebuilt from scratch if it returns.
///   last_timings(): detection and response (+ graph update) wall times of the last update().
///
/// Newton with contact-geometry updates (beyond SOFA, opt-in): attach_newton(solver) sets
/// solver.newton.update_geometry so that every Newton iterate of that solver re-detects the
/// live pairs whose force field lies in the solver's subtree, at the iterate's positions
/// (update_geometry(subtree)). The graph is not changed mid-solve (the solver's SubtreeSystem
/// holds pointers): the same PenaltyInteraction, PenaltyForceField, contact-point nodes and
/// mappings are kept; the contact list, the mappers and the contact-point states (resized by
/// ContactPointMapping::init) are rebuilt in place. A live pair without outputs at an iterate
/// keeps its (now empty) force field until the next update() destroys it; a pair that would
/// appear mid-solve is not created: the next update() (next step) picks it up.
/// Contact tracking across iterates: each iterate rebuilds the step's contacts *from the
/// state before this step's update()* (the pair's id map and contact list of the previous step
/// are restored first), so old_index always refers to the previous step's list: a contact's
/// age is (previous age + 1) or 0 whatever the number of iterates, friction history (ξ) is
/// inherited from the previous step once, and the dissipated-energy counters count the step
/// once (the last iterate's). The converged iterate's contacts are the step's contacts, and the
/// next update() tracks against them. With Coulomb friction the per-step anchor (u₀, ξ₀ =
/// rotate(ξ_prev) + h·P·(v2 − v1)) is taken at the iterate, i.e. with the end-of-step velocity:
/// ξ_{n+1} = rotate(ξ_n) + h·P·v_{n+1}, the backward-Euler update of the tangential spring.
///
/// Lifetime: the Simulation, the nodes and the models must outlive the pipeline; the pipeline's
/// destructor removes what it added to the graph, unregisters its contact stage, and clears the update_geometry of the
/// solvers it was attached to.

#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/collision/intersection.hpp"
#include "penalty/core/fidelity.hpp"
#include "penalty/core/pointer_index.hpp"
#include "penalty/response/collision_response.hpp"
#include "penalty/simulation/penalty_interaction.hpp"
#include "penalty/simulation/solver.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace penalty {

/// Maps a collision model's state (Vec3 or Rigid3) onto the Vec3 contact points of one side of
/// a pair, through that side's ContactMapper (weights / local points frozen at the last
/// set_detection_outputs): x = φ(x_parent) from mapper.update(), v = J·v_parent,
/// f_parent += Jᵀ·f (Rigid3: force Σf, torque Σ(R·L) × f, N·m, world frame).
template <class In>
class ContactPointMapping final : public Mapping<In, Vec3Types> {
public:
    using InCoord = typename In::Coord;
    using InDeriv = typename In::Deriv;

    /// `mapper` must map the model whose state is `from` (checked by the pipeline).
    ContactPointMapping(MechanicalObject<In>& from, Vec3Object& to, ContactMapper& mapper)
        : Mapping<In, Vec3Types>(from, to), mapper_(&mapper) {}

    /// Resizes the output state to the mapper's contact points (every vector, zero-filled) and
    /// copies their positions and velocities from the mapper, which must be current: called
    /// after each set_detection_outputs (which updates the mapper), never recomputed here.
    void init() override;
    void apply(std::span<Vec3> out, std::span<const InCoord> in) override;
    void apply_j(std::span<Vec3> out, std::span<const InDeriv> in) const override;
    void apply_jt(std::span<InDeriv> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override {
        mapper_->add_jacobian_triplets(t, row_offset, col_offset);
    }
    [[nodiscard]] std::size_t output_size() const override { return mapper_->size(); }
    /// Barycentric mapper: the vertices of its rows; other mappers: false (any input).
    [[nodiscard]] bool list_inputs_read(std::vector<std::uint32_t>& rows) const override;
    /// A barycentric mapper's rows when the input is Vec3 (apply_j and apply_jt are the mapper's
    /// combine and spread of each row); nullptr otherwise.
    [[nodiscard]] const std::vector<ContactBarycentricRow>* contact_barycentric_rows() const override;
    [[nodiscard]] const ContactMapper& mapper() const { return *mapper_; }

private:
    ContactMapper* mapper_;
};

extern template class ContactPointMapping<Vec3Types>;
extern template class ContactPointMapping<Rigid3Types>;

/// What the pipeline put into the graph for one live pair.
struct ContactGraphEntry {
    BarycentricPenaltyContact* contact = nullptr;
    Node* host = nullptr;                       ///< node storing the force field (§2.1)
    PenaltyInteraction* force_field = nullptr;  ///< owned by `host`
    std::array<Node*, 2> point_nodes{};         ///< contact-point nodes (null: identity mapper)
    std::array<Vec3Object*, 2> point_states{};  ///< the states the force field acts on
    std::array<BaseMapping*, 2> mappings{};     ///< null for an identity side
};

/// Node ids given by ContactPipeline::add_model (base + Node::id()), far from the ids users and
/// the scene builder choose.
inline constexpr int kAutoNodeIdBase = 1 << 24;

/// Most detection threads a ContactPipeline accepts (kMaxThreads, solver.hpp).
inline constexpr int kMaxDetectionThreads = kMaxThreads;

/// Options of ContactPipeline (defaults: kFidelityDefaults).
struct ContactPipelineOptions {
    ContactDetection detection =
        kFidelityDefaults.exhaustive_detection ? ContactDetection::exhaustive : ContactDetection::bvh;
    /// leaf_size, rebuild_ratio and narrow-phase chunking (bvh), depth and SOFA's output order.
    CollisionPipelineOptions bvh;
    /// Maximum TBB threads of the detection (bvh: its pairs and narrow phases) and of the
    /// response (contacts fed in parallel, CollisionResponse::set_detections); 0 = TBB's
    /// default; at most kMaxDetectionThreads. Output does not depend on it.
    int threads = 0;
    /// true: the constructor registers the pipeline as one of the simulation's contact stages
    /// (Simulation::step runs its detect() and respond(); several pipelines run in the order of
    /// their construction, SOFA's CompositeCollisionPipeline). false: the caller runs update()
    /// once per step.
    bool register_stage = true;
    /// SOFA HEAD's contact order (CollisionResponse::sofa_stable_id_order); off: scene rank.
    bool sofa_stable_id_order = kFidelityDefaults.sofa_head_orders;
    /// bvh: true: detections() lists every output of the intersection method. false: only those
    /// a contact may be made of (CollisionPipelineOptions::contact_outputs_only, set over
    /// `bvh`'s); the contacts, and so the trajectory, are the same.
    bool all_detection_outputs = false;
};

/// Wall-clock times (s, std::chrono::steady_clock) of the phases of the last update().
struct ContactPipelineTimings {
    double detection_seconds = 0.0;  ///< broad + narrow phase (exhaustive or BVH)
    double response_seconds = 0.0;   ///< CollisionResponse::set_detections + graph update
};

class ContactPipeline final : public ContactStage {
public:
    /// Attaches to `simulation` (registers as its contact stage unless options.register_stage is
    /// false). `node`: where a contact between
    /// two simulated models goes (default: the root). `response` supplies the response name and
    /// parameters; its on_create / on_destroy hooks are taken over by the pipeline. Throws
    /// std::invalid_argument for options.threads outside [0, kMaxDetectionThreads],
    /// options.bvh.leaf_size = 0 or options.bvh.rebuild_ratio < 1 (checked by CollisionPipeline).
    explicit ContactPipeline(Simulation& simulation,
                             const IntersectionParams& intersection = IntersectionParams::new_proximity(),
                             CollisionResponse response = CollisionResponse(), Node* node = nullptr,
                             const ContactPipelineOptions& options = {});
    ~ContactPipeline() override;
    ContactPipeline(const ContactPipeline&) = delete;
    ContactPipeline& operator=(const ContactPipeline&) = delete;

    /// Registers a collision model held by `node`, whose state must be the model's state
    /// (Vec3 for Point/Line/Triangle/Sphere/Tetrahedron, Rigid3 for RigidSphere/Cylinder).
    /// The model stays the caller's, but its node identity (params().node, SOFA's "same
    /// context" rule for self-collision) is part of what it means to register it here: a model
    /// whose params().node is −1 gets kAutoNodeIdBase + node.id() (Node::id is unique in its
    /// graph and never reused, so models shared by several pipelines of one simulation keep
    /// consistent ids); a model with an id ≥ 0 keeps it (the scene builder numbers its nodes).
    /// Throws std::invalid_argument naming the model and the node otherwise, or for a model
    /// registered twice.
    /// `scene_rank`: the model's rank in scene order, which orders the contacts as SOFA's
    /// contact map does (CollisionResponse::model_rank); default: the registration order.
    void add_model(CollisionModel& model, Node& node, std::size_t scene_rank = kRegistrationOrder);
    static constexpr std::size_t kRegistrationOrder = std::size_t(-1);

    /// One collision step: detect() then respond(); run by Simulation::step through the contact
    /// stage, or by the caller once per step when options().register_stage is false.
    void update();
    /// Detection (broad and narrow phase) at the current positions.
    void detect() override;
    /// Response to the last detect(): contacts created, fed and destroyed, graph updated.
    void respond() override;

    /// Newton iterate (beyond SOFA): re-detects the live pairs whose force field is stored in
    /// `subtree` (the node or a descendant) at the current positions and rebuilds their
    /// contacts in place, tracked against the previous step (see the file comment). Needs
    /// attach_newton() (which records the state before each update()); throws
    /// std::invalid_argument otherwise. Never adds or removes nodes or force fields.
    void update_geometry(const Node& subtree);
    /// Same for every live pair.
    void update_geometry();
    /// Sets solver.newton.update_geometry to update_geometry(node of `solver`) (the solver must
    /// be owned by a node of the simulation, else std::invalid_argument). Does not enable
    /// Newton: set solver.newton.enabled. From the next update() on, the pipeline keeps the
    /// pre-step contact state the iterates need (per step: a copy of each live pair's force
    /// field and of the registered models' positions and velocities).
    /// The hook is this pipeline's: its destructor clears it. A caller that drives several
    /// pipelines from one solver calls keep_step_start() on each and owns the solver's hook.
    void attach_newton(EulerImplicitSolver& solver);
    /// What attach_newton() does to the pipeline, without touching a solver: from the next
    /// update() on, keep the pre-step contact state update_geometry() needs.
    void keep_step_start();
    /// Whether keep_step_start() (or attach_newton) was called: Newton iterates may rebuild the
    /// contact lists within a solve.
    [[nodiscard]] bool keeps_step_start() const { return keep_step_start_; }
    /// update_geometry calls since the last update().
    [[nodiscard]] int geometry_updates_this_step() const { return geometry_updates_; }

    [[nodiscard]] const ContactPipelineOptions& options() const { return options_; }
    [[nodiscard]] const ContactPipelineTimings& last_timings() const { return timings_; }

    [[nodiscard]] const IntersectionParams& intersection() const { return intersection_; }
    [[nodiscard]] CollisionResponse& response() { return response_; }
    [[nodiscard]] const CollisionResponse& response() const { return response_; }
    /// Detections of the last update (one per model pair kept by the broad phase, in its order,
    /// registered order within a pair; outputs possibly empty; only those a contact may be made
    /// of unless options().all_detection_outputs).
    [[nodiscard]] const SceneDetection& detections() const { return collision_.detections(); }
    /// The detection driver (its models are the registered ones, in registration order).
    [[nodiscard]] const CollisionPipeline& collision() const { return collision_; }
    /// Model pairs that may collide but that the intersection method does not detect (SOFA
    /// registers them as ignored, has no intersector, or they are beyond-SOFA pairs not enabled),
    /// one line per pair, recorded the first time the pair is met: never silently skipped.
    [[nodiscard]] const std::vector<std::string>& skipped_pairs() const { return skipped_pairs_; }
    /// Graph entries of the live pairs (creation order).
    [[nodiscard]] const std::vector<ContactGraphEntry>& graph_entries() const { return entries_; }
    /// The entry of a live pair (m1, m2 in registered order), or nullptr.
    [[nodiscard]] const ContactGraphEntry* find(const CollisionModel& m1, const CollisionModel& m2) const;
    /// The node that stores the force field of a pair (m1, m2 registered, in SOFA's registered
    /// order), spec §2.1: m1 not simulated → m2's node; else m2 not simulated → m1's node; else
    /// the pipeline's node. Throws std::invalid_argument for a model not registered here.
    [[nodiscard]] Node* host_node(const CollisionModel& m1, const CollisionModel& m2) const;

private:
    struct ModelEntry {
        CollisionModel* model;
        Node* node;
        Vec3Object* vec3;        ///< the node's state when Vec3
        Rigid3Object* rigid;     ///< the node's state when Rigid3
        std::size_t scene_rank;  ///< add_model's scene_rank (the contact-map order)
        // Newton (attach_newton): the state's positions and velocities at the last update()
        std::vector<Vec3> start_x, start_v;
        std::vector<Rigid3Types::Coord> start_rx;
        std::vector<Rigid3Types::Deriv> start_rv;
    };
    /// Swaps the positions/velocities of a model's state with those recorded at update().
    static void swap_with_start(ModelEntry& e);
    /// First evaluation of a rebuilt pair at the start-of-step state (friction anchor, damping).
    void evaluate_at_step_start(std::size_t entry);
    const ModelEntry& model_entry(const CollisionModel& m) const;
    void on_create(BarycentricPenaltyContact& contact);
    void on_destroy(BarycentricPenaltyContact& contact);
    /// After a batch of on_destroy: the destroyed pairs' force fields and contact-point nodes
    /// out of the graph, their entries out of entries_ (and step_start_), each in one pass.
    void remove_destroyed_entries();
    /// Records the pairs of the last detection that the method does not detect (once each).
    void record_skipped_pairs();
    /// Runs `f` in the pipeline's thread arena (TBB's default one when options.threads = 0):
    /// the detection and the response.
    template <class F>
    void run_detection(const F& f);
    [[nodiscard]] std::size_t model_index(const CollisionModel& m) const;
    void update_geometry_if(const Node* subtree);
    void record_fed_outputs();
    /// entries_ (and step_start_) in the response's pair order, and each host's contact force
    /// fields at the end of its list in that order, as SOFA re-adds them at every step.
    void order_graph_entries();
    /// Every live contact's mapped contact states sized to its points (ContactPointMapping::init).
    void init_contact_states();

    /// Per live pair (same index as entries_): what update_geometry restores before rebuilding.
    struct StepStart {
        PenaltyForceField field_before;       ///< the pair's field before this step's update()
        DetectionOutputList outputs_before;   ///< the outputs that built field_before's contacts
        DetectionOutputList last_outputs;     ///< the outputs that built the current contacts
        DetectionOutputList iterate_outputs;  ///< scratch: the outputs at a Newton iterate
    };

    Simulation* simulation_;
    IntersectionParams intersection_;
    CollisionResponse response_;
    Node* node_;
    ContactPipelineOptions options_;
    ContactPipelineTimings timings_;
    CollisionPipeline collision_;  ///< the detection driver over models_' models
    struct ThreadArena;            ///< a tbb::task_arena, made once (threads > 0)
    std::unique_ptr<ThreadArena> arena_;
    std::vector<StepStart> step_start_;
    bool keep_step_start_ = false;  ///< attach_newton was called
    bool snapshot_valid_ = false;   ///< step_start_ recorded by an update() since then
    int geometry_updates_ = 0;
    std::vector<EulerImplicitSolver*> attached_solvers_;
    std::vector<ModelEntry> models_;
    std::vector<std::string> skipped_pairs_;
    std::vector<ModelPair> skipped_keys_;  ///< the pairs of skipped_pairs_
    std::vector<ContactGraphEntry> entries_;
    std::size_t created_count_ = 0;
    PointerIndex<CollisionModel> model_index_;  ///< model → its index in models_
    // on_destroy's lookups and the removals it leaves to remove_destroyed_entries
    PointerIndex<BarycentricPenaltyContact> entry_of_;  ///< contact → its entry, while entry_of_valid_
    bool entry_of_valid_ = false;
    std::size_t destroyed_entries_ = 0;                                    ///< entries_ with contact == nullptr
    std::vector<std::pair<Node*, const BaseForceField*>> removed_fields_;  ///< (host, field)
    std::vector<std::pair<Node*, const Node*>> removed_nodes_;             ///< (parent, point node)
    // order_graph_entries' scratch, reused from step to step
    std::vector<ContactGraphEntry> entries_scratch_;
    PointerIndex<BarycentricPenaltyContact> entry_of_scratch_;  ///< order_graph_entries: contact → its entry
    std::vector<StepStart> step_start_scratch_;
    std::vector<std::pair<Node*, std::size_t>> host_entries_scratch_;  ///< (host, entry index), sorted
    std::vector<BaseForceField*> fields_scratch_;
};

}  // namespace penalty
