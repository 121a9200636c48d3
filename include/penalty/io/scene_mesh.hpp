#pragma once
/// @file
/// The loading of the meshes that loader components (and `MeshTopology filename=`) name, with
/// SOFA's MeshLoader options. (The component types and their attributes are the scene layer's
/// registry, penalty/scene/components.hpp.)

#include "penalty/io/mesh.hpp"
#include "penalty/io/scene_file.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace penalty::io {

/// Loads the mesh of a loader component (MeshOBJLoader, MeshGmshLoader, SphereLoader,
/// MeshVTKLoader) or of a `MeshTopology` / `MechanicalObject` with a `filename`, as SOFA
/// would give it to the components that link to it:
///  - the file name is resolved with resolve_data_file(scene_dir, data_dirs);
///  - MeshLoader options: `triangulate`, `flipNormals` (not for Gmsh, as SOFA), `createSubelements`
///    (default true for MeshGmshLoader, false otherwise), then the transform
///    `translation`, `rotation` (degrees), `scale3d` times the scalar `scale`;
///  - SphereLoader: `translation`, `rotation`, `scale`/`scale3d` (3 numbers) on the centers,
///    radii unchanged;
///  - MeshTopology / MechanicalObject `filename`: the raw file, no transform.
/// Options SOFA offers but penalty does not (`transformation` other than identity,
/// `onlyAttachedPoints` true) are errors, since they change the point list; `handleSeams` is
/// load_obj's handle_seams (MeshOBJLoader only).
/// @throws SceneError naming the component and attribute (a LoadError from the file is wrapped:
///         `file:line: MeshOBJLoader 'loader': attribute 'filename': <file error>`).
/// The scalar `scale` of a mesh loader as SOFA's MeshLoader::parse reads it
/// (BaseObjectDescription::getAttributeAsFloat): a text that is not read whole ("0.25 0.25 0.25")
/// gives the default 1 (SOFA logs an error and goes on). Rounded to float as SOFA's strtof
/// (0.1 → 0.10000000149011612), in double when `in_double` (the SOFA quirk fix
/// mesh_loader_float_scale); a value beyond float range is an error naming the attribute.
/// `read_whole`, when given, tells whether the text was one number. Absent: 1.
[[nodiscard]] double mesh_loader_scale(const SceneComponent& component, bool* read_whole = nullptr,
                                       bool in_double = false);

/// `scale_in_double`: a mesh loader's `scale` in double (mesh_loader_scale's `in_double`).
[[nodiscard]] MeshData load_scene_mesh(const SceneComponent& component, const std::filesystem::path& scene_dir,
                                       const std::vector<std::filesystem::path>& data_dirs,
                                       bool scale_in_double = false);

}  // namespace penalty::io
