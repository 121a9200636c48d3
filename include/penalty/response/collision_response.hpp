#pragma once
/// @file
/// CollisionResponse: SOFA's contact manager and Contact factory (spec §6, §7.2). It chooses the
/// response of each model pair by name, creates one BarycentricPenaltyContact per pair that has
/// detection outputs, feeds it each step, and destroys a pair as soon as it has no output for
/// one step (recreated from scratch — empty id map, ages 0 — when outputs come back, as SOFA).
///
/// Names: the response name is `key` or `key?name=value&name=value`. The only key is
/// "PenalityContactForceField" (SOFA's spelling); "nullptr" disables a pair. Name resolution
/// per pair (SOFA's getContactResponse): base = response (+ "?" + response_params when not
/// empty); r1, r2 = the models' contact_response: both empty → base; one non-empty → it; both
/// non-empty and equal → it; both non-empty and different → base.
///
/// responseParams (beyond SOFA; SOFA's penalty contact has no Data, so SOFA only logs "not
/// found" for any key): damping (N·s/m), friction = ignored | coulomb, tangentialStiffnessRatio,
/// tangentialDamping (N·s/m), timeStep (s), stiffnessLaw = sofa | physical, rigidSphereRadius =
/// head | v26.06. Unknown keys are reported in warnings() (as SOFA logs them) and ignored;
/// malformed values of known keys throw std::invalid_argument naming the key.
///
/// Registered pairs (model 1, model 2), in that order, never swapped (§6): Sphere–Sphere,
/// Sphere–RigidSphere, RigidSphere–RigidSphere, Sphere–Point, RigidSphere–Point, Point–Point,
/// Line–Point, Line–Line, Line–Sphere, Line–RigidSphere, Triangle–Sphere, Triangle–RigidSphere,
/// Triangle–Point, Triangle–Line, Triangle–Triangle, Cylinder–Cylinder, Cylinder–Triangle,
/// Cylinder–Sphere, Cylinder–RigidSphere, Tetrahedron–{Sphere, Point, Line, Triangle, Tetrahedron}.
/// A pair outside this list gets no contact and a warning (SOFA: "creation failed").

