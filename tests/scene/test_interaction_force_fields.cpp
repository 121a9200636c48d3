// The interaction force fields in scenes (scene/builder/interaction_force_fields.cpp):
// InteractionEllipsoidForceField, a cloth pushed by an ellipsoid on a Rigid3d frame.
#include "force_field_family_scenes.hpp"
#include "penalty/mechanics/interaction_ellipsoid.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty::test_family_scenes;
using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

TEST(InteractionEllipsoidComponent, PointsRestOnTheSphereAndTheFrameIsOnlyRead) {
    auto s = build(kEllipsoidScene);
    for (int i = 0; i < 300; ++i) s->step();
    const Vec3Object& x = family_state(*s, 1);
    // at rest, k·(1 − |x|) = m·g at the top: |x| = 1 − 0.1·10/100 = 0.99 (the side point slides off)
    EXPECT_NEAR(x.position[0].y(), 0.99, 1e-6);
    EXPECT_NEAR(x.position[0].x(), 0.0, 1e-12);
    EXPECT_LT(x.position[2].y(), 5.0 - 1.0);  // the far point falls freely
    const auto& frame = dynamic_cast<const Rigid3Object&>(*s->states()[0].state);
    EXPECT_EQ(frame.position[0].center, Vec3::Zero());
}

TEST(InteractionEllipsoidComponent, BadAttributesNameTheAttribute) {
    EXPECT_THAT(
        error_of(with_text(kEllipsoidScene, R"(vradius="1 1 1")", R"(vradius="1 0 1")")),
        HasSubstr(
            "test.scn:11: InteractionEllipsoidForceField 'ellipsoid': attribute 'vradius': radii must be non-zero"));
    EXPECT_THAT(
        error_of(with_text(kEllipsoidScene, R"(center="0 0 0")", R"(center="0 0 0 1")")),
        HasSubstr("InteractionEllipsoidForceField 'ellipsoid': attribute 'center': needs 3 numbers per ellipsoid"));
    EXPECT_THAT(error_of(with_text(kEllipsoidScene, R"(object2="@../Obstacle/frame")", R"(object2="@dofs")")),
                HasSubstr("InteractionEllipsoidForceField 'ellipsoid': attribute 'object2': must be a Rigid3d state"));
    EXPECT_THAT(error_of(with_text(kEllipsoidScene, R"(object2_forces="false")", R"(object2_dof_index="2")")),
                HasSubstr("attribute 'object2_dof_index': 2 is out of range (1 frames)"));
    EXPECT_THAT(error_of(with_text(kEllipsoidScene, R"(template="Vec3,Rigid3")", R"(template="Vec3,Vec3")")),
                HasSubstr("InteractionEllipsoidForceField 'ellipsoid': template 'Vec3,Vec3' is not supported"));
}

}  // namespace
