#pragma once
/// @file
/// SOFA's shape matching (Müller et al. 2005) as its example scene ShapeMatching.scn wires it:
///   - ClusteringEngine (Sofa.Component.Engine.Analyze): overlapping clusters of points;
///   - ShapeMatching (same module): per cluster, the rigid (or rigid/affine blended) transform of
///     the rest cluster that best fits the current points; each point's target is the mean of its
///     clusters' transforms of its rest position;
///   - PositionBasedDynamicsProjectiveConstraint (Sofa.Component.Constraint.Projective): after each
///     step the positions are moved toward the targets and the velocities set from the motion.
/// docs/components/shape_matching.md cites SOFA's methods for each rule.

#include "penalty/core/types.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/topology.hpp"

#include <functional>
#include <vector>

namespace penalty {

/// ClusteringEngine's Data (SOFA's defaults).
struct ClusteringParameters {
    bool use_topology = true;   ///< useTopo: geodesic (edge-path) distances when a topology is given
    double radius = 1.0;        ///< radius (m): neighbourhood range
    double fixed_radius = 1.0;  ///< fixedRadius (m): range for the non-mechanical points
    int number = -1;            ///< number of clusters; -1: one cluster per point
};

/// ClusteringEngine::doUpdate: the clusters of `positions` (rest positions). Each cluster starts
/// with its seed. Seeds: farthest-point sampling from point 0 (ClusteringEngine::farthestPointSampling,
/// distances Euclidean or, with a topology and use_topology, Dijkstra along its edges; a point
/// whose distance is the largest and first in index order is the next seed; stops when it is 0),
/// or every point when number is -1. Members, with a topology: a breadth-first growth along the
/// edges from the seed, adding each neighbour within `radius` of the seed or any neighbour of a
/// point of the seed's Voronoi region (AddNeighborhoodFromNeighborhood); without: every point
/// within `radius` of the seed, a point in no cluster going to the nearest seed's, then the
/// `fixed_positions` within `fixed_radius` (index positions.size() + j). LLoyd is empty in SOFA.
/// `vertices_around_vertex`: the topology's lists (SOFA's order), or null for none.
[[nodiscard]] std::vector<std::vector<PointId>> clustering_engine(
    const std::vector<Vec3>& positions, const std::vector<std::vector<PointId>>* vertices_around_vertex,
    const ClusteringParameters& params, const std::vector<Vec3>& fixed_positions = {});

/// SOFA's helper::Decompose<double>::polarDecomposition(M, Q): the orthogonal factor Q of M = Q·S
/// by Higham's scaled Newton iteration on Mᵀ (γ from the one- and infinity-norms of the adjugate),
/// until ‖E‖₁ ≤ 1e-8·‖M_k‖₁; a zero determinant stops the iteration where it is.
[[nodiscard]] Mat3 sofa_polar_rotation(const Mat3& m);

/// ShapeMatching's Data (SOFA's defaults).
struct ShapeMatchingParameters {
    unsigned iterations = 1;    ///< iterations
    double affine_ratio = 0.0;  ///< affineRatio: 0 rigid, 1 affine (T·Qx⁻¹)
    double fixed_weight = 1.0;  ///< fixedweight of the non-mechanical points
};

/// ShapeMatching<Vec3d>::doUpdate. Built once from the clusters and the rest positions (the
/// cluster centres Xcm0 = Σw x0/W and Qx⁻¹ = (Σw x0x0ᵀ − W Xcm0Xcm0ᵀ)⁻¹); targets() then maps
/// current positions to targets: per iteration, per cluster T = Σw p x0ᵀ − (Σw p) Xcm0ᵀ,
/// R = polar factor of T, target(j) = mean over j's clusters of Xcm + R (x0_j − Xcm0), with the
/// previous iteration's targets as p (the current positions first). A point in no cluster keeps
/// its current position.
class ShapeMatching {
public:
    ShapeMatching(std::vector<std::vector<PointId>> clusters, std::vector<Vec3> rest_positions,
                  const ShapeMatchingParameters& params, std::vector<Vec3> fixed_rest_positions = {},
                  std::vector<Vec3> fixed_positions = {});
    /// The target of each point of `current` (the size of the rest positions).
    void targets(const std::vector<Vec3>& current, std::vector<Vec3>& out) const;
    [[nodiscard]] std::size_t num_clusters() const { return clusters_.size(); }

private:
    std::vector<std::vector<PointId>> clusters_;
    std::vector<Vec3> rest_;
    ShapeMatchingParameters params_;
    std::vector<Vec3> fixed_rest_, fixed_;
    std::vector<Vec3> rest_centres_;           ///< Xcm0 per cluster
    std::vector<Mat3> inverse_covariance_;     ///< Qx⁻¹ per cluster
    std::vector<double> weights_;              ///< W per cluster
    std::vector<unsigned> clusters_of_point_;  ///< number of clusters holding each point
};

/// The target positions of PositionBasedDynamicsProjectiveConstraint: fixed, or computed from
/// the state's positions when the constraint projects (SOFA reads its `position` link then, which
/// updates the engine behind it).
using TargetPositions = std::function<void(const std::vector<Vec3>& current, std::vector<Vec3>& target)>;

/// PositionBasedDynamicsProjectiveConstraint<Vec3d>::projectPosition: with dt > 0, per point
///   x ← x + s·(target − x),  v_pbd = (x − x_old)/dt,  x_old ← x
/// (x_old: the positions at the first projection, before it moves them); projectVelocity copies
/// v_pbd over the velocities (refused, as SOFA's error, until a projection has set them);
/// projectResponse does nothing. Empty `targets`: SOFA's case of an empty target list (a size
/// error at each projection): nothing is projected.
class PositionBasedDynamicsConstraint final : public BaseProjectiveConstraint {
public:
    PositionBasedDynamicsConstraint(Vec3Object& state, TargetPositions targets, double stiffness, ContextClock dt);
    void project_response(Eigen::Ref<Eigen::VectorXd> /*v*/) const override {}
    void project_velocity() override;
    void project_position() override;
    [[nodiscard]] bool projects_positions() const override { return true; }
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] const std::vector<Vec3>& pbd_velocities() const { return velocity_; }

private:
    Vec3Object* state_;
    TargetPositions targets_;
    double stiffness_;
    ContextClock dt_;
    std::vector<Vec3> target_, velocity_, old_position_;
};

}  // namespace penalty