#include "penalty/collision/intersection.hpp"
#include "penalty/core/fidelity.hpp"
#include "penalty/response/barycentric_penalty_contact.hpp"
#include "penalty/response/stable_pair_map.hpp"

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penalty {

/// SOFA's factory key of the penalty response.
inline constexpr std::string_view kPenaltyResponseName = "PenalityContactForceField";

/// True if (t1, t2), in this order, is registered for the penalty response.
[[nodiscard]] bool is_penalty_response_pair(ModelType t1, ModelType t2);

/// Applies `name=value&name=value` to `parameters`; unknown keys are appended to `unknown`.
/// Throws std::invalid_argument naming the key for a malformed item or value.
void apply_response_params(std::string_view params, ContactResponseParameters& parameters,
                           std::vector<std::string>* unknown = nullptr);

/// Checks a response name as a collision model's `contactResponse` writes it ("key" or
/// "key?params"): the key must be PenalityContactForceField, "nullptr" or empty, and the
/// parameters valid. Throws std::invalid_argument naming what is wrong (a model's name used to be
/// checked only when its first contact was created, at the step).
void check_response_name(std::string_view name);

/// One live model pair.
struct ContactPairEntry {
    const CollisionModel* model1 = nullptr;
    const CollisionModel* model2 = nullptr;
    std::string response;                                ///< resolved name (key?params)
    std::unique_ptr<BarycentricPenaltyContact> contact;  ///< null for a "nullptr" response
};

/// Critical time step of one live pair (see contact_critical_time_step).
struct PairTimeScale {
    ModelType type1, type2;
    std::string name1, name2;
    double max_stiffness;       ///< largest ks of the pair's springs (N/m)
    double critical_time_step;  ///< sqrt(m/ks) (s) with the reduced mass of the given masses
};

class CollisionResponse {
public:
    /// `response`: "PenalityContactForceField" (default), "nullptr" or "" (SOFA ≥ v25.12 without
    /// a response: no contact is ever created, a warning is recorded). Any other key throws
    /// std::invalid_argument naming the parameter `response`. `base` supplies the C++-side
    /// parameters that response_params then override.
    explicit CollisionResponse(std::string response = std::string(kPenaltyResponseName),
                               std::string response_params = "", const ContactResponseParameters& base = {});

    /// The pipeline-wide name: response, plus "?" + response_params when not empty.
    [[nodiscard]] std::string base_response_name() const;
    /// The name resolved for a pair (see the file comment).
    [[nodiscard]] std::string response_name(const CollisionModel& m1, const CollisionModel& m2) const;

    /// Factory: a new contact for `name` and (m1, m2) in this order; nullptr for "nullptr", an
    /// empty name, or an unregistered pair (then a warning is recorded). Throws
    /// std::invalid_argument for an unknown key or malformed parameters.
    [[nodiscard]] std::unique_ptr<BarycentricPenaltyContact> create_contact(const std::string& name,
                                                                            const CollisionModel& m1,
                                                                            const CollisionModel& m2,
                                                                            double intersection_contact_distance);

    /// Contacts fed in parallel (set_detections) only when the step's contacts (two or more) have
    /// twice this many outputs together.
    static constexpr std::size_t kMinOutputsPerConcurrentFeed = 128;

    /// One step of SOFA's narrow-phase outputs and contact manager: every detection with outputs
    /// gets its pair's contact (created when new) and set_detection_outputs (in parallel in the
    /// calling TBB arena when it has more than one thread and two contacts or more have
    /// 2·kMinOutputsPerConcurrentFeed outputs together; the same results); pairs without
    /// outputs this step are destroyed (on_destroy runs first). The pairs' order is that of
    /// creation (on_create) and of pairs() (the force fields' order in the graph):
    /// - sofa_stable_id_order (SOFA HEAD's, on by default): SOFA's two maps (StablePairMap)
    ///   fed as SOFA feeds them: `detections` are the broad phase's pairs in its order
    ///   (CollisionPipeline::detect), each keyed in SOFA's outputs map when narrow_phase is set,
    ///   with or without outputs; new pairs are created in the outputs map's order, and pairs()
    ///   follows the contact map's order;
    /// - otherwise: both by (model_rank(model1), model_rank(model2)).
    void set_detections(std::span<const ModelPairDetection> detections, double intersection_contact_distance);
    /// Destroys every pair (SOFA's CollisionResponse::cleanup: the contact map is emptied, its
    /// stable ids stay).
    void clear();

    /// The live pairs in the order above (sofa_stable_id_order: those with a contact, then the
    /// pairs detected but refused a contact, "nullptr" response or pair not registered, which
    /// SOFA drops from its map and tries again at each step).
    [[nodiscard]] const std::vector<ContactPairEntry>& pairs() const { return pairs_; }
    /// The live contact of (m1, m2), or nullptr.
    [[nodiscard]] BarycentricPenaltyContact* find(const CollisionModel& m1, const CollisionModel& m2) const;
    [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }
    /// Whether the last set_detections fed its contacts in parallel.
    [[nodiscard]] bool last_feed_concurrent() const { return last_feed_concurrent_; }
    /// The contacts the last set_detections fed, each with the detection it was fed.
    [[nodiscard]] std::span<const std::pair<BarycentricPenaltyContact*, const ModelPairDetection*>> fed() const {
        return feed_;
    }
    [[nodiscard]] const ContactResponseParameters& base_parameters() const { return base_; }

    /// Critical time step sqrt(m/ks) of each live pair; `mass_of` gives the mass (kg) a contact
    /// point of a model carries (+inf for a static model).
    [[nodiscard]] std::vector<PairTimeScale> time_scales(
        const std::function<double(const CollisionModel&)>& mass_of) const;

    /// SOFA HEAD's contact order (docs/sofa-compatibility.md, "SOFA HEAD's orders"): SOFA keeps
    /// its narrow-phase outputs and its contacts in two helper::map_ptr_stable_compare maps
    /// (NarrowPhaseDetection::DetectionOutputMap, CollisionResponse::contactMap), ordered by
    /// stable ids given to the models in the order comparisons first meet them; contacts are
    /// created in the first map's order (CollisionResponse::createNewContacts) and re-added to
    /// the graph at each step in the second's (SubCollisionPipeline::computeCollisionResponse).
    /// On by default (kFidelityDefaults). Off: pairs are ordered by (model_rank(model1), model_rank(model2)),
    /// model_rank standing for the models' addresses in scene order (unset: creation order).
    bool sofa_stable_id_order = kFidelityDefaults.sofa_head_orders;
    std::function<std::size_t(const CollisionModel&)> model_rank;

    /// Hooks for the scene-graph glue: called after a pair's contact is created and before it
    /// is destroyed; on_destroy_done after each batch of on_destroy calls (of a set_detections
    /// or a clear()), while the contacts they named are still alive, so that the glue can take
    /// what refers to them out of the graph in one pass.
    std::function<void(BarycentricPenaltyContact&)> on_create;
    std::function<void(BarycentricPenaltyContact&)> on_destroy;
    std::function<void()> on_destroy_done;

private:
    std::string response_;
    std::string response_params_;
    ContactResponseParameters base_;
    std::vector<ContactPairEntry> pairs_;
    std::vector<std::string> warnings_;
    /// SOFA's NarrowPhaseDetection::m_outputsMap (pair → this step's detection) and
    /// CollisionResponse::contactMap (pair → live contact): both helper::map_ptr_stable_compare.
    StablePairMap<CollisionModel, const ModelPairDetection*> outputs_map_;
    StablePairMap<CollisionModel, BarycentricPenaltyContact*> contact_map_;
    using ModelPair = StablePairMap<CollisionModel, const ModelPairDetection*>::Key;
    std::vector<std::pair<ModelPair, const ModelPairDetection*>> refill_;  ///< this step's outputs-map inserts
    void set_detections_by_rank(std::span<const ModelPairDetection> detections, double intersection_cd);
    /// set_detection_outputs of every fed contact (feed_), in parallel when worth it.
    void feed_contacts();
    // set_detections' scratch, reused from step to step
    std::vector<ContactPairEntry> ordered_;  // pairs_ in their new order
    /// stable ids: (contact, its place in pairs_), sorted by address (kept: no allocation a step)
    std::vector<std::pair<const BarycentricPenaltyContact*, std::size_t>> place_of_;
    std::vector<char> seen_;                 // by rank: per pair, fed this step
    std::vector<ContactPairEntry> created_;  // by rank: pairs new this step
    std::vector<std::pair<BarycentricPenaltyContact*, const ModelPairDetection*>> feed_;
    bool last_feed_concurrent_ = false;
};

}  // namespace penalty
