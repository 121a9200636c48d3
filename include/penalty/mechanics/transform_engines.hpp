#pragma once
/// @file
/// SOFA's point-transforming data engines, with SOFA's operations so that the points they give a
/// MechanicalObject agree with SOFA's to the last bit:
///   - TransformEngine (TransformEngine::doUpdate): scale, then the rotation of the Euler angles
///     (degrees, R = Rz·Ry·Rx: Quat::createQuaterFromEuler(r·(π/180)) then Quat::rotate), then the
///     rotation of a quaternion, then the translation; each step only when it is not the identity.
///     `inverse`: the inverse steps in the reverse order (1/s, q⁻¹, −t).
///   - TransformPosition (TransformPosition::doUpdate): one method among translation, scale (about
///     an origin), rotation, scaleTranslation, scaleRotationTranslation, projectOnPlane, affine (a
///     4×4 matrix) and fromFile (the affine matrix of a .tfm, .trm, .xfm or .txt file); the points
///     of `fixedIndices` keep their input position.
///   - MergePoints (MergePoints::doUpdate): two point lists merged, appended or, with `mappingX2`,
///     the second injected into the first at the given indices.

#include "penalty/core/types.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace penalty {

/// TransformEngine's Data (SOFA's defaults).
struct TransformEngineParameters {
    Vec3 translation = Vec3::Zero();
    Vec3 rotation_deg = Vec3::Zero();    ///< Euler angles (degrees)
    Quat quaternion = Quat::Identity();  ///< applied after the Euler rotation
    Vec3 scale = Vec3::Ones();
    bool inverse = false;
};

/// The transformed points (TransformEngine::doUpdate on Vec3d points).
std::vector<Vec3> transform_engine(std::span<const Vec3> points, const TransformEngineParameters& p);

/// TransformPosition's methods.
enum class TransformPositionMethod {
    project_on_plane,
    translation,
    rotation,
    scale,
    scale_translation,
    scale_rotation_translation,
    affine,  ///< also `fromFile`, whose file gives the matrix
};

/// TransformPosition's Data (SOFA's defaults).
struct TransformPositionParameters {
    TransformPositionMethod method = TransformPositionMethod::project_on_plane;
    Vec3 origin = Vec3::Zero();  ///< a point of the plane; the centre of `scale`
    Vec3 normal = Vec3::Zero();  ///< the plane's normal (normalised as TransformPosition::init)
    Vec3 translation = Vec3::Zero();
    Vec3 rotation_deg = Vec3::Zero();
    Vec3 scale = Vec3::Ones();
    Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();  ///< affine
    std::vector<PointId> fixed_indices;                    ///< keep their input position
};

/// The transformed points (TransformPosition::doUpdate). Throws std::invalid_argument for a
/// fixed index out of range.
std::vector<Vec3> transform_position(std::span<const Vec3> points, const TransformPositionParameters& p);

/// The affine matrix of a transformation file, as TransformPosition reads it by its extension:
/// .tfm (ITK: the 12 numbers of the first line holding "Parameters", a 3×3 matrix row by row, then
/// the translation, which SOFA reads backwards: t_i = value[11 − i]), .trm (a translation line,
/// then three matrix rows), .xfm or .txt (four rows of four). Throws std::invalid_argument
/// (file and line) for a file that cannot be read or does not hold the numbers the format needs.
Eigen::Matrix4d read_affine_transform_file(const std::filesystem::path& path);

/// What MergePoints gives: the merged points and which of them come from each input.
struct MergedPoints {
    std::vector<Vec3> points;
    std::vector<PointId> indices1;  ///< indices (into points) of the first list's points
    std::vector<PointId> indices2;  ///< of the second list's
};

/// MergePoints::doUpdate. Without `mapping_x2`: points = x1 then x2. With it (injection): points =
/// x1 with x1[mapping_x2[i]] = x2[i] for each i whose index is inside x1 (SOFA skips the others);
/// indices2 = the sorted mapping indices met while walking the points, indices1 the rest.
/// Throws std::invalid_argument when mapping_x2 has more entries than x2 has points.
MergedPoints merge_points(std::span<const Vec3> x1, std::span<const Vec3> x2, std::vector<PointId> mapping_x2);

}  // namespace penalty
