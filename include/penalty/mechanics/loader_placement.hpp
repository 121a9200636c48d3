#pragma once
/// @file
/// How SOFA's loaders place the points they read (translation, rotation, scale), in SOFA's
/// operations, so that a scene's initial positions are SOFA's to the bit.

#include "penalty/core/types.hpp"

#include <span>

namespace penalty {

/// SOFA's MeshLoader family (MeshOBJLoader, MeshGmshLoader, MeshVTKLoader, MeshOffLoader,
/// MeshTrianLoader, GridMeshCreator) or SphereLoader.
enum class LoaderKind { mesh_loader, sphere_loader };

/// Places loaded points (m) as SOFA's loaders do. T = Matrix4::transformTranslation(t) ·
/// transformRotation(Quat::createQuaterFromEuler(r·π/180)) · transformScale(s), the 4×4 products
/// summed term by term, and a point goes to T.transform(p) = Σ_j T_ij·p_j + T_i3, left to right:
/// scale first, then the rotation R = Rz·Ry·Rx (x first), then the translation.
/// SphereLoader::applyTransform applies T once. A MeshLoader applies it in reinit, which SOFA HEAD
/// runs twice (MeshLoader::init, then the update callback of its transform Data when its positions
/// are first read), the second undoing the first with transformInvert(T) (its 3×3 part inverted by
/// cofactors over the determinant, t' = −R⁻¹·t) before applying T again: the points are
/// T(T⁻¹(T(p))), which can differ from T(p) in the last bits (a singular T, s with a 0, skips
/// the round trip). Nothing happens for t = 0, r = 0, s = 1.
void place_loaded_points(std::span<Vec3> points, const Vec3& translation, const Vec3& rotation_degrees,
                         const Vec3& scale3d, LoaderKind kind);

}  // namespace penalty
