#pragma once
/// @file
/// Continuous detection over one step's motion (beyond SOFA: the tunnelling guard,
/// docs/no-tunnelling.md): which features of the collision models passed through one another
/// between the positions recorded at the start of the step (record_start) and the current ones,
/// each vertex moving on a straight line.
///
/// Surfaces. The models are grouped by state: a surface is the union of the features of the
/// models on one state (vertices of Point, Line and Triangle models, edges of Line and Triangle
/// models, triangles, spheres of Sphere and RigidSphere models), so a body described by a
/// Triangle, a Line and a Point model is tested once. Cylinder and Tetrahedron models add no
/// feature (a limit: docs/no-tunnelling.md).
/// Pairs. Two surfaces are tested when the broad phase keeps (broad_phase(), SOFA's filters, a
/// supported pair) some pair of their models; each kept model pair (m1, m2) adds the tests its
/// features allow, where its intersection method makes contacts that resist them:
///   point–triangle   vertices of m1 (Point/Line/Triangle) through triangles of m2, and back;
///   edge–edge        edges of m1 through edges of m2 (Line/Triangle both), when the method
///                    makes edge–edge contacts: two Line models, or useLineLine (NewProximity's
///                    default, off, lets triangle edges pass through each other unresisted: not
///                    a tunnelling of its contacts);
///   sphere–triangle  a sphere's centre through a triangle (a sphere tunnels when its centre
///                    passes the surface: the penalty then pushes it on through);
///   sphere–sphere    a centre entering the other sphere (its penalty has then spent its reach:
///                    the centres may pass each other in the next steps).
/// A vertex entering a sphere is not a crossing (the sphere's penalty keeps pushing it out
/// along the centre line).
/// Within one surface (self-collision kept) features that share a vertex are not tested. A
/// feature that meets several elements of the other surface at once (a vertex through an edge
/// two triangles share) is one crossing, the earliest.
/// A vertex of a state is tested once per pair of surfaces (not once per model).
///
/// Detection: per surface and feature kind a Bvh (bvh.hpp) over the swept boxes (the box of the
/// feature's start and end positions, spheres grown by their radius), surfaces paired by a sweep
/// over their swept boxes, the feature candidates of the trees (bvh_candidates), then the exact
/// tests of geometry/ccd.hpp, in parallel (TBB) over the (surface pair, kind) tasks. The result
/// does not depend on the threads: crossings are sorted by (toi, task, feature pair).

#include "penalty/collision/collision_pipeline.hpp"
#include "penalty/core/index_types.hpp"
#include "penalty/geometry/ccd.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace penalty {

/// The feature pair of a crossing.
enum class CrossingKind : std::uint8_t { point_triangle, edge_edge, sphere_triangle, sphere_sphere };

/// "point-triangle", "edge-edge", "sphere-triangle", "sphere-sphere".
[[nodiscard]] const char* crossing_kind_name(CrossingKind kind);

/// One feature pair that met during the step.
struct Crossing {
    CrossingKind kind = CrossingKind::point_triangle;
    /// Feature 1: the point, the first edge or the (first) sphere; feature 2: the triangle, the
    /// other edge or sphere. The model is one of the surface's models that holds the feature.
    const CollisionModel* model1 = nullptr;
    const CollisionModel* model2 = nullptr;
    /// DOFs of the features in their states: point {p}, edge {a, b}, triangle {t1, t2, t3},
    /// sphere {centre} (−1 for the unused places).
    std::array<Index, 3> dofs1{-1, -1, -1};
    std::array<Index, 3> dofs2{-1, -1, -1};
    /// Element of model2 for a triangle or a sphere, of model1 for a sphere (−1 otherwise).
    Index element1 = -1;
    Index element2 = -1;
    double toi = 1.0;  ///< fraction of the step at which the features met (conservative: ≤ the true one)
    /// How far the features ended beyond each other (m): point–triangle, sphere–triangle and
    /// edge–edge, their distance at the end of the step; sphere–sphere, max(r1, r2) − |c2 − c1|
    /// at the end (0 when the centres left each other's sphere by then).
    double depth = 0.0;
    Vec3 point = Vec3::Zero();  ///< where they met (m, at toi): the point, edge 1's closest point or the centre
    std::size_t surface1 = 0, surface2 = 0;  ///< their surfaces (ContinuousDetection::surface_name)
    /// One line: "vertex 12 of 'ball' through triangle 7 of 'sheet' at 0.43 of the step, 2.1 mm beyond".
    [[nodiscard]] std::string describe() const;
};

