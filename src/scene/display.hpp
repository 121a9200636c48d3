#pragma once
// Number and path formatting of the one-line descriptions of `penalty info` (scene_builder.cpp
// writes the component roles, describe.cpp the tree and the contact pairs).
#include "penalty/core/types.hpp"
#include "penalty/io/mesh.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/simulation/solver.hpp"  // Node (its OdeSolver member needs the full type)

#include <string>

namespace penalty::scene::display {

/// Six significant digits (a display, not a round trip: the writers use output::format_number).
[[nodiscard]] std::string number(double value);
/// "(x, y, z)" with number().
[[nodiscard]] std::string vector(const Vec3& v);
/// Path of a simulation node as in the file: "/" for the root, "/A/B" below.
[[nodiscard]] std::string node_path(const Node& node);
/// Path of a file node: "/" for the root, "/A/B" below.
[[nodiscard]] std::string node_path(const io::SceneNode& node);

/// "1 DOF", "3 DOFs".
[[nodiscard]] std::string counted(std::size_t n, std::string_view singular, std::string_view plural);
/// "8 points, 12 edges, 6 quads" (the kinds present).
[[nodiscard]] std::string element_counts(std::size_t points, const MeshTopology& t);
[[nodiscard]] std::string mesh_counts(const io::MeshData& m);

}  // namespace penalty::scene::display
