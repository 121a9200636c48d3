#pragma once
/// @file
/// Which SOFA component types a scene may use, a scene check before building, and the loading
/// of the meshes that loader components (and `MeshTopology filename=`) name.

#include "penalty/io/mesh.hpp"
#include "penalty/io/scene_file.hpp"

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::io {

/// How penalty treats a component type.
enum class ComponentCategory {
    physics,  ///< changes the simulation; the scene builder must implement it
    loader,   ///< reads a data file (mesh, spheres); its outputs are linked by other components
    ignored,  ///< visual or editor only: accepted and ignored
};

/// One known component type.
struct ComponentInfo {
    std::string_view type;         ///< SOFA class name (XML tag)
    ComponentCategory category;
    std::string_view role;         ///< one-line description
};

/// Every known type, physics first, then loaders, then ignored ones.
[[nodiscard]] std::span<const ComponentInfo> known_components();

/// Category of a type; nullopt when unknown.
[[nodiscard]] std::optional<ComponentCategory> component_category(std::string_view type);

/// Mapping types (their `output` may be a visual model, in which case they are visual-only).
[[nodiscard]] bool is_mapping_type(std::string_view type);

/// Result of validate().
struct SceneCheck {
    std::vector<const SceneComponent*> physics;  ///< physics components, depth-first order
    std::vector<const SceneComponent*> loaders;  ///< loaders used by physics components (through a link)
    std::vector<const SceneComponent*> ignored;  ///< visual-only components, visual mappings and
                                                 ///< loaders no physics component uses
    /// One line: `ignored N visual-only components: OglModel x4, RequiredPlugin x13, ...`
    /// (types sorted by name; a mapping to a visual model is listed as `Type (visual output)`,
    /// a loader used only by visual components as `Type (visual only)`).
    std::string summary;
};

/// Checks a parsed scene before it is built:
///  - every component type is known (physics, loader or ignored);
///  - a mapping whose `output` links to an ignored component is visual-only;
///  - the links in `src`, `input`, `output` and in any attribute of a physics component resolve;
///  - a loader is "used" when a physics component (or a used loader) links to it.
/// @throws SceneError `file:line: unknown component 'Type' (not supported by penalty)` for the
///         first unknown type, or the broken-link error of resolve_link().
[[nodiscard]] SceneCheck validate(const SceneFile& scene);

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
/// `onlyAttachedPoints`, `handleSeams` true) are errors, since they change the point list.
/// @throws SceneError naming the component and attribute (a LoadError from the file is wrapped:
///         `file:line: MeshOBJLoader 'loader': attribute 'filename': <file error>`).
[[nodiscard]] MeshData load_scene_mesh(const SceneComponent& component, const std::filesystem::path& scene_dir,
                                       const std::vector<std::filesystem::path>& data_dirs);

}  // namespace penalty::io
