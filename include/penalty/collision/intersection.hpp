#pragma once
/// @file
/// The four intersection methods of SOFA (DiscreteIntersection, NewProximityIntersection,
/// MinProximityIntersection, LocalMinDistance) with their parameters and defaults (spec §5.1),
/// the [type][type] dispatch table with explicit "unsupported"/"ignored" entries, the SOFA
/// quirk switches (§14) and an exhaustive all-element-pairs loop (reference narrow phase).

#include "penalty/collision/collision_model.hpp"
#include "penalty/collision/detection_output.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penalty {

enum class IntersectionMethod : std::uint8_t { Discrete, NewProximity, MinProximity, LocalMinDistance };
inline constexpr int kIntersectionMethodCount = 4;
/// SOFA's component type of the method: "DiscreteIntersection", "NewProximityIntersection",
/// "MinProximityIntersection", "LocalMinDistance".
[[nodiscard]] const char* intersection_method_name(IntersectionMethod m);
/// The method as `penalty info` and the scene summary name it: the component type without
/// "Intersection" ("Discrete", "NewProximity", "MinProximity", "LocalMinDistance").
[[nodiscard]] const char* intersection_method_short_name(IntersectionMethod m);

/// What to do when a proximity routine finds two coincident points (zero distance, so the
/// normal d/|d| is undefined). SOFA (§14 item 8) emits a NaN normal in NewProximity
/// (point/line/triangle routines) and LocalMinDistance; MinProximity and NewProximity
/// Triangle–Sphere substitute (1,0,0).
enum class ZeroDistanceNormal : std::uint8_t {
    FallbackX,  ///< default: normal (1,0,0), as SOFA's MinProximity does (never NaN)
    Drop,       ///< emit no output for that element pair
    SofaNaN,    ///< reproduce SOFA exactly: NaN normal where SOFA has no guard
};

