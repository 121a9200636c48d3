#pragma once
// The attributes the scene builder reads, per component type. Anything else on a physics
// component is reported ("not read by penalty") so that a user sees which SOFA Data have no
// effect here. Attributes that never change the physics (printLog, tags, draw...) are accepted
// silently on every element.
#include "penalty/io/scene_file.hpp"

#include <string>
#include <vector>

namespace penalty::scene {

/// Attributes of `element` that penalty does not read (file order).
[[nodiscard]] std::vector<std::string> unread_attributes(const io::SceneElement& element);

/// Attributes penalty reads for a component type ("" for an unknown type).
[[nodiscard]] std::vector<std::string> read_attributes(const std::string& type);

}  // namespace penalty::scene
