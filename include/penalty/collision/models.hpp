#pragma once
/// @file
/// The concrete collision models over mechanical states (spec §3.2–3.7): Point, Line, Triangle,
/// Sphere, RigidSphere, Cylinder, Tetrahedron. Models keep a non-owning pointer to their state
/// (and topology); positions are read live, element lists are copied at construction.

#include "penalty/collision/collision_model.hpp"
#include "penalty/geometry/point_cylinder.hpp"
#include "penalty/mechanics/state.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace penalty {

/// The row of a state's positions (CollisionModel::element_row of a model with one element per DOF).
template <class State>
[[nodiscard]] CollisionModel::ElementRow position_row(const State& state) {
    return {reinterpret_cast<const std::byte*>(state.position.data()), sizeof(state.position[0])};
}

/// PointCollisionModel<Vec3>: one element per DOF; element index = DOF index.
/// Box: p ± contact_distance.
class PointModel final : public CollisionModel {
public:
    /// `topology` (optional, non-owning) is needed for the self-collision neighbour filter
    /// and the LocalMinDistance point filter.
    PointModel(const Vec3State& state, const MeshTopology* topology = nullptr, CollisionModelParams params = {});

    [[nodiscard]] std::size_t size() const override { return state_->size(); }
    [[nodiscard]] Aabb element_box(Index i) const override;
    void element_boxes(std::size_t begin, std::size_t end, Aabb* out) const override;
    void validate() const override;

    [[nodiscard]] const Vec3& point(Index i) const { return state_->position[std::size_t(i)]; }
    [[nodiscard]] ElementRow element_row() const override { return position_row(*state_); }
    [[nodiscard]] const Vec3State& state() const { return *state_; }
    [[nodiscard]] const MeshTopology* topology() const { return topology_; }

    /// SOFA applies the LocalMinDistance point filter only when the point model's node also
    /// holds a LineCollisionModel; set this to say so (default false: filter skipped).
    bool node_has_line_model = false;

protected:
    [[nodiscard]] bool elements_unchanged_and_finite() const override;

private:
    mutable std::size_t validated_state_size_ = kNotValidated;  ///< state size at the last validate()
    const Vec3State* state_;
    const MeshTopology* topology_;
};

/// LineCollisionModel<Vec3>: one element per topology edge; element index = edge index.
/// Box: AABB of the two vertices ± contact_distance.
class LineModel final : public CollisionModel {
public:
    /// SOFA's line flags (not used by the penalty intersectors, provided for completeness).
    enum Flags : std::uint32_t { kP1 = 1u, kP2 = 2u, kBP1 = 4u, kBP2 = 8u };

    LineModel(const Vec3State& state, const MeshTopology& topology, CollisionModelParams params = {});

    [[nodiscard]] std::size_t size() const override { return edges_.size(); }
    [[nodiscard]] Aabb element_box(Index i) const override;
    void element_boxes(std::size_t begin, std::size_t end, Aabb* out) const override;
    void validate() const override;

    [[nodiscard]] const Edge& edge(Index i) const { return edges_[std::size_t(i)]; }
    [[nodiscard]] const Vec3& p1(Index i) const { return state_->position[std::size_t(edges_[std::size_t(i)][0])]; }
    [[nodiscard]] const Vec3& p2(Index i) const { return state_->position[std::size_t(edges_[std::size_t(i)][1])]; }
    [[nodiscard]] std::uint32_t flags(Index i) const { return flags_[std::size_t(i)]; }
    [[nodiscard]] const Vec3State& state() const { return *state_; }
    [[nodiscard]] const MeshTopology& topology() const { return *topology_; }

protected:
    [[nodiscard]] bool elements_unchanged_and_finite() const override;

private:
    mutable std::size_t validated_state_size_ = kNotValidated;  ///< state size at the last validate()
    const Vec3State* state_;
    const MeshTopology* topology_;
    std::vector<Edge> edges_;
    std::vector<std::uint32_t> flags_;
};

/// TriangleCollisionModel<Vec3>. Elements: topology triangles (index = triangle id), then each
/// quad (q0,q1,q2,q3) as the two triangles (q1,q2,q0) and (q3,q0,q2) (elements nbTri + 2k and
/// nbTri + 2k + 1). Normal n = normalize((p2−p1)×(p3−p1)). Box: AABB of the vertices ±
/// contact_distance.
///
/// Flags (spec §3.4), only for topology triangles (split-quad triangles get 0):
/// kP1<<j if this triangle is the first of trianglesAroundVertex(t[j]); kE23/kE31/kE12 if it is
/// the first of trianglesAroundEdge of the edge opposite vertex 0/1/2; kBE23/kBE31/kBE12 if that
/// edge has a single triangle.
class TriangleModel final : public CollisionModel {
public:
    enum Flags : std::uint32_t {
        kP1 = 1u,
        kP2 = 2u,
        kP3 = 4u,
        kE23 = 8u,
        kE31 = 16u,
        kE12 = 32u,
        kBE23 = 64u,
        kBE31 = 128u,
        kBE12 = 256u,
        kPoints = kP1 | kP2 | kP3,
        kEdges = kE23 | kE31 | kE12,
    };

