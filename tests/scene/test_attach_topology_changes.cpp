// AttachProjectiveConstraint through a topological change of the state it pulls, with SOFA's rule:
// its indices get no topology handler (AttachProjectiveConstraint::init creates none), so each
// keeps naming the point now at its index; a pair left past its state's end acts on nothing, with a
// warning (SOFA HEAD reads and writes past the state's vectors there).
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace penalty {
namespace {

/// A 3 × 2 sheet whose last point (11) is (3, 1) and whose corner (3, 0) is point 3, only in
/// triangle 4 (2, 3, 11); two fixed anchors (a state without solver), (3, 0, -0.05) and (1, 2, 0),
/// pull sheet points `attached` (indices2) towards anchors `anchors` (indices1); triangle 4 is
/// removed at t = 0.03 (point 3 goes with it, point 11 takes its index).
std::string attached_sheet(const std::string& anchors, const std::string& attached) {
    // one file a process: CTest runs this file's tests side by side
    const auto file =
        std::filesystem::temp_directory_path() / ("penalty_attach_changes_" + std::to_string(::getpid()) + ".txt");
    std::ofstream(file) << "T= 0.03\n  REMOVE= 1\n4\n";
    return R"(<Node name="root" gravity="0 0 -9.81" dt="0.01">
  <DefaultAnimationLoop/>
  <Node name="anchors">
    <MechanicalObject name="w" position="3 0 -0.05  1 2 0"/>
  </Node>
  <Node name="sheet">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <TriangleSetTopologyContainer name="surface" position="0 0 0 1 0 0 2 0 0 3 0 0 0 1 0 1 1 0 2 1 0 3 2 0 0 2 0 1 2 0 2 2 0 3 1 0"
      triangles="0 1 5 0 5 4 1 2 6 1 6 5 2 3 11 2 11 6 4 5 9 4 9 8 5 6 10 5 10 9 6 11 7 6 7 10"/>
    <TriangleSetTopologyModifier/>
    <MechanicalObject name="dofs"/>
    <DiagonalMass massDensity="1"/>
    <FixedProjectiveConstraint indices="0 8"/>
    <TriangularFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>
    <AttachProjectiveConstraint object1="@../anchors/w" object2="@dofs" indices1=")" +
           anchors + R"(" indices2=")" + attached + R"("/>
    <TopologicalChangeProcessor filename=")" +
           file.string() + R"("/>
  </Node>
</Node>)";
}

const std::vector<Vec3>& sheet_positions(scene::Scene& s) {
    for (const auto& r : s.states())
        if (r.name == "dofs") return dynamic_cast<const Vec3Object&>(*r.state).position;
    throw std::logic_error("no state 'dofs'");
}

// SOFA HEAD (2a278d8), the same scene and change file, `sofa-head SCENE 20 OUT --every 1`: after
// the removal the pair on index 3 pulls the former point 11, (3, 1), to the anchor (3, 0, -0.05).
// After 10 steps, bit for bit.
TEST(AttachTopologyChanges, AnIndexNamesThePointNowAtItAsSofaHead) {
    auto s = test::build(attached_sheet("0 1", "3 9"));
    for (int k = 0; k < 10; ++k) s->step();
    const std::vector<Vec3>& x = sheet_positions(*s);
    ASSERT_EQ(x.size(), 11U);
    EXPECT_EQ(x[3], Vec3(2.9999918936200274, 0.0078250779181532198, -0.051121146105865933));
    EXPECT_EQ(x[7], Vec3(3.0331068959351088, 1.7079224407831977, -0.062355446781143638));
    EXPECT_EQ(x[9], Vec3(1, 2, 0));
}

TEST(AttachTopologyChanges, APairPastTheStatesEndActsOnNothingWithAWarning) {
    auto s = test::build(attached_sheet("0 0", "3 11"));
    for (int k = 0; k < 3; ++k) s->step();
    const std::vector<Vec3>& x = sheet_positions(*s);
    EXPECT_LT(x[11].y(), 0.2);  // (3, 1) pulled half way to the anchor (3, 0, -0.05) at each step
    testing::internal::CaptureStderr();
    s->step();  // t = 0.03: point 11 takes index 3; index 11 is past the end
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_THAT(err, ::testing::HasSubstr("AttachProjectiveConstraint"));
    EXPECT_THAT(err, ::testing::HasSubstr("1 attached pairs name points past their state's end"));
    ASSERT_EQ(x.size(), 11U);
    for (int k = 0; k < 5; ++k) s->step();
    for (const Vec3& p : x) EXPECT_TRUE(p.allFinite());
}

}  // namespace
}  // namespace penalty
