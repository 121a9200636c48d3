#pragma once
// Scenes written in a test as .scn text ("test.scn"): built, or the SceneError they raise.
#include "penalty/io/error.hpp"
#include "penalty/io/scene_file.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace penalty::test {

/// The scene of `xml`, built with `options` (data files resolve against the working directory).
inline std::unique_ptr<scene::Scene> build(const std::string& xml, const scene::BuildOptions& options = {}) {
    return scene::build_scene(io::parse_scene_string(xml, "test.scn"), options);
}

/// The message of the SceneError that building `xml` raises (fails the test when none is raised).
inline std::string error_of(const std::string& xml) {
    try {
        (void)build(xml);
    } catch (const io::SceneError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no SceneError for:\n" << xml;
    return {};
}

/// The message of the E that running `s` with `options` raises, or "no error".
template <class E>
std::string run_error(scene::Scene& s, const scene::RunOptions& options) {
    try {
        (void)scene::run_scene(s, options);
    } catch (const E& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace penalty::test
