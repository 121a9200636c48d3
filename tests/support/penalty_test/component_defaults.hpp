#pragma once
/// @file
/// The component registry's declared defaults, read back by the tests that compare them with the
/// library's own.

#include "penalty/scene/components.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <string_view>

namespace penalty::test {

/// `type`.`attribute`'s declared default as a number (the test fails when the type or the
/// attribute is not declared).
inline double default_number(std::string_view type, std::string_view attribute) {
    const scene::ComponentSpec* spec = scene::find_component(type);
    EXPECT_NE(spec, nullptr) << type;
    const scene::AttributeSpec* a = spec != nullptr ? scene::find_attribute(*spec, attribute) : nullptr;
    EXPECT_NE(a, nullptr) << type << "." << attribute;
    return a != nullptr ? std::stod(std::string(a->default_value)) : std::nan("");
}

}  // namespace penalty::test
