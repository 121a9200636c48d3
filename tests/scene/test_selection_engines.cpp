// The selection engines in scenes (scene/builder/selection_engines.cpp): MeshROI, ProximityROI and
// ValuesFromPositions built from .scn text.
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

TEST(SelectionEngineComponents, MeshRoiSelectsThePointsInsideTheMesh) {
    auto s = build(with(kMeshRoi, "ATTR", ""));
    EXPECT_THAT(s->role(*s->file().root->children[0]->components[4]), HasSubstr("selects 2 of 4 points"));
    const std::string plain = with(kMeshRoi, "ATTR", "");
    EXPECT_THAT(error_of(with(plain, R"(ROIposition="0 0 0 1 0 0)", R"(ROIposition="0 0 0 1 0)")),
                HasSubstr("test.scn:5: MeshROI 'roi': attribute 'ROIposition': expected a multiple of 3 numbers"));
    const std::string outside = error_of(with(plain, R"(ROItriangles="0 2 3)", R"(ROItriangles="0 2 30)"));
    EXPECT_THAT(outside, HasSubstr("test.scn:5: MeshROI 'roi': ROI triangle 0 uses point 30"));
}

TEST(SelectionEngineComponents, ProximityRoiKeepsTheNearestPointsAndRefusesANegativeCount) {
    const std::string xml = R"(<Node name="root" dt="0.01" gravity="0 -1 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 0 0  0.1 0 0  0.2 0 0  0.3 0 0  3 0 0"/>
    <UniformMass vertexMass="1"/>
    <ProximityROI name="roi" centers="0 0 0" radii="1" N="2"/>
    <FixedProjectiveConstraint indices="@roi.indices"/>
  </Node>
</Node>)";
    auto s = build(xml);
    s->step();
    const Vec3Object& x = engine_state(*s);
    EXPECT_EQ(x.position[0], Vec3(0, 0, 0));  // the two nearest are fixed
    EXPECT_EQ(x.position[1], Vec3(0.1, 0, 0));
    EXPECT_LT(x.position[2].y(), 0.0);  // the others fall
    EXPECT_THAT(error_of(with(xml, R"(N="2")", R"(N="-2")")),
                HasSubstr("test.scn:5: ProximityROI 'roi': attribute 'N': must be >= 0"));
}

}  // namespace