    TriangleModel(const Vec3State& state, const MeshTopology& topology, CollisionModelParams params = {});

    [[nodiscard]] std::size_t size() const override { return triangles_.size(); }
    [[nodiscard]] Aabb element_box(Index i) const override;
    void element_boxes(std::size_t begin, std::size_t end, Aabb* out) const override;
    void validate() const override;

    [[nodiscard]] const Triangle& triangle(Index i) const { return triangles_[std::size_t(i)]; }
    [[nodiscard]] const Vec3& p(Index i, int k) const {
        return state_->position[std::size_t(triangles_[std::size_t(i)][std::size_t(k)])];
    }
    [[nodiscard]] std::uint32_t flags(Index i) const { return flags_[std::size_t(i)]; }
    /// Whether every triangle owns its three vertices and three edges (a soup of separate
    /// triangles; flags as above, fixed at construction).
    [[nodiscard]] bool owns_every_feature() const { return owns_every_feature_; }
    /// Stored unit normal (computed by update(); may be overwritten by SOFA's Triangle–Triangle
    /// quirk §14.4, see set_normal).
    [[nodiscard]] const Vec3& normal(Index i) const { return normals_[std::size_t(i)]; }
    void set_normal(Index i, const Vec3& n) { normals_[std::size_t(i)] = n; }
    /// Computes, for the current positions, the planes the separation tests of NewProximity
    /// Triangle–Triangle read (separation.hpp), unless they are current (computed since the last
    /// update()): about 80 instructions a triangle, so CollisionPipeline calls it only for a pair
    /// with candidates, before evaluating them. Not thread-safe.
    void update_planes();
    /// True when the planes were computed since the last update() (otherwise a test must not
    /// use them).
    [[nodiscard]] bool planes_current() const { return planes_current_; }
    /// Unit normal of triangle i's plane (see update_planes; not SOFA's stored normal, and never
    /// overwritten): (AB × AC) / |AB × AC|, or zero when the plane is not reliable_plane (a thin
    /// or zero-area triangle).
    [[nodiscard]] const Vec3& plane_normal(Index i) const { return plane_normals_[std::size_t(i)]; }
    /// Largest |coordinate| of the state's positions at update_planes (m).
    [[nodiscard]] double coordinate_bound() const { return coordinate_bound_; }
    /// Number of triangles that come from the topology's triangle list (the rest are split quads).
    [[nodiscard]] std::size_t num_topology_triangles() const { return num_topology_triangles_; }
    [[nodiscard]] const Vec3State& state() const { return *state_; }
    [[nodiscard]] const MeshTopology& topology() const { return *topology_; }

    bool compute_normals = true;  ///< SOFA `computeNormals`

    /// Topological changes (docs/topological-changes.md; defined in
    /// src/collision/triangle_model_changes.cpp): the model takes its topology's triangles again,
    /// refreshing only the `touched` ones (the slots whose triangle or flags may have changed),
    /// which gives the model a construction on the changed topology would, in time proportional
    /// to `touched`. The topology must have no quads.
    void refresh_triangles(std::span<const std::size_t> touched);

protected:
    void do_update() override;
    [[nodiscard]] bool elements_unchanged_and_finite() const override;

private:
    /// The feature flags of topology triangle t (who owns its vertices and edges, its border edges).
    [[nodiscard]] std::uint32_t topology_flags(std::size_t t) const;
    std::size_t partial_feature_count_ = 0;  ///< triangles that do not own all their vertices and edges
    mutable std::size_t validated_state_size_ = kNotValidated;  ///< state size at the last validate()
    const Vec3State* state_;
    const MeshTopology* topology_;
    std::vector<Triangle> triangles_;
    std::vector<std::uint32_t> flags_;
    bool owns_every_feature_ = false;
    std::vector<Vec3> normals_;
    std::vector<Vec3> plane_normals_;
    bool planes_current_ = false;
    double coordinate_bound_ = std::numeric_limits<double>::infinity();
    std::size_t num_topology_triangles_ = 0;
};

/// SphereCollisionModel<Vec3>: one sphere per DOF, centre = DOF position,
/// r(i) = list_radius[i] if present else `radius` (default 1.0). Box: centre ± (r + contact_distance).
class SphereModel final : public CollisionModel {
public:
    SphereModel(const Vec3State& state, double radius = 1.0, std::vector<double> list_radius = {},
                CollisionModelParams params = {});

    [[nodiscard]] std::size_t size() const override { return state_->size(); }
    [[nodiscard]] Aabb element_box(Index i) const override;
    void validate() const override;

