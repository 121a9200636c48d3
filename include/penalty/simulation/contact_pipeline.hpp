#pragma once
/// @file
/// ContactPipeline: puts penalty contacts into a Simulation (spec §2, §2.1). It is SOFA's
/// CollisionPipeline + CollisionResponse + the scene-graph part of BarycentricPenalityContact:
///
/// At the start of every step (Simulation::collision_hook, i.e. with the positions of the end
/// of the previous step, as SOFA's DefaultAnimationLoop) it
///   1. detects every model pair (i ≤ j in registration order; SOFA's broad-phase filter
///      keep_model_pair; pairs the method does not support are skipped) with the exhaustive
///      detect_model_pair, which puts each pair in the intersector's registered order;
///   2. hands the outputs to its CollisionResponse (create / feed / destroy pairs);
///   3. keeps the scene graph in step with the live pairs:
///      - contact points of side s: an Identity mapper (Point, Sphere<Vec3>) uses the model's own
///        state; a Barycentric (Line, Triangle, Tetrahedron on Vec3) or Rigid (RigidSphere,
///        Cylinder on Rigid3) mapper gets a child node of the model's node holding a Vec3 state
///        mapped by a ContactPointMapping (J of the mapper: weights, or v_c + ω × (R·L) with
///        force and torque (R·L) × f on the way back). Models on mapped states (e.g. spheres
///        carried by a RigidMapping) chain through the existing mappings;
///      - the pair's PenaltyForceField, wrapped in a ContactInteraction, is stored in the node
///        chosen by §2.1: model1 not simulated → model2's node; else model2 not simulated →
///        model1's node; else the pipeline's node (default: the root). So a contact between a
///        static and a simulated object is integrated implicitly by the simulated object's
///        solver, and a contact between two objects with one solver each is explicit (forces
///        from the start-of-step x, v added as external forces) unless the pipeline node owns a
///        solver;
///      - a pair destroyed by the response (no output for one step) has its force field and its
///        contact-point nodes removed from the graph; it is rebuilt from scratch if it returns.
///
/// Lifetime: the Simulation, the nodes and the models must outlive the pipeline; the pipeline's
/// destructor removes what it added to the graph and resets Simulation::collision_hook.

#include "penalty/collision/intersection.hpp"
#include "penalty/response/collision_response.hpp"
#include "penalty/simulation/solver.hpp"

#include <array>
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
    /// computes their positions and velocities. Called after each set_detection_outputs.
    void init() override;
    void apply(std::span<Vec3> out, std::span<const InCoord> in) override;
    void apply_j(std::span<Vec3> out, std::span<const InDeriv> in) const override;
    void apply_jt(std::span<InDeriv> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override {
        mapper_->add_jacobian_triplets(t, row_offset, col_offset);
    }
    [[nodiscard]] std::size_t output_size() const override { return mapper_->size(); }
    [[nodiscard]] const ContactMapper& mapper() const { return *mapper_; }

private:
    ContactMapper* mapper_;
};

extern template class ContactPointMapping<Vec3Types>;
extern template class ContactPointMapping<Rigid3Types>;

/// Interaction force field of the scene graph over a PenaltyForceField it does not own (the
/// one of a BarycentricPenaltyContact, rebuilt by set_detection_outputs each step).
class ContactInteraction final : public Vec3InteractionForceField {
public:
    ContactInteraction(Vec3Object& state1, Vec3Object& state2, PenaltyForceField& field)
        : Vec3InteractionForceField(state1, state2), field_(&field) {}

    [[nodiscard]] PenaltyForceField& field() const { return *field_; }
    void add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                   ConstVec3Span v2) override {
        field_->add_force(f1, f2, x1, x2, v1, v2);
    }
    void add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                    double b_factor) const override {
        field_->add_dforce(df1, df2, dx1, dx2, k_factor, b_factor);
    }
    void add_stiffness_triplets(TripletList& triplets, Index offset1, Index offset2, double factor) const override {
        field_->add_stiffness_triplets(triplets, offset1, offset2, factor);
    }
    [[nodiscard]] double potential_energy() const override { return field_->potential_energy(); }
    [[nodiscard]] std::vector<BaseState*> states() const override {
        if (s1_ == s2_) return {s1_};
        return {s1_, s2_};
    }

