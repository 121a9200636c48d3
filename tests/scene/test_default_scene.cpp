// The built-in scene (scene/default_scene.cpp) runs and makes contacts.
#include "builder_scenes.hpp"
#include "penalty/io/error.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using namespace penalty::test_builder_scenes;

TEST(SceneBuilder, BuiltInSceneRunsAndMakesContacts) {
    auto s = build_scene(io::parse_scene_string(scene::default_scene_xml(), "<built-in scene>"));
    ASSERT_EQ(s->states().size(), 3u);
    scene::RunOptions run;
    run.steps = 200;
    std::size_t max_pairs = 0;
    const auto summary = scene::run_scene(*s, run, [&](std::int64_t, std::int64_t, const scene::RunSummary&) {
        max_pairs = std::max(max_pairs, s->contacts().size());
    });
    EXPECT_GE(summary.max_contacts, 25u);  // the cube's 25 bottom points on the floor
    EXPECT_EQ(max_pairs, 2u);              // floor–cube points, then ball–cube points too
    EXPECT_LT(summary.max_penetration, 0.1);
}

}  // namespace
