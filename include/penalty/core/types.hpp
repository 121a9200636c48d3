#pragma once
/// @file
/// Small value types shared by every layer: 3-vectors, 3x3 matrices, rigid frames.
/// Double precision throughout (SOFA's SReal = double). Eigen underneath.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <cstdint>
#include <span>
#include <vector>

namespace penalty {

using Real = double;
using Vec3 = Eigen::Vector3d;  ///< position, displacement, force, normal (3 doubles, unaligned)
using Mat3 = Eigen::Matrix3d;  ///< 3x3 block (stiffness, rotation)
using Quat = Eigen::Quaterniond;
using Index = std::int64_t;  ///< element and DOF indices

/// A Rigid3 frame: world position of the origin and orientation (body -> world).
/// SOFA's Rigid3d coordinate, stored in its file order x y z qx qy qz qw.
struct RigidFrame {
    Vec3 center = Vec3::Zero();
    Quat orientation = Quat::Identity();
};

/// Rigid3 velocity or small displacement: linear part, then angular part (world frame).
struct RigidDeriv {
    Vec3 linear = Vec3::Zero();
    Vec3 angular = Vec3::Zero();
};

using Vec3List = std::vector<Vec3>;
using ConstVec3Span = std::span<const Vec3>;
using Vec3Span = std::span<Vec3>;

/// Sparse matrix triplets; global assembly collects them then calls setFromTriplets (which sums
/// duplicates).
using Triplet = Eigen::Triplet<Real, Eigen::Index>;
using TripletList = std::vector<Triplet>;
using SparseMatrix = Eigen::SparseMatrix<Real, Eigen::RowMajor, Eigen::Index>;

}  // namespace penalty
