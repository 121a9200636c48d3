// ClusteringEngine → ShapeMatching → PositionBasedDynamicsProjectiveConstraint wired through Data
// links as SOFA's ShapeMatching.scn does, on a scene made here: after a step the body is the best
// rigid fit of the solver's positions (distances kept, centroid where the solver put it); bad
// links and attributes are errors naming the component and attribute.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty;
using ::testing::HasSubstr;

std::string shape_matching_scene(const std::string& clustering, const std::string& matching,
                                 const std::string& constraint) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-20" threshold="1e-20"/>
    <MeshTopology name="topo" position="0 0 0  1 0 0  0 1 0  1 1 0  0 0 1  1 0 1  0 1 1  1 1 1"
                  edges="0 1  1 3  3 2  2 0  4 5  5 7  7 6  6 4  0 4  1 5  2 6  3 7"/>
    <MechanicalObject name="dofs" position="@topo.position"/>
    <UniformMass vertexMass="1"/>
    <ConstantForceField indices="0" forces="100 0 0"/>
    )" + clustering +
           "\n    " + matching + "\n    " + constraint + R"(
  </Node>
</Node>)";
}

const std::string kClustering =
    R"(<ClusteringEngine name="clustering" radius="10" number="1" position="@topo.position"/>)";
const std::string kMatching =
    R"(<ShapeMatching template="Vec3" name="sm" position="@dofs.position" cluster="@clustering.cluster"/>)";
const std::string kConstraint =
    R"(<PositionBasedDynamicsProjectiveConstraint stiffness="1" position="@sm.targetPosition"/>)";

TEST(ShapeMatchingComponents, AStepEndsOnTheRigidFitOfTheSolversPositions) {
    auto s = penalty::test::build(shape_matching_scene(kClustering, kMatching, kConstraint));
    const auto& x = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    const std::vector<Vec3> rest = x.position;
    s->step();
    // the solver's step (no stiffness): v = dt·(g + f/m), x = x0 + dt·v, with f = (100, 0, 0) on
    // point 0 only; the rigid fit keeps the centroid: c = c0 + dt²·(g + (100/8, 0, 0))
    Vec3 c0 = Vec3::Zero(), c = Vec3::Zero();
    for (std::size_t i = 0; i < 8; ++i) {
        c0 += rest[i] / 8.0;
        c += x.position[i] / 8.0;
    }
    EXPECT_NEAR((c - (c0 + 0.0001 * Vec3(12.5, -10, 0))).norm(), 0, 1e-12);
    for (std::size_t i = 0; i < 8; ++i)
        for (std::size_t j = i + 1; j < 8; ++j)
            EXPECT_NEAR((x.position[i] - x.position[j]).norm(), (rest[i] - rest[j]).norm(), 1e-12) << i << " " << j;
    // point 0 alone was pushed (0.01 m by the solver): the fit shares its motion with the others
    EXPECT_LT(x.position[0].x() - rest[0].x(), 0.009);
    // velocities: the projected motion over dt
    for (std::size_t i = 0; i < 8; ++i)
        EXPECT_NEAR((x.velocity[i] - (x.position[i] - rest[i]) / 0.01).norm(), 0, 1e-9) << i;
}

TEST(ShapeMatchingComponents, WithoutATemplateShapeMatchingIsSofasInertRigid3dOne) {
    // SOFA's factory picks ShapeMatching<Rigid3d> (an empty doUpdate): no targets, no projection
    auto s = penalty::test::build(shape_matching_scene(
        kClustering, R"(<ShapeMatching name="sm" position="@dofs.position" cluster="@clustering.cluster"/>)",
        kConstraint));
    bool noted = false;
    for (const std::string& w : s->warnings()) noted = noted || w.find("SOFA makes Rigid3d") != std::string::npos;
    EXPECT_TRUE(noted);
    const auto& x = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    s->step();
    // the solver's step alone: point 0 gets dt²·(g + f/m), the others dt²·g
    EXPECT_NEAR((x.position[0] - Vec3(0.01, -0.001, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((x.position[7] - Vec3(1, 0.999, 1)).norm(), 0, 1e-12);
}

TEST(ShapeMatchingComponents, BadLinksAndAttributesNameTheComponent) {
    using penalty::test::error_of;
    EXPECT_THAT(
        error_of(shape_matching_scene(
            kClustering, R"(<ShapeMatching template="Vec3" name="sm" position="@dofs.position"/>)", kConstraint)),
        AllOf(HasSubstr("ShapeMatching"), HasSubstr("cluster")));
    EXPECT_THAT(error_of(shape_matching_scene(
                    kClustering,
                    R"(<ShapeMatching template="Vec3" name="sm" position="@dofs.position" cluster="@topo.edges"/>)",
                    kConstraint)),
                AllOf(HasSubstr("cluster"), HasSubstr("ClusteringEngine")));
    EXPECT_THAT(
        error_of(shape_matching_scene(R"(<ClusteringEngine name="clustering" number="-3" position="@topo.position"/>)",
                                      kMatching, kConstraint)),
        AllOf(HasSubstr("ClusteringEngine"), HasSubstr("number")));
    EXPECT_THAT(error_of(shape_matching_scene(
                    kClustering, kMatching, R"(<PositionBasedDynamicsProjectiveConstraint position="0 0 0  1 1 1"/>)")),
                AllOf(HasSubstr("PositionBasedDynamicsProjectiveConstraint"), HasSubstr("2 targets for a state of 8")));
    EXPECT_THAT(
        error_of(shape_matching_scene(R"(<ClusteringEngine name="clustering" radius="-1" position="@topo.position"/>)",
                                      kMatching, kConstraint)),
        AllOf(HasSubstr("ClusteringEngine"), HasSubstr("radius")));
}

}  // namespace