/// Switches for SOFA behaviours we consider bugs (spec §14). Default = reproduce SOFA
/// (all false), except item 8 whose default never emits NaN (see ZeroDistanceNormal).
struct SofaQuirkFixes {
    /// §14.1 MinProximity Line–Sphere/RigidSphere builds the closest point mirrored about the
    /// segment midpoint. true: use the true projection.
    bool fix_minproximity_line_sphere_mirror = false;
    /// §14.2 NewProximity Triangle–Sphere checks FLAG_E12 for edge AC and FLAG_E31 for edge BC.
    /// true: check FLAG_E31 and FLAG_E23 (as Triangle–Point does).
    bool fix_newproximity_triangle_sphere_edge_flags = false;
    /// Found while characterizing (not in spec §14): NewProximity Triangle–Sphere's edge tests
    /// have no lower bound on the edge parameter (pAB, pAC may be negative when the vertex-A
    /// test, which uses 1e-7 for pAC, fails), so the contact point can lie on the extension of
    /// an edge outside the triangle and the reported distance can be below the true one.
    /// true: vertex A uses 1e-6 for both, edges require pAB ≥ 1e-6 / pAC ≥ 1e-6 (as NP-TP).
    bool fix_newproximity_triangle_sphere_edge_range = false;
    /// §14.3 NewProximity Triangle–Triangle tests vertex 1 of e1 without its ownership flag.
    /// true: require FLAG_P1 like the other vertices.
    bool fix_newproximity_triangle_triangle_vertex1_flag = false;
    /// §14.4 NewProximity Triangle–Triangle overwrites the stored normals (bothSide logic).
    /// true: leave the stored normals alone.
    bool fix_newproximity_triangle_triangle_normal_overwrite = false;
    /// Found by the trajectory comparison (not in spec §14; not a collision quirk, but a fix of
    /// the scene loader): MechanicalObject::parse reads the short forms `dx dy dz`, `rx ry rz`,
    /// `scale` and `sx sy sz` with BaseObjectDescription::getAttributeAsFloat (strtof), so
    /// `scale="0.7"` scales by 0.699999988079071. true: read them in double, as the long forms
    /// `translation`, `rotation`, `scale3d`. Read when a scene is built (BuildOptions).
    bool fix_mechanical_object_float_short_forms = false;
    /// Found by the trajectory comparison (a fix of the scene loader, as the one above): SOFA
    /// keeps a Rigid3 MechanicalObject's orientation quaternions as written (RigidCoord's parse;
    /// neither init nor a write after init normalizes them, and its integration premultiplies by
    /// a unit quaternion, so the norm stays): `0 0 0.7 0.7` maps a frame's points by a matrix
    /// that is not a rotation. true: normalized when read and when written after init.
    bool fix_rigid_orientation_as_written = false;
    /// Found by the trajectory comparison (a fix of the scene loader, as the one above):
    /// RegularGridTopology::parse reads `xmin` ... `zmax` (and `scale`) with getAttributeAsFloat.
    /// true: read them in double, as `min` and `max`.
    bool fix_regular_grid_float_bounds = false;
    /// A scene-loader quirk (as the two above): SOFA's Data<T>::read extracts a number with
    /// `istringstream >> value` and ignores what follows it, so `tolerance="10-3"` reads 10.
    /// true: such a number attribute is an error, as any other unreadable number.
    bool fix_number_trailing_text = false;
    /// A topology-change quirk: SOFA's Edge/Triangle/Quad/Tetrahedron/HexahedronSetTopologyModifier::
    /// remove* drop the indices past the container's end with a warning (and remove the rest), so
    /// TopologicalChangeProcessor files listing elements that no longer exist run on. true: such an
    /// index is an error naming the file and line, as any other bad change.
    bool fix_topology_removal_out_of_range = false;
    /// A topology-change quirk: SOFA's TopologicalChangeProcessor::processTopologicalChanges logs
    /// an error for an INCISE= segment whose path does not reach its end point across the surface
    /// ("Invalid path in computeIntersectedPointsList") and skips the rest of the line. true: such
    /// a segment is an error naming the file and line, and the line changes nothing.
    bool fix_incision_invalid_path = false;
    /// A live-write quirk (docs/python.md): SOFA's UniformMass takes a totalMass or vertexMass
    /// written after init in its update callback (UniformMass::updateFromTotalMass /
    /// updateFromVertexMass), which runs at the first isComponentStateValid() of the next step:
    /// after addForce (no such check: the weight uses vertexMass as it then is), before addMDx,
    /// addMToMatrix, accFromF; the callback recomputes from the Data init used (totalMass when it
    /// was set, so a vertexMass write lasts one weight; else vertexMass, so a totalMass write is
    /// dropped). true: the write reaches weight and mass matrix together, as a fresh scene.
    bool fix_uniform_mass_lazy_write = false;
    /// A live-write quirk: MeshSpringForceField's `stiffness` / `damping` Data after init are
    /// SpringForceField's per-spring lists (its own are scene aliases), whose update callback
    /// (SpringForceField::updateSpringsFromTopologyIndices) gives spring i the written list's
    /// value i (the last one past its end): every spring's ks (kd) becomes the written value, not
    /// value / rest length as MeshSpringForceField::init makes. true: as a fresh scene.
    bool fix_mesh_spring_stiffness_write = false;
    /// A live-write quirk: BoxROI orders each box's corners (min below max) and computes its
    /// oriented boxes once, in BoxROI::roiInit; a write after init re-runs the engine (the boxes
    /// are inputs) with the `box` as written (a corner above the other selects nothing on that
    /// axis) and the oriented boxes of init (computeOrientedBoxes is not run again). true: as a
    /// fresh scene with the written value.
    bool fix_box_roi_write = false;
    /// A topology-change quirk: SOFA's TopologySubsetData::remove (the pressure loads'
    /// edge/triangle/quadPressureMap) renames the entries of its m_lastElementIndex, the
    /// topology's last element at init plus the elements added since, never lowered by a
    /// removal: from the second removal on it misnames entries, and an entry left past the end
    /// crashes SOFA HEAD (penalty drops it with a warning). true: the entries of the topology's
    /// current last element, as TopologySubsetIndices::getLastElementIndex.
    bool fix_subset_data_last_index = false;
    /// A topology-change quirk: SOFA's TriangleFEMForceField keeps no topology data: init sizes its
    /// per-triangle vectors (rest frames, material) and its loops read the topology's current
    /// triangles, so after a change a slot keeps the data of the triangle first there, and a
    /// triangle added past init's count is read past the vectors. true: the data are made again
    /// for the changed triangles, as a fresh scene.
    bool fix_triangle_fem_slot_data = false;
    /// A scene-loader quirk: a MechanicalObject's `src="@loader"` links every Data of the loader
    /// whose name (or alias) it shares and does not set itself (BaseComponent::setSrc); a
    /// SphereLoader's `translation`, `rotation` and `scale` (alias `scale3d`) are auto-linked (a
    /// MeshLoader's are not), so the state moves its loaded points again by the loader's
    /// transform. true: the state keeps its own transform (none unless it sets one).
    bool fix_sphere_loader_src_transform = false;
    /// A scene-loader quirk (as mechanical_object_float_short_forms): MeshLoader::parse reads a
    /// mesh loader's `scale` with getAttributeAsFloat (strtof), so `scale="0.1"` scales by
    /// 0.10000000149011612. true: read it in double, as `scale3d`.
    bool fix_mesh_loader_float_scale = false;
    /// §14.8 zero-distance normal policy.
    ZeroDistanceNormal zero_distance_normal = ZeroDistanceNormal::FallbackX;
};

