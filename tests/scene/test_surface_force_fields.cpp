// The scene components of triangle surfaces: TriangularFEMForceField and TriangularBendingSprings
// built from a .scn on a MeshTopology, described, and run.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using namespace penalty;
using ::testing::HasSubstr;

/// A 3×3-vertex cloth [0, 2]² in the x-z plane, 8 triangles, fixed at two corners, with the
/// given force fields (XML) in its node.
std::string surface_cloth_scene(const std::string& force_fields) {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
      <Node name="Cloth"><EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
        <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
        <MeshTopology name="topo" position="0 0 0  1 0 0  2 0 0  0 0 1  1 0 1  2 0 1  0 0 2  1 0 2  2 0 2"
            triangles="0 1 4  0 4 3  1 2 4  2 5 4  3 4 6  4 7 6  4 5 8  4 8 7"/>
        <MechanicalObject name="cloth"/>
        <UniformMass vertexMass="0.1"/>
        <FixedConstraint indices="0 2"/>
        )" +
           force_fields + R"(
      </Node>
    </Node>)";
}

using penalty::test::build;

/// Lowest y of the cloth after `steps` steps (all positions checked finite).
double surface_sag_after(scene::Scene& s, int steps) {
    for (int i = 0; i < steps; ++i) s.step();
    const auto& cloth = dynamic_cast<const Vec3Object&>(*s.states()[0].state);
    double lowest = 0;
    for (const Vec3& p : cloth.position) {
        EXPECT_TRUE(p.allFinite());
        lowest = std::min(lowest, p.y());
    }
    EXPECT_EQ(cloth.position[0], Vec3(0, 0, 0));  // fixed
    return lowest;
}

TEST(SurfaceComponents, TriangularFemAndBendingSpringsBuildDescribeAndRun) {
    auto s = build(surface_cloth_scene(
        R"(<TriangularFEMForceField name="fem" youngModulus="500" poissonRatio="0.3" method="large"/>
        <TriangularBendingSprings name="bend" stiffness="300" damping="1"/>)"));
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text, HasSubstr("8 triangles, E = 500 Pa, nu = 0.3, co-rotational (large)"));
    // shared edges: the 8 edges at the centre vertex 4 (every other edge is on the border)
    EXPECT_THAT(text, HasSubstr("8 bending springs across the edges shared by two triangles"));
    const double stiff = surface_sag_after(*s, 100);
    auto free_fall = build(surface_cloth_scene(""));
    const double loose = surface_sag_after(*free_fall, 100);
    EXPECT_LT(loose, -0.4);         // nothing holds the free vertices: ½ g t² ≈ 4.9 m, damped
    EXPECT_GT(stiff, 0.5 * loose);  // the membrane and the springs hold the cloth up
    EXPECT_LT(stiff, -1e-3);        // it still sags under gravity
}

TEST(SurfaceComponents, SmallMethodDefaultsAndErrors) {
    auto s = build(surface_cloth_scene(R"(<TriangularFEMForceField method="small"/><TriangularBendingSprings/>)"));
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text, HasSubstr("8 triangles, E = 5000 Pa, nu = 0.45, linear (small)"));  // SOFA's defaults
    (void)surface_sag_after(*s, 10);
    EXPECT_THROW(build(surface_cloth_scene(R"(<TriangularFEMForceField method="polar"/>)")), io::SceneError);
    EXPECT_THROW(build(surface_cloth_scene(R"(<TriangularFEMForceField poissonRatio="0.5"/>)")), io::SceneError);
    EXPECT_THROW(build(surface_cloth_scene(R"(<TriangularBendingSprings stiffness="-1"/>)")), io::SceneError);
}

TEST(SurfaceComponents, OlderTriangleFemReadsThicknessAndPlaneStrain) {
    auto s = build(surface_cloth_scene(
        R"(<TriangleFEMForceField youngModulus="500" poissonRatio="0.3" thickness="0.5" planeStrain="1"/>)"));
    const std::string text = scene::describe_scene(*s);
    EXPECT_THAT(text,
                HasSubstr("8 triangles, E = 500 Pa, nu = 0.3, co-rotational (large), thickness 0.5 m, plane strain"));
    const double sag = surface_sag_after(*s, 50);
    EXPECT_LT(sag, -1e-3);
    EXPECT_GT(sag, -2.0);
    EXPECT_THROW(build(surface_cloth_scene(R"(<TriangleFEMForceField thickness="0"/>)")), io::SceneError);
}

}  // namespace
