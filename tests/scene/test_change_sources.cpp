// The components that change topologies while a scene runs, made from the scene file
// (src/scene/topology/change_sources.cpp): TopologicalChangeProcessor with useDataInputs, its
// lists given or linked to a BoxROI's output (the box selecting on the current positions when the
// list is used), and TopologyBoundingTrasher on a triangle surface, against SOFA HEAD; the
// refusals at build, naming the file, line, component and attribute.
#include "penalty/io/error.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/tetra_cube.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace penalty {
namespace {

using ::testing::HasSubstr;

const Vec3Object& cs_state(const scene::Scene& s) { return dynamic_cast<const Vec3Object&>(*s.states().at(0).state); }

/// The 2×2×2-cell tetrahedral cube (side 0.2 m) hanging from its x = 0 face, and `processor`.
std::string cs_cube(const std::string& processor) {
    return test::fixed_tetra_cube_head("0 -9.81 0") + R"(  )" + processor + "\n</Node></Node>\n";
}

// SOFA HEAD (2a278d8), `sofa-head SCENE 15 OUT --every 1`: useDataInputs with
// tetrahedraToRemove linked to a BoxROI's tetrahedronIndices (box x >= 0.09, y >= -0.01, strict:
// the tetrahedra whose four points are in it, on the sagging body's positions at removal time) and
// timeToRemove 0.05: 27 points after steps 0 to 6, 24 from step 7 on; the positions of every step
// bit for bit (three after step 15 here). With the list "0 4" and timeToRemove 0.02: 27 points
// after steps 0 to 3, 26 from step 4 on (bit for bit too).
TEST(ChangeSources, ProcessorListsGivenOrLinkedToABoxRoiRemoveAtTheirTimeAsSofaHead) {
    auto linked = test::build(cs_cube(R"(<BoxROI name="roi" box="0.09 -0.01 -1 1 1 1" position="@dofs.position"
    tetrahedra="@volume.tetrahedra"/>
  <TopologicalChangeProcessor useDataInputs="1" timeToRemove="0.05" tetrahedraToRemove="@roi.tetrahedronIndices"/>)"));
    std::vector<std::size_t> sizes;
    for (int k = 1; k <= 15; ++k) {
        linked->step();
        sizes.push_back(cs_state(*linked).num_dofs());
    }
    std::vector<std::size_t> expected(15, 24);
    std::fill(expected.begin(), expected.begin() + 6, 27);
    EXPECT_EQ(sizes, expected);
    const Vec3Object& x = cs_state(*linked);
    EXPECT_EQ(x.position[1], Vec3(0.082675720947291531, -0.096539061272694335, 0.0021403725154170643));
    EXPECT_EQ(x.position[5], Vec3(0.19816307497475918, -0.016843517942969934, 0.00064267716753879569));
    EXPECT_EQ(x.position[13], Vec3(0.097741475410170489, 0.0064571743974280605, 0.099707357392831666));
    // a box selecting on the rest positions would have taken the right half, 20 of the 40
    // tetrahedra, and 9 points; its sagging tip is below y = -0.01 at t = 0.05
    EXPECT_GT(linked->topology_container("volume").mesh().tetrahedra().size(), 20u);

    auto listed = test::build(
        cs_cube(R"(<TopologicalChangeProcessor useDataInputs="1" timeToRemove="0.02" tetrahedraToRemove="0 4"/>)"));
    sizes.clear();
    for (int k = 1; k <= 6; ++k) {
        listed->step();
        sizes.push_back(cs_state(*listed).num_dofs());
    }
    EXPECT_EQ(sizes, (std::vector<std::size_t>{27, 27, 27, 26, 26, 26}));
    EXPECT_EQ(listed->topology_container("volume").mesh().tetrahedra().size(), 38u);
}

// SOFA HEAD (2a278d8), `sofa-head SCENE 25 OUT --every 1`: a 4×4 sheet of triangles on the slope
// y = z falling freely through the box's floor y = −0.05; the trasher removes, at each step's
// end, the triangles whose centre is below it, with the points they leave alone
// (removeTriangles(…, true, true)): 25 points after steps 0 to 12, then 24, 24, 20, 20, 20, 20,
// 19, 19, 15, 15, 15, 14, 10 after steps 13 to 25, SOFA HEAD's sizes (its positions bit for bit).
TEST(ChangeSources, ATrasherRemovesTheTrianglesWhoseCentreLeftItsBoxAndTheirLonePointsAsSofaHead) {
    test::TriangleSheet sheet = test::triangle_sheet(4, 0.1);
    for (Vec3& p : sheet.points) p.y() = p.z();
    auto s = test::build(R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><DefaultAnimationLoop/><Node name="sheet">
  <EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-12" threshold="1e-12"/>
  <TriangleSetTopologyContainer name="surface" position=")" +
                         test::points_text(sheet.points) + R"(" triangles=")" + test::elements_text(sheet.triangles) +
                         R"("/>
  <TriangleSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="1"/>
  <TopologyBoundingTrasher position="@dofs.position" box="-1 -0.05 -1 1 1 1"/>
</Node></Node>)");
    std::vector<std::size_t> sizes;
    for (int k = 1; k <= 25; ++k) {
        s->step();
        sizes.push_back(cs_state(*s).num_dofs());
    }
    std::vector<std::size_t> expected(12, 25);
    for (const std::size_t n : {24, 24, 20, 20, 20, 20, 19, 19, 15, 15, 15, 14, 10}) expected.push_back(n);
    EXPECT_EQ(sizes, expected);
    // every triangle left has its centre in the box; the mesh has no point without a triangle
    const MeshTopology& m = s->topology_container("surface").mesh();
    std::vector<int> used(m.num_points(), 0);
    for (const Triangle& t : m.triangles()) {
        double centre = 0;
        for (const PointId p : t) {
            centre += cs_state(*s).position[std::size_t(p)].y() / 3;
            used[std::size_t(p)] = 1;
        }
        EXPECT_GE(centre, -0.05);
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
}

TEST(ChangeSources, WhatCannotChangeOrIsMalformedIsRefusedAtBuild) {
    const test::TetraCube cube = test::tetra_cube(1, 1.0);
    const auto body = [&](const std::string& container, const std::string& components) {
        return R"(<Node name="root"><Node name="body"><)" + container + R"( name="volume" position=")" +
               test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) +
               R"("/><TetrahedronSetTopologyModifier/><MechanicalObject name="dofs"/><UniformMass totalMass="1"/>)" +
               components + "</Node></Node>";
    };
    // no modifier, so no topology that can change
    EXPECT_THAT(
        test::error_of(R"(<Node name="root"><Node name="body"><MeshTopology position=")" +
                       test::points_text(cube.points) + R"(" tetrahedra=")" + test::elements_text(cube.tetrahedra) +
                       R"("/><MechanicalObject/><TopologyBoundingTrasher box="-1 -1 -1 1 1 1"/></Node></Node>)"),
        HasSubstr("test.scn:1: TopologyBoundingTrasher: needs a topology that can change: a "
                  "...SetTopologyContainer with a ...SetTopologyModifier in its node (or a `topology` link to "
                  "one)"));
    const std::string tetra = "TetrahedronSetTopologyContainer";
    EXPECT_THAT(test::error_of(body(tetra, R"(<TopologicalChangeProcessor/>)")),
                HasSubstr("TopologicalChangeProcessor: attribute 'filename': names the file of topological changes "
                          "(or set useDataInputs)"));
    EXPECT_THAT(test::error_of(body(tetra, R"(<TopologicalChangeProcessor filename="no_such_changes.txt"/>)")),
                HasSubstr("TopologicalChangeProcessor: attribute 'filename': cannot open no_such_changes.txt"));
    EXPECT_THAT(
        test::error_of(body(tetra, R"(<TopologyBoundingTrasher box="0 0 0 1 1"/>)")),
        HasSubstr("TopologyBoundingTrasher: attribute 'box': expected 6 numbers: xmin ymin zmin xmax ymax zmax"));
    EXPECT_THAT(
        test::error_of(body(tetra, R"(<TopologyBoundingTrasher position="@volume.position" box="0 0 0 1 1 1"/>)")),
        HasSubstr("TopologyBoundingTrasher: attribute 'position': must link to a MechanicalObject's position"));
    // a blocked topology: the source is refused naming what blocks it
    EXPECT_THAT(test::error_of(body(tetra, R"(<PlaneForceField name="floor"/>
      <TopologicalChangeProcessor useDataInputs="1" tetrahedraToRemove="0"/>)")),
                HasSubstr("TopologicalChangeProcessor: topology '/body/volume' cannot change: PlaneForceField 'floor' "
                          "(test.scn:1) does not follow topological changes"));
    // a list linked to what is not a BoxROI's output, or to a BoxROI without explicit boxes
    EXPECT_THAT(
        test::error_of(body(tetra, R"(<TopologicalChangeProcessor useDataInputs="1"
      tetrahedraToRemove="@dofs.position"/>)")),
        HasSubstr("TopologicalChangeProcessor: attribute 'tetrahedraToRemove': a link must name a BoxROI's "
                  "indices, edgeIndices, triangleIndices, quadIndices, tetrahedronIndices or hexahedronIndices"));
    EXPECT_THAT(test::error_of(body(tetra, R"(<BoxROI name="roi" orientedBox="0 0 0  1 0 0  1 1 0  1"/>
      <TopologicalChangeProcessor useDataInputs="1" tetrahedraToRemove="@roi.tetrahedronIndices"/>)")),
                HasSubstr("BoxROI 'roi': attribute 'box': penalty follows a BoxROI's output over time only with "
                          "explicit boxes"));
}

}  // namespace
}  // namespace penalty
