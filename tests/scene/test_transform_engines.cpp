// The transform engines in scenes (scene/builder/transform_engines.cpp): TransformEngine,
// TransformPosition and MergePoints built from .scn text, their outputs linked into states.
#include "engine_and_mapping_scenes.hpp"
#include "penalty/io/error.hpp"
#include "penalty/mechanics/frame_mappings.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/output/state_record.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty::test_engine_scenes;
using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

TEST(DataEngineComponents, TransformEngineFeedsAStateScaledRotatedTranslated) {
    auto s = build(with(
        kEngineScene, "ENGINE",
        R"(<TransformEngine name="engine" input_position="0 0 0  1 0 0  0 2 0" scale="2 1 1" rotation="0 0 90" translation="5 0 0"/>)"));
    const Vec3Object& x = engine_state(*s);
    ASSERT_EQ(x.position.size(), 3u);
    EXPECT_NEAR((x.position[1] - Vec3(5, 2, 0)).norm(), 0, 1e-15);  // (1,0,0) → (2,0,0) → (0,2,0) → +5 x
    EXPECT_NEAR((x.position[2] - Vec3(3, 0, 0)).norm(), 0, 1e-15);
    EXPECT_EQ(x.position[0], Vec3(5, 0, 0));
}

TEST(DataEngineComponents, AnEngineAfterItsReaderIsBuiltWhenRead) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="@merge.points"/>
    <UniformMass vertexMass="1"/>
    <MergePoints name="merge" position1="0 0 0  1 1 1" position2="7 7 7"/>
  </Node>
</Node>)";
    auto s = build(xml);
    const Vec3Object& x = engine_state(*s);
    ASSERT_EQ(x.position.size(), 3u);
    EXPECT_EQ(x.position[2], Vec3(7, 7, 7));
}

TEST(DataEngineComponents, TransformPositionMethodsAndErrors) {
    auto s = build(with(
        kEngineScene, "ENGINE",
        R"(<TransformPosition name="engine" method="translation" translation="0 0 3" input_position="1 2 3  4 5 6" fixedIndices="1"/>)"));
    EXPECT_EQ(engine_state(*s).position[0], Vec3(1, 2, 6));
    EXPECT_EQ(engine_state(*s).position[1], Vec3(4, 5, 6));
    const std::string bad = error_of(
        with(kEngineScene, "ENGINE", R"(<TransformPosition name="engine" method="warp" input_position="1 2 3"/>)"));
    EXPECT_THAT(bad, HasSubstr("test.scn:3: TransformPosition 'engine': attribute 'method': unknown method 'warp'"));
    const std::string file = error_of(
        with(kEngineScene, "ENGINE",
             R"(<TransformPosition name="engine" method="fromFile" filename="no_such.tfm" input_position="1 2 3"/>)"));
    EXPECT_THAT(file, HasSubstr("TransformPosition 'engine': attribute 'filename'"));
    const std::string rigid = error_of(
        with(kEngineScene, "ENGINE", R"(<TransformEngine name="engine" template="Rigid3" input_position="1 2 3"/>)"));
    EXPECT_THAT(rigid, HasSubstr("TransformEngine 'engine': template 'Rigid3' is not supported"));
}

}  // namespace
