// The scene components of src/scene/builder/bending_springs.cpp (QuadularBendingSprings,
// TriangleBendingSprings, QuadBendingSprings, SpringForceField with explicit springs,
// TriangularTensorMassForceField) built from scenes made here: the springs built are SOFA's
// (same list as the mechanics functions), the defaults are SOFA's, bad input is refused, and the
// scenes run.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/bending_spring_lists.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/triangular_biquadratic_springs.hpp"
#include "penalty/mechanics/triangular_quadratic_springs.hpp"
#include "penalty/mechanics/triangular_tensor_mass.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/node.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using ::testing::HasSubstr;

constexpr const char* kGridPoints = "0 0 0  1 0 0  2 0 0  0 0 1  1 0 1  2 0 1  0 0 2  1 0 2  2 0 2";

/// A 3×3-vertex cloth [0, 2]² in the x-z plane as 4 quads (or 8 triangles), fixed at two
/// corners, with the given force fields (XML) in its node.
std::string cloth_scene(const std::string& force_fields, bool quads = true) {
    const std::string elements = quads ? R"(quads="0 1 4 3  1 2 5 4  3 4 7 6  4 5 8 7")"
                                       : R"(triangles="0 1 4  0 4 3  1 2 4  2 5 4  3 4 6  4 7 6  4 5 8  4 8 7")";
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
      <Node name="Cloth"><EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
        <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
        <MeshTopology name="topo" position=")" +
           std::string(kGridPoints) + "\" " + elements + R"(/>
        <MechanicalObject name="cloth"/>
        <UniformMass vertexMass="0.1"/>
        <FixedConstraint indices="0 2"/>
        )" +
           force_fields + R"(
      </Node>
    </Node>)";
}

using penalty::test::build;

/// The force fields of the cloth node.
const std::vector<std::unique_ptr<BaseForceField>>& cloth_force_fields(scene::Scene& s) {
    return s.simulation().root().children().at(0)->force_fields();
}

/// Lowest y of the cloth after `steps` steps (all positions finite, fixed corner still).
double sag_after(scene::Scene& s, int steps) {
    for (int i = 0; i < steps; ++i) s.step();
    const auto& cloth = dynamic_cast<const Vec3Object&>(*s.states()[0].state);
    double lowest = 0;
    for (const Vec3& p : cloth.position) {
        EXPECT_TRUE(p.allFinite());
        lowest = std::min(lowest, p.y());
    }
    EXPECT_EQ(cloth.position[0], Vec3(0, 0, 0));
    return lowest;
}

std::vector<Vec3> grid() {
    return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1),
            Vec3(2, 0, 1), Vec3(0, 0, 2), Vec3(1, 0, 2), Vec3(2, 0, 2)};
}

MeshTopology grid_quads() {
    MeshTopology t;
    t.set_quads({{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}});
    return t;
}

void expect_same_springs(const std::vector<Spring>& built, const std::vector<Spring>& expected) {
    ASSERT_EQ(built.size(), expected.size());
    for (std::size_t i = 0; i < built.size(); ++i) {
        EXPECT_EQ(built[i].a, expected[i].a) << i;
        EXPECT_EQ(built[i].b, expected[i].b) << i;
        EXPECT_EQ(built[i].ks, expected[i].ks) << i;
        EXPECT_EQ(built[i].kd, expected[i].kd) << i;
        EXPECT_EQ(built[i].rest_length, expected[i].rest_length) << i;
    }
}