private:
    PenaltyForceField* field_;
};

/// What the pipeline put into the graph for one live pair.
struct ContactGraphEntry {
    BarycentricPenaltyContact* contact = nullptr;
    Node* host = nullptr;                        ///< node storing the force field (§2.1)
    ContactInteraction* force_field = nullptr;   ///< owned by `host`
    std::array<Node*, 2> point_nodes{};          ///< contact-point nodes (null: identity mapper)
    std::array<Vec3Object*, 2> point_states{};   ///< the states the force field acts on
    std::array<BaseMapping*, 2> mappings{};      ///< null for an identity side
};

class ContactPipeline {
public:
    /// Attaches to `simulation` (sets its collision_hook; throws std::invalid_argument if a hook
    /// is already set). `node`: where a contact between two simulated models goes (default: the
    /// root). `response` supplies the response name and parameters; its on_create / on_destroy
    /// hooks are taken over by the pipeline.
    explicit ContactPipeline(Simulation& simulation,
                             const IntersectionParams& intersection = IntersectionParams::new_proximity(),
                             CollisionResponse response = CollisionResponse(), Node* node = nullptr);
    ~ContactPipeline();
    ContactPipeline(const ContactPipeline&) = delete;
    ContactPipeline& operator=(const ContactPipeline&) = delete;

    /// Registers a collision model held by `node`, whose state must be the model's state
    /// (Vec3 for Point/Line/Triangle/Sphere/Tetrahedron, Rigid3 for RigidSphere/Cylinder).
    /// A model whose params().node is −1 gets an id of its node (SOFA's "same context" rule for
    /// self-collision). Throws std::invalid_argument naming the model and the node otherwise,
    /// or for a model registered twice.
    void add_model(CollisionModel& model, Node& node);

    /// One collision step (detection, response, graph update); run by the collision hook.
    void update();

    [[nodiscard]] const IntersectionParams& intersection() const { return intersection_; }
    [[nodiscard]] CollisionResponse& response() { return response_; }
    [[nodiscard]] const CollisionResponse& response() const { return response_; }
    /// Detections of the last update (one per detected model pair, registered order).
    [[nodiscard]] const std::vector<ModelPairDetection>& detections() const { return detections_; }
    /// Model pairs that may collide but that the intersection method does not detect (SOFA
    /// registers them as ignored, has no intersector, or they are beyond-SOFA pairs not enabled),
    /// one line per pair, recorded the first time the pair is met: never silently skipped.
    [[nodiscard]] const std::vector<std::string>& skipped_pairs() const { return skipped_pairs_; }
    /// Graph entries of the live pairs (creation order).
    [[nodiscard]] const std::vector<ContactGraphEntry>& graph_entries() const { return entries_; }
    /// The entry of a live pair (m1, m2 in registered order), or nullptr.
    [[nodiscard]] const ContactGraphEntry* find(const CollisionModel& m1, const CollisionModel& m2) const;

private:
    struct ModelEntry {
        CollisionModel* model;
        Node* node;
        Vec3Object* vec3;    ///< the node's state when Vec3
        Rigid3Object* rigid; ///< the node's state when Rigid3
    };
    const ModelEntry& model_entry(const CollisionModel& m) const;
    void on_create(BarycentricPenaltyContact& contact);
    void on_destroy(BarycentricPenaltyContact& contact);
    void remove_entry(ContactGraphEntry& e);

    Simulation* simulation_;
    IntersectionParams intersection_;
    CollisionResponse response_;
    Node* node_;
    std::vector<ModelEntry> models_;
    std::vector<const Node*> node_ids_;
    std::vector<ModelPairDetection> detections_;
    std::vector<std::string> skipped_pairs_;
    std::vector<std::pair<const CollisionModel*, const CollisionModel*>> skipped_keys_;
    std::vector<ContactGraphEntry> entries_;
    std::size_t created_count_ = 0;
};

}  // namespace penalty
