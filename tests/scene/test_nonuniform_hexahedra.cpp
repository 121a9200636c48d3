// NonUniformHexahedronFEMForceFieldAndMass in a scene (scene/builder/nonuniform_hexahedra.cpp): a grid
// with virtual finer levels.
#include "field_and_constraint_scenes.hpp"

namespace {

using namespace penalty;
using namespace penalty::test_field_scenes;
using penalty::test::error_of;
using ::testing::HasSubstr;

TEST(FieldAndConstraintComponents, NonUniformHexahedraOnAGridWithVirtualFinerLevels) {
    // the project's SOFA comparison scene: a box voxelised 4 times finer, condensed back
    auto s = scene::load_scene(penalty::test::source_dir() / "tests/scene/data/nonuniform_hexahedra.scn");
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text, HasSubstr("sparse grid 5 x 3 x 3 (from 2 virtual finer levels)"));
    EXPECT_THAT(text, HasSubstr("condensed from 2 virtual finer levels"));
    for (int i = 0; i < 20; ++i) s->step();
    const Vec3Object& two = vec3_dofs(*s, 0);
    // clamped at x = 0, the free end sags under gravity
    double lowest = 0;
    for (const Vec3& x : two.position) lowest = std::min(lowest, x.y());
    EXPECT_LT(lowest, -1e-3);
    const std::string error = error_of(R"(<Node name="root"><Node name="N"><EulerImplicitSolver/><CGLinearSolver/>
        <RegularGridTopology n="2 2 2" min="0 0 0" max="1 1 1"/><MechanicalObject/>
        <NonUniformHexahedronFEMForceFieldAndMass nbVirtualFinerLevels="1"/></Node></Node>)");
    EXPECT_THAT(error, HasSubstr("needs a SparseGridTopology in its node"));
}

}  // namespace