    [[nodiscard]] const Vec3& center(Index i) const { return state_->position[std::size_t(i)]; }
    [[nodiscard]] ElementRow element_row() const override { return position_row(*state_); }
    [[nodiscard]] double radius(Index i) const {
        return std::size_t(i) < list_radius_.size() ? list_radius_[std::size_t(i)] : radius_;
    }
    [[nodiscard]] const Vec3State& state() const { return *state_; }

private:
    const Vec3State* state_;
    double radius_;
    std::vector<double> list_radius_;
};

/// SphereCollisionModel<Rigid3> (RigidSphereModel): one sphere per Rigid3 DOF, centre = frame
/// origin. Same radius rule and box as SphereModel.
class RigidSphereModel final : public CollisionModel {
public:
    RigidSphereModel(const Rigid3State& state, double radius = 1.0, std::vector<double> list_radius = {},
                     CollisionModelParams params = {});

    [[nodiscard]] std::size_t size() const override { return state_->size(); }
    [[nodiscard]] Aabb element_box(Index i) const override;
    void validate() const override;

    [[nodiscard]] const Vec3& center(Index i) const { return state_->position[std::size_t(i)].center; }
    [[nodiscard]] ElementRow element_row() const override { return position_row(*state_); }
    [[nodiscard]] const RigidFrame& frame(Index i) const { return state_->position[std::size_t(i)]; }
    [[nodiscard]] double radius(Index i) const {
        return std::size_t(i) < list_radius_.size() ? list_radius_[std::size_t(i)] : radius_;
    }
    [[nodiscard]] const Rigid3State& state() const { return *state_; }

private:
    const Rigid3State* state_;
    double radius_;
    std::vector<double> list_radius_;
};

/// CylinderCollisionModel<Rigid3>: one solid cylinder per Rigid3 DOF. Per-cylinder radius,
/// height and local axis (defaults 0.5, 2, (0,1,0)); world axis = orientation·local axis; end
/// points = centre ∓ axis·h/2. Box: both end points ± radius (SOFA adds no contact distance).
class CylinderModel final : public CollisionModel {
public:
    CylinderModel(const Rigid3State& state, double default_radius = 0.5, double default_height = 2.0,
                  const Vec3& default_local_axis = Vec3::UnitY(), CollisionModelParams params = {});

    [[nodiscard]] std::size_t size() const override { return state_->size(); }
    [[nodiscard]] Aabb element_box(Index i) const override;
    void validate() const override;

    std::vector<double> radii;     ///< per-cylinder radius (padded with the default)
    std::vector<double> heights;   ///< per-cylinder full height
    std::vector<Vec3> local_axes;  ///< per-cylinder local axis (normalised on use)

    [[nodiscard]] double radius(Index i) const;
    [[nodiscard]] double height(Index i) const;
    /// Unit local axis of element i (body frame).
    [[nodiscard]] Vec3 local_axis(Index i) const;
    /// A unit world vector ⟂ to the axis, fixed in the body frame (moves with the cylinder).
    [[nodiscard]] Vec3 radial_direction(Index i) const;
    /// World-frame solid cylinder of element i.
    [[nodiscard]] CylinderShape shape(Index i) const;
    [[nodiscard]] const RigidFrame& frame(Index i) const { return state_->position[std::size_t(i)]; }
    [[nodiscard]] const Rigid3State& state() const { return *state_; }

private:
    const Rigid3State* state_;
    double default_radius_;
    double default_height_;
    Vec3 default_axis_;
};

/// TetrahedronCollisionModel: one element per topology tetrahedron; stores coord2bary =
/// [p1−p0, p2−p0, p3−p0]^{-1} (updated by update()). Box: AABB of the vertices ± contact_distance.
class TetrahedronModel final : public CollisionModel {
public:
    TetrahedronModel(const Vec3State& state, const MeshTopology& topology, CollisionModelParams params = {});

    [[nodiscard]] std::size_t size() const override { return tetrahedra_.size(); }
    [[nodiscard]] Aabb element_box(Index i) const override;
    void element_boxes(std::size_t begin, std::size_t end, Aabb* out) const override;
    void validate() const override;

    [[nodiscard]] const Tetrahedron& tetrahedron(Index i) const { return tetrahedra_[std::size_t(i)]; }
    [[nodiscard]] const Vec3& p(Index i, int k) const {
        return state_->position[std::size_t(tetrahedra_[std::size_t(i)][std::size_t(k)])];
    }
    /// Barycentric weights (1−fx−fy−fz, fx, fy, fz) of P, (fx,fy,fz) = coord2bary·(P − p0).
    [[nodiscard]] std::array<double, 4> barycentric(Index i, const Vec3& P) const;
    [[nodiscard]] const Vec3State& state() const { return *state_; }

protected:
    [[nodiscard]] bool elements_unchanged_and_finite() const override;
    void do_update() override;

private:
    mutable std::size_t validated_state_size_ = kNotValidated;  ///< state size at the last validate()
    const Vec3State* state_;
    std::vector<Tetrahedron> tetrahedra_;
    std::vector<Mat3> coord2bary_;
};

}  // namespace penalty
