// The frame mappings in scenes (scene/builder/frame_mappings.cpp): SkinningMapping and the other
// mappings from rigid frames, built from .scn text.
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

TEST(FrameMappingComponents, DeformableOnRigidFrameMappingCarriesTheBody) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Frame"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject template="Rigid3" name="frame" position="1 2 3 0 0 0.7071067811865476 0.7071067811865476" velocity="0 0 0 0 0 1"/>
    <UniformMass vertexMass="1"/>
    <Node name="Local"><MechanicalObject name="local" position="1 0 0  0 1 0"/><UniformMass vertexMass="1"/>
      <Node name="World"><MechanicalObject name="world"/>
        <DeformableOnRigidFrameMapping input1="@.." input2="@../../frame" output="@world"/>
      </Node>
    </Node>
  </Node>
</Node>)";
    auto s = build(xml);
    const auto* world =
        dynamic_cast<const Vec3Object*>(s->simulation().root().children()[0]->children()[0]->children()[0]->state());
    ASSERT_NE(world, nullptr);
    EXPECT_NEAR((world->position[0] - Vec3(1, 3, 3)).norm(), 0, 1e-15);   // 90° about z, then +(1, 2, 3)
    EXPECT_NEAR((world->velocity[0] - Vec3(-1, 0, 0)).norm(), 0, 1e-15);  // ω × (R·u) = z × y
    EXPECT_THAT(error_of(with(xml, R"( input2="@../../frame")", "")),
                HasSubstr("DeformableOnRigidFrameMapping: attribute 'input2': needs the frames"));
}

TEST(FrameMappingComponents, DistanceFromTargetMappingOntoAVec1State) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="3 4 0  0 0 2"/><UniformMass vertexMass="1"/>
    <Node name="distances"><MechanicalObject template="Vec1" name="d"/>
      <DistanceFromTargetMapping input="@../dofs" output="@d" targetPositions="0 0 0  0 0 0" restLengths="1" GS/>
    </Node>
  </Node>
</Node>)";
    auto s = build(with(xml, "GS", ""));
    const auto* d = dynamic_cast<const Vec1Object*>(s->simulation().root().children()[0]->children()[0]->state());
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->position, (std::vector<double>{4.0, 2.0}));  // |(3,4,0)| − 1, |(0,0,2)| − 0
    // the Vec1d state is recorded; SOFA's regression selection leaves it out (mapped)
    ASSERT_EQ(s->states().size(), 2u);
    EXPECT_EQ(output::select_exported_states(s->states(), false).size(), 1u);
    ASSERT_EQ(output::select_exported_states(s->states(), true).size(), 2u);
    EXPECT_EQ(output::format_positions(*s->states()[1].state), "4 2");
    s->step();
    EXPECT_THAT(
        error_of(with(xml, "GS", R"(geometricStiffness="Sometimes")")),
        HasSubstr("DistanceFromTargetMapping: attribute 'geometricStiffness': expected None, Exact or Stabilized"));
}

TEST(FrameMappingComponents, SkinningMappingFollowsTheFrames) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Frames"><EulerImplicitSolver/><CGLinearSolver iterations="20" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject template="Rigid3" name="frames" position="0 0 0 0 0 0 1  4 0 0 0 0 0 1" velocity="1 0 0 0 0 0  1 0 0 0 0 0"/>
    <UniformMass vertexMass="1"/>
    <Node name="Skin"><MechanicalObject name="skin" position="1 0 0  3 1 0"/>
      <SkinningMapping nbRef="2" WEIGHTS/>
    </Node>
  </Node>
</Node>)";
    auto s = build(with(xml, "WEIGHTS", ""));
    s->step();
    const auto* skin = dynamic_cast<const Vec3Object*>(s->simulation().root().children()[0]->children()[0]->state());
    ASSERT_NE(skin, nullptr);
    // both frames translate by 0.01 in x: every skinned point follows (weights sum to 1)
    EXPECT_NEAR((skin->position[0] - Vec3(1.01, 0, 0)).norm(), 0, 1e-14);
    EXPECT_NEAR((skin->position[1] - Vec3(3.01, 1, 0)).norm(), 0, 1e-14);
    EXPECT_THAT(error_of(with(xml, "WEIGHTS", R"(indices="[0 1] [1]" weight="[0.5 0.5] [1 0]")")),
                HasSubstr("SkinningMapping: attribute 'weight': point 1: one weight per index"));
}

}  // namespace
