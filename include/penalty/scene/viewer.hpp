#pragma once
/// @file
/// The browser viewer of a built scene: what each collision model looks like
/// (output::ViewerShape) and the writer the runner feeds (`penalty run --view DIR`).

#include "penalty/output/viewer_writer.hpp"
#include "penalty/scene/scene.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace penalty::scene {

/// The states the viewer draws and one shape per collision model, in scene order.
struct ViewerBodies {
    std::vector<const output::StateRecord*> states;  ///< the states of the collision models, scene order
    std::vector<output::ViewerShape> shapes;         ///< ViewerShape::state indexes `states`
};

/// Triangle models: their triangles; Tetrahedron models: the faces that belong to one
/// tetrahedron only (the boundary); Line: edges; Point: every DOF; Sphere and RigidSphere:
/// every DOF with its radius; Cylinder: every frame with radius, height and local axis.
/// A scene without any collision model gets one points shape (type "state") per Vec3 state.
/// Throws std::invalid_argument when a model's state is not one of the scene's states.
[[nodiscard]] ViewerBodies viewer_bodies(const Scene& scene);

/// A ViewerWriter over viewer_bodies(scene) in `directory`.
[[nodiscard]] std::unique_ptr<output::ViewerWriter> open_viewer(const Scene& scene,
                                                                const std::filesystem::path& directory,
                                                                std::string title);

}  // namespace penalty::scene
