#pragma once
// The table of when a write of a Data after init takes effect (src/scene/live_policy.cpp).
#include "penalty/scene/live_data.hpp"

#include <string>
#include <string_view>

namespace penalty::scene {

/// How a write after init of Data `name` of a component of `type` (or of a node) takes effect:
/// `spec` is the registry's attribute (null when penalty does not read it), `sofa` SOFA's
/// catalog row (null when SOFA's catalog lacks it). `refusal` gets the reason of a refusal.
[[nodiscard]] LiveWrite live_policy(std::string_view type, bool node, std::string_view name, const AttributeSpec* spec,
                                    const CatalogEntry* sofa, std::string& refusal);

}  // namespace penalty::scene