/// Counts of the last detect().
struct ContinuousDetectionStats {
    std::size_t surfaces = 0;       ///< surfaces with features
    std::size_t surface_pairs = 0;  ///< pairs of surfaces whose swept boxes overlapped
    std::size_t candidates = 0;     ///< feature pairs whose swept boxes overlapped (tested exactly)
    std::size_t capped = 0;         ///< tests stopped on CcdOptions::max_iterations (reported as crossings)
};

class ContinuousDetection {
public:
    ContinuousDetection();
    ~ContinuousDetection();
    ContinuousDetection(const ContinuousDetection&) = delete;
    ContinuousDetection& operator=(const ContinuousDetection&) = delete;

    /// The model pairs to test (registered models of one or several pipelines; each pair once,
    /// any order), edge–edge tested when `edge_edge`; builds the surfaces. Throws
    /// std::invalid_argument for a null model.
    void set_pairs(std::span<const ModelPair> pairs, bool edge_edge = true);
    /// Adds the pairs a pipeline's broad phase keeps with an active intersector (registered
    /// order), edge–edge where the method makes edge–edge contacts (above), then rebuilds the
    /// surfaces: what the guard tests for a ContactPipeline.
    void add_pipeline_pairs(const IntersectionParams& params, std::span<CollisionModel* const> models);
    /// Records the current positions as the start of the motion.
    void record_start();
    /// The crossings of the motion from the recorded start to the current positions, sorted by
    /// toi (ties: surface pairs in order, then features); the reference is valid until the next
    /// call. Throws std::logic_error when no start was recorded for the current state sizes.
    const std::vector<Crossing>& detect(const CcdOptions& options = {});
    [[nodiscard]] const std::vector<Crossing>& crossings() const { return crossings_; }
    [[nodiscard]] const ContinuousDetectionStats& stats() const { return stats_; }
    [[nodiscard]] std::size_t surface_count() const;
    /// The surface holding model `m`, if it is tested.
    [[nodiscard]] std::optional<std::size_t> surface_of(const CollisionModel& m) const;
    /// The name of a surface: its models' names joined by '+'.
    [[nodiscard]] const std::string& surface_name(std::size_t surface) const;
    /// The recorded start position of DOF `dof` of the state of `model` (m; a rigid DOF: its
    /// centre), for a model of a surface; throws std::invalid_argument otherwise.
    [[nodiscard]] Vec3 start_position(const CollisionModel& model, Index dof) const;

    struct Surface;  // ccd_surfaces.cpp
    struct Task;

private:
    void build_surfaces();
    /// The (surface pair, kind) tasks of this detection: surfaces paired by a sweep over their
    /// swept boxes, the tests of each listed pair whose kinds' boxes overlap.
    void find_tasks();
    /// A task's candidate feature pairs (PairKey(e1, e2).bits()), ascending.
    void candidates(const Task& task, bool parallel, std::vector<std::uint64_t>& keys) const;
    std::vector<ModelPair> pairs_;
    std::vector<char> pair_edge_edge_;  ///< per pair: edge–edge tested
    std::vector<std::unique_ptr<Surface>> surfaces_;
    std::unordered_map<const CollisionModel*, std::size_t> surface_of_;
    /// (lower surface, higher surface) → its tests (detail::PairTest bits), ascending
    std::vector<std::pair<PairKey, std::uint32_t>> pair_tests_;
    std::vector<Task> tasks_;
    std::vector<std::vector<Crossing>> task_crossings_;  ///< per task of the last detect()
    std::vector<std::size_t> task_candidates_;
    std::vector<std::vector<std::uint64_t>> task_keys_;  ///< per task: its candidates (capacity kept)
    std::vector<std::size_t> sweep_;                     ///< find_tasks' scratch
    std::vector<PairKey> near_;                          ///< find_tasks' scratch: (lower surface, higher surface)
    std::vector<Crossing> crossings_;
    ContinuousDetectionStats stats_;
    bool started_ = false;
};

}  // namespace penalty
