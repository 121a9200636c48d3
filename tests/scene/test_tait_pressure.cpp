// TaitSurfacePressureForceField in a scene (scene/builder/tait_pressure.cpp): the box inflates while
// the injection ramps.
#include "field_and_constraint_scenes.hpp"

namespace {

using namespace penalty;
using namespace penalty::test_field_scenes;
using ::testing::HasSubstr;

TEST(FieldAndConstraintComponents, TaitPressureInflatesItsBoxWhileTheInjectionRamps) {
    // the project's SOFA comparison scene: 0.6 m³ injected at 12 m³/s (dt 0.01: 5 steps) into a
    // 2 m³ box; the quad box under a constant 20 Pa swells against its springs
    auto s = scene::load_scene(penalty::test::source_dir() / "tests/scene/data/tait_pressure.scn");
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("fluid in 12 surface triangles, rest volume 2 m^3"));
    // the balloon, pinned at one corner, swings down while it swells: its diagonal lengthens
    const auto diagonal = [&] { return (vec3_dofs(*s, 0).position[6] - vec3_dofs(*s, 0).position[0]).norm(); };
    const double diagonal0 = diagonal(), box0 = vec3_dofs(*s, 1).position[7].y();
    for (int i = 0; i < 30; ++i) s->step();
    EXPECT_GT(diagonal(), diagonal0 + 0.01) << "the balloon swells";
    EXPECT_GT(vec3_dofs(*s, 1).position[7].y(), box0 + 0.005) << "the box swells";
}

}  // namespace