/// One switchable SOFA quirk: its name in scenes (`fixSofaQuirks="NAME ..."` on an intersection
/// component) and on the command line (`--fix-sofa-quirk NAME`), the member of SofaQuirkFixes it
/// sets, and one line on what the fix does.
struct SofaQuirkInfo {
    std::string_view name;
    bool SofaQuirkFixes::*member;
    std::string_view description;
};
/// Every boolean quirk fix, in a fixed order (the zero-distance normal policy is not a fix of a
/// SOFA bug but a choice among three behaviours: `zeroDistanceNormal`).
[[nodiscard]] std::span<const SofaQuirkInfo> sofa_quirk_table();
/// Turns on the fix named `name` ("all" turns every fix on). Returns false for an unknown name.
bool enable_sofa_quirk_fix(SofaQuirkFixes& fixes, std::string_view name);
/// Names of the fixes that are on, in table order.
[[nodiscard]] std::vector<std::string> enabled_sofa_quirk_fixes(const SofaQuirkFixes& fixes);
/// Every fix on in `a` or in `b` (the zero-distance policy of `a` unless `b`'s is not the default).
[[nodiscard]] SofaQuirkFixes merge_sofa_quirk_fixes(const SofaQuirkFixes& a, const SofaQuirkFixes& b);
/// "fallbackX", "drop", "sofaNaN".
[[nodiscard]] const char* zero_distance_normal_name(ZeroDistanceNormal policy);

/// Parameters of an intersection method. Build with one of the factories to get SOFA's
/// defaults for that method.
struct IntersectionParams {
    IntersectionMethod method = IntersectionMethod::NewProximity;
    double alarm_distance = 1.0;    ///< A (m), ≥ 0; Discrete: 0
    double contact_distance = 0.5;  ///< C (m), ≥ 0; Discrete: 0
    // NewProximity and MinProximity
    bool use_line_line = false;  ///< NewProximity default false, MinProximity default true
    // MinProximity switches (false = pair registered as ignored)
    bool use_sphere_triangle = true;  ///< Sphere/RigidSphere vs Point, Line, Triangle
    bool use_point_point = true;
    bool use_line_point = true;
    bool use_surface_normals = false;  ///< Triangle–Point normal = stored triangle normal
    // LocalMinDistance
    bool filter_intersection = true;
    double angle_cone = 0.0;
    double cone_factor = 0.5;
    bool use_lmd_filters = false;  ///< true: skip the built-in validity filters
    /// Beyond SOFA (opt-in, SOFA has no intersector): the four Cylinder pairs (NewProximity
    /// and MinProximity) and Tetrahedron–Point (all methods, proximity semantics).
    bool enable_beyond_sofa_pairs = false;
    SofaQuirkFixes quirks;

    [[nodiscard]] static IntersectionParams discrete();
    [[nodiscard]] static IntersectionParams new_proximity();
    [[nodiscard]] static IntersectionParams min_proximity();
    [[nodiscard]] static IntersectionParams local_min_distance();

    /// Throws std::invalid_argument for negative or non-finite distances/cone parameters.
    void validate() const;
};

/// How a method handles a pair of model types.
enum class PairSupport : std::uint8_t {
    Supported,    ///< SOFA has an intersector and so do we
    Ignored,      ///< SOFA registers the pair as ignored (e.g. MinProximity Triangle–Triangle,
                  ///< or a MinProximity use* switch is false): no output, by design
    Unsupported,  ///< SOFA has no intersector for the pair: no output (SOFA warns once)
    BeyondSofa,   ///< not in SOFA; implemented here, active when enable_beyond_sofa_pairs
};
[[nodiscard]] const char* pair_support_name(PairSupport s);

