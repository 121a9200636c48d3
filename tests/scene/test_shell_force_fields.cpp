// The shell force fields of a scene file (src/scene/builder/shell_force_fields.cpp):
// TriangularFEMForceFieldOptim, FastTriangularBendingSprings and QuadBendingFEMForceField built
// with their attributes (the built field's forces equal those of one made with the same
// parameters, bit for bit), their roles, the ignored method's warning and the refusals' exact
// messages naming test.scn:line, the component and the attribute.
#include "penalty/mechanics/triangular_fem_optim.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

/// Node "S": two triangles of the unit square, or with `quads` the square as one quad, and `field`.
std::string shell_scene(const std::string& field, bool quads = false) {
    return R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="S">
    <MechanicalObject position="0 0 0  1 0 0  1 1 0  0 1 0"/>
    <MeshTopology )" +
           std::string(quads ? R"(quads="0 1 2 3")" : R"(triangles="0 1 2  0 2 3")") + R"(/>
)" + field +
           R"(
  </Node>
</Node>)";
}

TEST(ShellForceFields, TheOptimFieldIsBuiltWithItsAttributes) {
    auto s = build(shell_scene(
        R"(    <TriangularFEMForceFieldOptim youngModulus="1000 2000" poissonRatio="0.3" restScale="0.9"/>)"));
    Node* node = s->simulation().root().children().front().get();
    ASSERT_EQ(node->force_fields().size(), 1U);
    auto* built = dynamic_cast<TriangularFEMForceFieldOptim*>(node->force_fields().front().get());
    ASSERT_NE(built, nullptr);
    auto* state = dynamic_cast<Vec3Object*>(s->states().front().state);
    // the same field made here: the rest shape scaled by 0.9 pulls the square in
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}, {0, 2, 3}});
    TriangularFemOptimParameters p;
    p.young_modulus = {1000, 2000};
    p.poisson_ratio = {0.3};
    p.rest_scale = 0.9;
    TriangularFEMForceFieldOptim own(*state, topo, p);
    own.init();
    std::vector<Vec3> f_built(4, Vec3::Zero()), f_own(4, Vec3::Zero());
    const std::vector<Vec3> v(4, Vec3::Zero());
    built->add_force(f_built, state->position, v);
    own.add_force(f_own, state->position, v);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(f_built[i], f_own[i]) << i;
    EXPECT_GT(f_built[2].norm(), 1.0);  // not at rest
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("2 corotational triangles, E = 1000 Pa, nu = 0.3"));
}

TEST(ShellForceFields, RolesOfTheBendingFields) {
    EXPECT_THAT(
        scene::describe_scene(*build(shell_scene(R"(    <FastTriangularBendingSprings bendingStiffness="3"/>)"))),
        HasSubstr("1 bending element across the edges shared by two triangles, stiffness 3"));
    EXPECT_THAT(scene::describe_scene(
                    *build(shell_scene(R"(    <QuadBendingFEMForceField youngModulus="500" thickness="0.1"/>)", true))),
                HasSubstr("1 plate quad, E = 500 Pa, thickness 0.1 m (small displacements)"));
}

TEST(ShellForceFields, AnotherMethodOfTheOptimFieldIsIgnoredWithAWarning) {
    auto s = build(shell_scene(R"(    <TriangularFEMForceFieldOptim method="small"/>)"));
    const std::vector<std::string> warnings = s->warnings();
    EXPECT_THAT(warnings,
                ::testing::Contains(std::string("test.scn:5: TriangularFEMForceFieldOptim: method 'small' ignored: "
                                                "TriangularFEMForceFieldOptim is large-displacement only (as SOFA)")));
}

TEST(ShellForceFields, RefusalsNameTheLineTheComponentAndTheAttribute) {
    EXPECT_EQ(error_of(shell_scene(R"(    <QuadBendingFEMForceField method="large"/>)", true)),

              "test.scn:5: QuadBendingFEMForceField: attribute 'method': only 'small' is implemented (as in SOFA)");
    EXPECT_EQ(error_of(shell_scene(R"(    <QuadBendingFEMForceField/>)")),
              "test.scn:5: QuadBendingFEMForceField: its topology has no quads");
    EXPECT_EQ(error_of(shell_scene(R"(    <QuadBendingFEMForceField thickness="0"/>)", true)),
              "test.scn:5: QuadBendingFEMForceField: attribute 'thickness': must be > 0, found '0'");
    EXPECT_EQ(error_of(shell_scene(R"(    <TriangularFEMForceFieldOptim poissonRatio="0.5"/>)")),
              "test.scn:5: TriangularFEMForceFieldOptim: attribute 'poissonRatio': must be in [0, 0.5), found 0.5");
    EXPECT_EQ(error_of(shell_scene(R"(    <TriangularFEMForceFieldOptim youngModulus="1 0"/>)")),
              "test.scn:5: TriangularFEMForceFieldOptim: attribute 'youngModulus': must be > 0, found 0");
    EXPECT_EQ(error_of(shell_scene(R"(    <TriangularFEMForceFieldOptim restScale="0"/>)")),
              "test.scn:5: TriangularFEMForceFieldOptim: attribute 'restScale': must be > 0, found '0'");
    EXPECT_EQ(error_of(shell_scene(R"(    <FastTriangularBendingSprings bendingStiffness="-1"/>)")),
              "test.scn:5: FastTriangularBendingSprings: attribute 'bendingStiffness': must be >= 0, found '-1'");
}

}  // namespace
