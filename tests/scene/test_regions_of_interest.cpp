// BoxROI in scenes (scene/builder/regions_of_interest.cpp): an oriented box selects the points inside;
// a position link that finds nothing selects nothing.
#include "field_and_constraint_scenes.hpp"

namespace {

using namespace penalty;
using namespace penalty::test_field_scenes;
using penalty::test::build;
using ::testing::HasSubstr;

TEST(FieldAndConstraintComponents, BoxRoiOrientedBoxSelectsThePointsInside) {
    // an oriented box spanning (1,0,0)–(3,0,0)–(3,1,0), depth 1: points with 1 ≤ x ≤ 3,
    // 0 ≤ y ≤ 1, |z| ≤ 0.5; no `box`: the default box is not added
    auto s = build(particles("0 0 0  2 0.5 0  2 0.5 0.7  2.9 0.9 -0.4  5 0 0",
                             R"(<BoxROI name="roi" orientedBox="1 0 0  3 0 0  3 1 0  1"/>
                                <FixedProjectiveConstraint indices="@roi.indices"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("selects 2 of 5 points"));
}

TEST(FieldAndConstraintComponents, BoxRoiPositionLinkThatFindsNothingSelectsNothing) {
    auto s = build(particles("0 0 0  0.5 0.5 0.5", R"(<BoxROI name="roi" position="@../Volume.position"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("selects 0 of 0 points"));
    bool warned = false;
    for (const std::string& w : s->warnings()) warned = warned || w.find("finds nothing") != std::string::npos;
    EXPECT_TRUE(warned);
}

}  // namespace