TEST(BendingSpringComponents, QuadularBendingSpringsBuildSofasSpringsAndRun) {
    auto s = build(cloth_scene(R"(<QuadularBendingSprings name="bend" stiffness="3000" damping="1"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("8 bending springs (two across each edge shared by two quads)"));
    const auto& ff = dynamic_cast<const SpringForceField&>(*cloth_force_fields(*s).at(0));
    expect_same_springs(ff.springs(), quadular_bending_springs(grid_quads(), grid(), 3000.0, 1.0));
    // defaults: QuadularBendingSprings' stiffness 100000, damping 1
    auto d = build(cloth_scene("<QuadularBendingSprings/>"));
    const auto& fd = dynamic_cast<const SpringForceField&>(*cloth_force_fields(*d).at(0));
    EXPECT_EQ(fd.springs().at(0).ks, 100000.0);
    EXPECT_EQ(fd.springs().at(0).kd, 1.0);
    // the springs only resist bending across the shared edges: the cloth still falls, finite
    EXPECT_LT(sag_after(*s, 50), -1e-3);
    EXPECT_THROW(build(cloth_scene(R"(<QuadularBendingSprings stiffness="-1"/>)")), io::SceneError);
}

TEST(BendingSpringComponents, TriangleAndQuadBendingSpringsReadTheFirstStiffness) {
    auto t = build(cloth_scene(R"(<TriangleBendingSprings stiffness="100 7" damping="0.1"/>)"));
    EXPECT_THAT(scene::describe_scene(*t),
                HasSubstr("bending springs between the opposite vertices of faces sharing an edge"));
    const auto& tf = dynamic_cast<const SpringForceField&>(*cloth_force_fields(*t).at(0));
    expect_same_springs(tf.springs(), triangle_bending_springs(grid_quads(), grid(), 100.0, 0.1));
    EXPECT_EQ(tf.springs().size(), 8u);  // one across each quad's split diagonal, one across each of the 4 shared edges
    auto q = build(cloth_scene(R"(<QuadBendingSprings stiffness="20" damping="0"/>)"));
    EXPECT_THAT(scene::describe_scene(*q), HasSubstr("6 bending springs across the edges shared by two quads"));
    const auto& qf = dynamic_cast<const SpringForceField&>(*cloth_force_fields(*q).at(0));
    expect_same_springs(qf.springs(), quad_bending_springs(grid_quads(), grid(), 20.0, 0.0));
    // SpringForceField's defaults (100 N/m, 5 N·s/m) and localRange
    auto defaults = build(cloth_scene(R"(<QuadBendingSprings localRange="3 -1"/>)"));
    const auto& df = dynamic_cast<const SpringForceField&>(*cloth_force_fields(*defaults).at(0));
    expect_same_springs(df.springs(), quad_bending_springs(grid_quads(), grid(), 100.0, 5.0, {.first = 3, .last = -1}));
    EXPECT_LT(sag_after(*q, 20), -1e-3);
    EXPECT_LT(sag_after(*t, 20), -1e-3);
    EXPECT_THROW(build(cloth_scene(R"(<QuadBendingSprings localRange="1"/>)")), io::SceneError);
    // ends that are not ints are the attribute's error, never a conversion out of range
    for (const char* range : {"0 1e19", "-1e10 2", "0.5 2", "2147483648 3"}) {
        try {
            (void)build(cloth_scene("<QuadBendingSprings localRange=\"" + std::string(range) + "\"/>"));
            ADD_FAILURE() << range << " was accepted";
        } catch (const io::SceneError& e) {
            EXPECT_THAT(
                e.what(),
                HasSubstr(
                    "QuadBendingSprings: attribute 'localRange': expected integers from -2147483648 to 2147483647"))
                << range;
        }
    }
    EXPECT_THROW(build(cloth_scene(R"(<TriangleBendingSprings stiffness="-5"/>)")), io::SceneError);
}

TEST(BendingSpringComponents, SpringForceFieldTakesExplicitListsOrIndexLists) {
    auto s = build(cloth_scene(R"(<SpringForceField name="FF" spring="4 8 50 0.5 1.2   1 5 60 0 0.9"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("2 springs (explicit list)"));
    const auto& ff = dynamic_cast<const SpringForceField&>(*cloth_force_fields(*s).at(0));
    expect_same_springs(ff.springs(), {{.a = 4, .b = 8, .ks = 50, .kd = 0.5, .rest_length = 1.2},
                                       {.a = 1, .b = 5, .ks = 60, .kd = 0, .rest_length = 0.9}});
    // indices1/indices2: lengths, stiffness and damping resized by repeating their last value
    auto i =
        build(cloth_scene(R"(<SpringForceField indices1="0 1 2" indices2="3 4 5" lengths="1 2" stiffness="10"/>)"));
    const auto& fi = dynamic_cast<const SpringForceField&>(*cloth_force_fields(*i).at(0));
    expect_same_springs(fi.springs(), {{.a = 0, .b = 3, .ks = 10, .kd = 5, .rest_length = 1},
                                       {.a = 1, .b = 4, .ks = 10, .kd = 5, .rest_length = 2},
                                       {.a = 2, .b = 5, .ks = 10, .kd = 5, .rest_length = 2}});
    // no springs (SOFA's examples write <SpringForceField name="FF"/>): builds, does nothing
    auto empty = build(cloth_scene(R"(<SpringForceField name="FF" object1="@cloth" object2="@cloth"/>)"));
    EXPECT_TRUE(dynamic_cast<const SpringForceField&>(*cloth_force_fields(*empty).at(0)).springs().empty());
    EXPECT_LT(sag_after(*s, 20), -1e-3);
    EXPECT_THROW(build(cloth_scene(R"(<SpringForceField spring="0 1 10 0"/>)")), io::SceneError);
    EXPECT_THROW(build(cloth_scene(R"(<SpringForceField spring="0 12 10 0 1"/>)")), io::SceneError);  // out of range
    EXPECT_THROW(build(cloth_scene(R"(<SpringForceField indices1="0 1" indices2="3"/>)")), io::SceneError);
    EXPECT_THROW(build(cloth_scene(R"(<SpringForceField spring="0 1 10 0 1" enabled="0"/>)")), io::SceneError);
    EXPECT_THROW(build(cloth_scene(R"(<SpringForceField spring="0 1 10 0 1" object2="@topo"/>)")), io::SceneError);
}

TEST(BendingSpringComponents, TriangularTensorMassDefaultsAndRun) {
    auto s = build(
        cloth_scene(R"(<TriangularTensorMassForceField name="TM" youngModulus="15" poissonRatio="0.3"/>)", false));
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text, HasSubstr("E = 15 Pa, nu = 0.3 (linear, from the rest positions)"));
    const auto& ff = dynamic_cast<const TriangularTensorMassForceField&>(*cloth_force_fields(*s).at(0));
    EXPECT_EQ(ff.edge_tensors().size(), 16u);  // the 16 edges of the 8 triangles
    auto d = build(cloth_scene("<TriangularTensorMassForceField/>", false));
    const auto& fd = dynamic_cast<const TriangularTensorMassForceField&>(*cloth_force_fields(*d).at(0));
    EXPECT_DOUBLE_EQ(fd.mu(), 1000.0 * 0.7 / 0.91);  // SOFA's defaults E = 1000, nu = 0.3
    const double stiff = sag_after(*s, 100);
    auto free_fall = build(cloth_scene("", false));
    const double loose = sag_after(*free_fall, 100);
    EXPECT_GT(stiff, 0.5 * loose);  // the membrane holds the cloth up
    EXPECT_LT(stiff, -1e-3);
    EXPECT_THROW(build(cloth_scene(R"(<TriangularTensorMassForceField poissonRatio="1"/>)", false)), io::SceneError);
}

TEST(BendingSpringComponents, TriangularSpringMembranesDefaultsAndRun) {
    auto bq = build(cloth_scene(
        R"(<TriangularBiquadraticSpringsForceField name="BQS" youngModulus="500" poissonRatio="0.3" useAngularSprings="1" dampingRatio="0"/>)",
        false));
    EXPECT_THAT(
        scene::describe_scene(*bq),
        HasSubstr(
            "16 edge springs on squared lengths, E = 500 Pa, nu = 0.3, angular springs, area term under compression"));
    auto q = build(cloth_scene(
        R"(<TriangularQuadraticSpringsForceField name="QS" youngModulus="500" poissonRatio="0.3"/>)", false));
    EXPECT_THAT(scene::describe_scene(*q),
                HasSubstr("16 edge springs on lengths, E = 500 Pa, nu = 0.3, angular springs"));
    // SOFA's defaults: E = 1000, nu = 0.3, angular springs, compressible
    auto d =
        build(cloth_scene("<TriangularBiquadraticSpringsForceField/><TriangularQuadraticSpringsForceField/>", false));
    const auto& bd = dynamic_cast<const TriangularBiquadraticSpringsForceField&>(*cloth_force_fields(*d).at(0));
    const auto& qd = dynamic_cast<const TriangularQuadraticSpringsForceField&>(*cloth_force_fields(*d).at(1));
    EXPECT_DOUBLE_EQ(bd.mu(), 1000.0 * 0.7 / 0.91);
    EXPECT_DOUBLE_EQ(qd.lambda(), 1000.0 * 0.3 / 0.91);
    EXPECT_THAT(scene::describe_scene(*d),
                HasSubstr("E = 1000 Pa, nu = 0.3, angular springs, area term under compression"));
    auto free_fall = build(cloth_scene("", false));
    const double loose = sag_after(*free_fall, 100);
    for (scene::Scene* s : {bq.get(), q.get()}) {
        const double sag = sag_after(*s, 100);
        EXPECT_GT(sag, 0.5 * loose);  // the membrane holds the cloth up
        EXPECT_LT(sag, -1e-3);
    }
    EXPECT_THROW(build(cloth_scene(R"(<TriangularQuadraticSpringsForceField poissonRatio="-1"/>)", false)),
                 io::SceneError);
    EXPECT_THROW(build(cloth_scene(R"(<TriangularBiquadraticSpringsForceField youngModulus="-2"/>)", false)),
                 io::SceneError);
}

}  // namespace