/// True if (a, b) is SOFA's registered order for that pair of types (the order of model 1,
/// model 2 in DetectionOutputs and in the response). Exactly one of (a,b), (b,a) is registered
/// unless a == b.
[[nodiscard]] bool is_registered_order(ModelType a, ModelType b);

/// Support of the (unordered) pair {a, b} by the method, taking the use* switches and
/// enable_beyond_sofa_pairs into account (BeyondSofa is returned whatever the switch; it is
/// active only when the switch is on).
[[nodiscard]] PairSupport pair_support(const IntersectionParams& params, ModelType a, ModelType b);

/// True when `params` has an active intersector for the pair of types: Supported with its use*
/// switch on, or BeyondSofa with enable_beyond_sofa_pairs.
[[nodiscard]] bool has_active_intersector(const IntersectionParams& params, ModelType a, ModelType b);

/// SOFA's cube-test margin for a model pair (§3.8): Discrete → alarm_distance, otherwise
/// alarm_distance + contact_distance(m1) + contact_distance(m2).
[[nodiscard]] double box_margin(const IntersectionParams& params, const CollisionModel& m1, const CollisionModel& m2);

/// Runs the element intersector for (e1 of m1, e2 of m2); (m1, m2) must be in registered order.
/// Appends 0 or more outputs to `out` and returns their number. Throws std::invalid_argument
/// for an unsupported/ignored pair or a wrong order (callers should check pair_support first).
/// May modify m1/m2 (SOFA's Triangle–Triangle normal overwrite, quirk §14.4).
int intersect_elements(const IntersectionParams& params, CollisionModel& m1, Index e1, CollisionModel& m2, Index e2,
                       DetectionOutputList& out);

/// Self-collision element filters of SOFA (spec §3.2, §3.4), applied by the narrow phase only
/// to two models of the same node (same_node(m1, m2)): a Point model with itself rejects
/// topological neighbours, a Line model with itself rejects edges sharing a vertex, and a mesh
/// element against a Point model over the same state rejects its own vertices. (m1, m2) in
/// registered order, as passed to intersect_elements.
[[nodiscard]] bool elements_may_collide(const CollisionModel& m1, Index e1, const CollisionModel& m2, Index e2);

/// The detection of one model pair: SOFA's map entry (model1, model2) → DetectionOutputVector.
/// The one result type of detection (detect_model_pair, CollisionPipeline, CollisionResponse).
struct ModelPairDetection {
    CollisionModel* model1 = nullptr;  ///< first in registered order
    CollisionModel* model2 = nullptr;
    PairSupport support = PairSupport::Unsupported;
    bool skipped = false;  ///< pair filtered out (inactive, both non-simulated, canCollideWith)
    /// SOFA's broad phase passes the pair to the narrow phase (BruteForceBroadPhase::
    /// addCollisionModel: neither model empty, root boxes within box_margin), which keys it in
    /// its outputs map even without outputs (CollisionResponse orders contacts by that map).
    /// CollisionPipeline::detect lists only such pairs; false (no outputs) from other sources.
    bool narrow_phase = true;
    DetectionOutputList outputs;
};

/// Exhaustive narrow phase of one model pair (m1, m2) in registered order with an active
/// intersector: validates both models, update()s them, then calls the element intersector on
/// every element pair (e1 ascending, then e2 ascending) whose element boxes pass SOFA's
/// proximity cube test (which never changes the result, §3.8) and which pass the self-collision
/// element filters. For a model paired with itself, each unordered element pair is visited
/// once (e1 > e2). Outputs are appended to `out`; `box_scratch` holds m2's element boxes (its
/// capacity is reused from call to call).
void exhaustive_narrow_phase(const IntersectionParams& params, CollisionModel& m1, CollisionModel& m2,
                             DetectionOutputList& out, std::vector<Aabb>& box_scratch);

/// One model pair, exhaustively (the reference of the BVH narrow phase): validates both
/// models, swaps them into registered order, applies the model-pair filter (keep_model_pair:
/// skipped) and, for a pair with an active intersector, runs exhaustive_narrow_phase.
[[nodiscard]] ModelPairDetection detect_model_pair(const IntersectionParams& params, CollisionModel& a,
                                                   CollisionModel& b);

}  // namespace penalty
