#pragma once
/// @file
/// Base of every collision model (SOFA's CollisionModel): the common parameters with SOFA's
/// defaults (spec §3.1), the model kind, per-element and per-model axis-aligned boxes, and the
/// `canCollideWith` rule.

#include "penalty/core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace penalty {

/// The kinds of collision model. The numeric order is the row/column order of the dispatch
/// table (see intersection.hpp). The scoped enumerators Triangle and Tetrahedron share their
/// names with the element types of topology.hpp; GCC's -Wshadow reports that when topology.hpp is
/// included first, although scoped enumerators cannot be confused with them.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#endif
enum class ModelType : std::uint8_t { Point, Line, Triangle, Sphere, RigidSphere, Cylinder, Tetrahedron };
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
inline constexpr int kModelTypeCount = 7;

/// SOFA-like name: "Point", "Line", "Triangle", "Sphere", "RigidSphere", "Cylinder", "Tetrahedron".
[[nodiscard]] const char* model_type_name(ModelType t);

/// Axis-aligned box [min, max] (m). An empty box has min > max.
struct Aabb {
    Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

    [[nodiscard]] bool empty() const { return (min.array() > max.array()).any(); }
    void extend(const Vec3& p) {
        min = min.cwiseMin(p);
        max = max.cwiseMax(p);
    }
    void extend(const Aabb& b) {
        min = min.cwiseMin(b.min);
        max = max.cwiseMax(b.max);
    }
    /// Grows the box by m on every side.
    void inflate(double m) {
        min.array() -= m;
        max.array() += m;
    }
    /// SOFA's proximity cube test: the boxes are disjoint iff on some axis
    /// min1 > max2 + margin or min2 > max1 + margin (so touching boxes overlap).
    [[nodiscard]] bool overlaps(const Aabb& o, double margin = 0.0) const {
        for (int i = 0; i < 3; ++i)
            if (min[i] > o.max[i] + margin || o.min[i] > max[i] + margin) return false;
        return true;
    }
};

/// The Data common to all SOFA collision models, with SOFA's defaults.
struct CollisionModelParams {
    std::string name;                  ///< used in error messages and contact names
    bool active = true;                ///< excluded from detection if false
    bool moving = true;                ///< false: per-element data (normals) computed once only
    bool simulated = true;             ///< pairs of two non-simulated models are skipped
    bool self_collision = false;       ///< models of the same node collide only if true
    double contact_distance = 0.0;     ///< SOFA `contactDistance` (alias `proximity`), m, ≥ 0:
                                       ///< skin added to alarm/contact distances and to `dist`
    double contact_stiffness = 10.0;   ///< SOFA `contactStiffness` k (ks = k1·k2/dist), ≥ 0
    double contact_friction = 0.0;     ///< summed into mu_v, unused by the penalty response
    double contact_restitution = 0.0;  ///< unused
    std::string contact_response;      ///< per-model response override ("" = none)
    std::vector<int> group;            ///< models sharing a group id never collide
    /// Identifier of the scene-graph node (SOFA "context") that holds the model. Two models
    /// with the same node id ≥ 0, or a model with itself, are "in the same node".
    /// −1 (default) = a node of its own.
    int node = -1;
    bool both_side = false;  ///< SOFA `bothSide` (Point/Line/Triangle; LMD filters)
};

/// A collision model: a list of elements over a mechanical state.
class CollisionModel {
public:
    CollisionModel(ModelType type, CollisionModelParams params);
    virtual ~CollisionModel() = default;
    CollisionModel(const CollisionModel&) = default;
    CollisionModel& operator=(const CollisionModel&) = default;

    [[nodiscard]] ModelType type() const { return type_; }
    [[nodiscard]] const CollisionModelParams& params() const { return params_; }
    /// Mutable parameters; call validate() after changing them.
    [[nodiscard]] CollisionModelParams& params() { return params_; }
    [[nodiscard]] const std::string& name() const { return params_.name; }

    /// Number of elements.
    [[nodiscard]] virtual std::size_t size() const = 0;
    /// Box of element i (SOFA's leaf cube): see each model for its enlargement.
    [[nodiscard]] virtual Aabb element_box(Index i) const = 0;
    /// out[k] = element_box(begin + k) for k < end − begin: one virtual call for a range (the
    /// models of meshes override it with a loop the compiler can inline).
    virtual void element_boxes(std::size_t begin, std::size_t end, Aabb* out) const;
    /// Where element i's own data lies in memory: base + i·stride bytes. The kernels read it
    /// for every candidate, in no memory order, so evaluate_candidates prefetches it a few
    /// candidates ahead. A hint for the prefetch only, never read through; {nullptr, 0} (the
    /// default) for a model whose elements have no such row.
    struct ElementRow {
        const std::byte* base = nullptr;
        std::size_t stride = 0;
    };
    [[nodiscard]] virtual ElementRow element_row() const { return {}; }
    /// Union of the element boxes (empty box for an empty model).
    [[nodiscard]] Aabb model_box() const;

    /// Recomputes per-element derived data from the current positions (SOFA's
    /// computeBoundingTree part that matters for detection: triangle normals, tetrahedron
    /// coord2bary). When `moving` is false only the first call recomputes.
    void update();

    /// Checks parameters and positions; throws std::invalid_argument naming the model, the
    /// element and the parameter (NaN/inf positions, negative radius, bad indices, ...).
    virtual void validate() const;
    /// Throws std::invalid_argument for a non-finite position of element `elem` (validate()'s rule).
    void check_point(const Vec3& p, Index elem, const char* what) const;
    /// The check before each detection: the same outcome as validate() (the same error, if any),
    /// cheaper when the model can tell that its elements passed validate() before and nothing
    /// validate() reads has changed but the positions, which are all finite (see
    /// elements_unchanged_and_finite); then only the parameters are checked again.
    void validate_for_step() const;

protected:
    /// validated_state_size_ of a model whose elements have not passed validate() yet.
    static constexpr std::size_t kNotValidated = std::size_t(-1);
    virtual void do_update() {}
    /// True only if a validate() of the elements would pass: every position of the state is
    /// finite and the state's size is the one the last successful validate() saw. Default: false
    /// (validate_for_step() runs validate()).
    [[nodiscard]] virtual bool elements_unchanged_and_finite() const { return false; }

private:
    ModelType type_;
    CollisionModelParams params_;
    bool updated_once_ = false;
};

/// True when the two models are in the same scene-graph node (or are the same model).
[[nodiscard]] bool same_node(const CollisionModel& a, const CollisionModel& b);

/// SOFA's canCollideWith(a, b): same node → a.self_collision; else if either group set is
/// empty → true; else true iff the group sets are disjoint.
[[nodiscard]] bool can_collide_with(const CollisionModel& a, const CollisionModel& b);

/// The model-pair filter of SOFA's broad phase: both active, not both non-simulated,
/// can_collide_with(a, b) && can_collide_with(b, a).
[[nodiscard]] bool keep_model_pair(const CollisionModel& a, const CollisionModel& b);

}  // namespace penalty
