#pragma once
// Number and path formatting of the one-line descriptions of `penalty info` (scene_builder.cpp
// writes the component roles, describe.cpp the tree and the contact pairs).
#include "penalty/core/types.hpp"
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

}  // namespace penalty::scene::display
