#pragma once
/// @file
/// The surfaces and tasks of ContinuousDetection (private to the collision stage): each surface's
/// features (DOF indices into its state), its recorded start positions and its swept-box trees.

#include "penalty/collision/bvh.hpp"
#include "penalty/collision/ccd_detection.hpp"
#include "penalty/mechanics/state.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace penalty {

namespace detail {

/// A CollisionModel view of a list of boxes, so that a Bvh can be built over swept boxes (the
/// tree reads only size() and element_boxes()).
class SweptBoxes final : public CollisionModel {
public:
    SweptBoxes();
    [[nodiscard]] std::size_t size() const override { return boxes.size(); }
    [[nodiscard]] Aabb element_box(Index i) const override { return boxes[std::size_t(i)]; }
    void element_boxes(std::size_t begin, std::size_t end, Aabb* out) const override;
    std::vector<Aabb> boxes;
};

/// The feature kinds of a surface (the index of its trees).
enum FeatureKind : int {
    kVertexFeature = 0,
    kEdgeFeature = 1,
    kTriangleFeature = 2,
    kSphereFeature = 3,
    kFeatureKinds = 4
};

/// The tests of a pair of surfaces (a, b), a ≤ b, as bits: `ab` tests a's first feature against
/// b's second, `ba` the other way (for a == b only the `ab` bits are used).
enum PairTest : std::uint32_t {
    kVertexTriangleAB = 1u << 0,
    kVertexTriangleBA = 1u << 1,
    kEdgeEdge = 1u << 2,
    kSphereTriangleAB = 1u << 3,
    kSphereTriangleBA = 1u << 4,
    kSphereSphere = 1u << 5,
};

}  // namespace detail

struct ContinuousDetection::Surface {
    std::string name;
    const Vec3State* vec3 = nullptr;  ///< the state (one of the two)
    const Rigid3State* rigid = nullptr;
    std::vector<const CollisionModel*> models;

    // features: DOFs in the state, and the model (and element) each comes from
    std::vector<Index> vertices;
    std::vector<const CollisionModel*> vertex_model;
    std::vector<std::array<Index, 2>> edges;
    std::vector<const CollisionModel*> edge_model;
    std::vector<std::array<Index, 3>> triangles;
    std::vector<const CollisionModel*> triangle_model;
    std::vector<Index> triangle_element;
    std::vector<Index> sphere_dof;
    std::vector<double> sphere_radius;
    std::vector<const CollisionModel*> sphere_model;
    std::vector<Index> sphere_element;

    // the motion: positions (centres for a Rigid3 state) at record_start; empty: read live
    std::vector<Vec3> start;
    bool start_live = true;
    std::size_t recorded_size = 0;  ///< the state's size at record_start

    // swept boxes per feature kind, a tree over those of more than kTreeMin features, the
    // union of a kind's boxes and of all
    std::array<detail::SweptBoxes, detail::kFeatureKinds> boxes;
    std::array<Bvh, detail::kFeatureKinds> trees;
    std::array<Aabb, detail::kFeatureKinds> kind_box;
    Aabb swept_box;
    std::array<bool, detail::kFeatureKinds> tree_built{};
    /// Features of one kind below which a plain list of boxes is tested (a tree's building and
    /// traversal cost more than the few box tests of a small body).
    static constexpr std::size_t kTreeMin = 32;
    [[nodiscard]] bool has_tree(int kind) const { return feature_count(kind) > kTreeMin; }

    [[nodiscard]] std::size_t state_size() const { return vec3 ? vec3->size() : rigid->size(); }
    [[nodiscard]] Vec3 now(Index dof) const {
        return vec3 ? vec3->position[std::size_t(dof)] : rigid->position[std::size_t(dof)].center;
    }
    [[nodiscard]] Vec3 then(Index dof) const { return start_live ? now(dof) : start[std::size_t(dof)]; }
    [[nodiscard]] std::size_t feature_count(int kind) const;
    /// Computes the swept boxes and refits (or builds) the trees; the union box.
    void update_trees();
};

/// One (surface pair, test) of a detection.
struct ContinuousDetection::Task {
    std::size_t first = 0, second = 0;  ///< surfaces: `first`'s features of kind1 against `second`'s of kind2
    int kind1 = 0, kind2 = 0;
    CrossingKind crossing = CrossingKind::point_triangle;
};

}  // namespace penalty
