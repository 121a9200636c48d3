// TrianglePressureForceField, QuadPressureForceField, EdgePressureForceField, SurfacePressureForceField, PlaneROI and
// SphereROI built from scenes made here, and the element outputs of BoxROI they read.
#include "penalty/io/error.hpp"
#include "penalty/scene/components.hpp"
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

const Vec3Object& state_of(const scene::Scene& s, std::size_t i = 0) {
    return dynamic_cast<const Vec3Object&>(*s.states()[i].state);
}

std::string replaced(std::string xml, const std::string& what, const std::string& with) {
    xml.replace(xml.find(what), what.size(), with);
    return xml;
}

// A 2 m × 1 m plate in z = 0 (points 0..5 on a 3×2 grid, spacing 1 m), four triangles of ½ m²;
// each point has 0.5 kg, no gravity, dt = 0.1 s. The box holds x ≤ 1.1 (points 0, 1, 3, 4):
// triangles 0 and 1.
const std::string kPlate = R"(<Node name="root" dt="0.1" gravity="0 0 0">
  <Node name="Plate"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="50" tolerance="1e-14" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 0 0  1 0 0  2 0 0  0 1 0  1 1 0  2 1 0"/>
    <TriangleSetTopologyContainer name="surface" triangles="0 1 4  0 4 3  1 2 5  1 5 4"/>
    <UniformMass vertexMass="0.5"/>
    <BoxROI name="box" box="-0.1 -0.1 -0.1 1.1 1.1 0.1"/>
    LOAD
  </Node>
</Node>)";

TEST(PressureComponents, TrianglePressureOnTheBoxTrianglesPushesTheirCornersByPressureTimesArea) {
    auto s = build(replaced(kPlate, "LOAD",
                            R"(<TrianglePressureForceField triangleList="@box.triangleIndices" pressure="0 0 6"/>)"));
    s->step();
    const Vec3Object& x = state_of(*s);
    // triangle 0 (0,1,4) and 1 (0,4,3): 6 N/m² · ½ m² = 3 N each, 1 N per corner; Δv = h·f/m
    // (K = 0, no damping) = 0.1·f/0.5 and Δx = h·Δv
    const double per_corner = 1.0;
    const std::vector<double> corners = {2, 1, 0, 1, 2, 0};  // triangles touching each point
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_NEAR(x.velocity[i].z(), 0.1 * corners[i] * per_corner / 0.5, 1e-12) << i;
        EXPECT_NEAR(x.position[i].z(), 0.1 * 0.1 * corners[i] * per_corner / 0.5, 1e-12) << i;
        EXPECT_EQ(x.velocity[i].x(), 0.0);
    }
}

TEST(PressureComponents, BoxRoiElementsFollowStrictOrTheCentre) {
    // strict = 0: a triangle is in when its centre is: triangle 3 (1,5,4) has x̄ = 4/3 > 1.1, out;
    // with the box up to x = 1.4 it is in (centre), but not strictly (point 5 at x = 2)
    auto centre = build(
        replaced(replaced(kPlate, "LOAD",
                          R"(<TrianglePressureForceField triangleList="@box.triangleIndices" pressure="0 0 6"/>)"),
                 R"(box="-0.1 -0.1 -0.1 1.1 1.1 0.1")", R"(box="-0.1 -0.1 -0.1 1.4 1.1 0.1" strict="0")"));
    centre->step();
    // triangles 0, 1, 3: point 5 is a corner of triangle 3 only
    EXPECT_NEAR(state_of(*centre).velocity[5].z(), 0.1 * 1.0 / 0.5, 1e-12);
    EXPECT_NEAR(state_of(*centre).velocity[2].z(), 0.0, 1e-15);
    auto strict = build(
        replaced(replaced(kPlate, "LOAD",
                          R"(<TrianglePressureForceField triangleList="@box.triangleIndices" pressure="0 0 6"/>)"),
                 R"(box="-0.1 -0.1 -0.1 1.1 1.1 0.1")", R"(box="-0.1 -0.1 -0.1 1.4 1.1 0.1")"));
    strict->step();
    EXPECT_EQ(state_of(*strict).velocity[5].z(), 0.0);
}

TEST(PressureComponents, TrianglePressureInAChildNodeActsOnTheParentsState) {
    // SOFA's pattern: the loaded surface is a child node with a topology and no state
    auto s = build(replaced(kPlate, "LOAD", R"(<Node name="Load">
        <TriangleSetTopologyContainer name="loaded" triangles="1 2 5"/>
        <TrianglePressureForceField triangleList="0" pressure="3 0 0"/>
      </Node>)"));
    s->step();
    const Vec3Object& x = state_of(*s);
    // ½ m² · 3 N/m² = 1.5 N, 0.5 N per corner on points 1, 2, 5
    for (std::size_t i : {1, 2, 5}) EXPECT_NEAR(x.velocity[i].x(), 0.1 * 0.5 / 0.5, 1e-12) << i;
    for (std::size_t i : {0, 3, 4}) EXPECT_EQ(x.velocity[i].x(), 0.0) << i;
}

TEST(PressureComponents, UnknownTriangleIndicesAttributeLoadsNothingAsSofa) {
    // SOFA's TrianglePressureForceField has no `triangleIndices`: its list stays empty
    auto s = build(replaced(
        kPlate, "LOAD", R"(<TrianglePressureForceField triangleIndices="@box.triangleIndices" pressure="0 0 6"/>)"));
    s->step();
    for (const Vec3& v : state_of(*s).velocity) EXPECT_EQ(v, Vec3::Zero());
    EXPECT_THAT(
        error_of(replaced(kPlate, "LOAD", R"(<TrianglePressureForceField triangleList="7" pressure="0 0 6"/>)")),
        HasSubstr("triangle index 7"));
}

TEST(PressureComponents, EdgePressureOnTheEdgesOfALinkedList) {
    // the plate's container edges (derived from the triangles), loaded by 0.2 N/m along −z
    auto s = build(replaced(kPlate, "LOAD", R"(<Node name="Edges">
        <EdgeSetTopologyContainer name="lines" edges="0 1  1 2"/>
        <EdgePressureForceField edges="@lines.edges" pressure="0 0 -0.2" normal="0 0 1" p_intensity="1"/>
      </Node>)"));
    s->step();
    const Vec3Object& x = state_of(*s);
    // two 1 m edges: 0.1 N per end; point 1 is the end of both
    EXPECT_NEAR(x.velocity[0].z(), -0.1 * 0.1 / 0.5, 1e-12);
    EXPECT_NEAR(x.velocity[1].z(), -0.1 * 0.2 / 0.5, 1e-12);
    EXPECT_NEAR(x.velocity[2].z(), -0.1 * 0.1 / 0.5, 1e-12);
    EXPECT_EQ(x.velocity[3].z(), 0.0);
    EXPECT_THAT(error_of(replaced(kPlate, "LOAD", R"(<EdgePressureForceField edgeIndices="0" pressure="0 0 0"/>)")),
                HasSubstr("zero pressure"));
}

TEST(PressureComponents, EdgePressureSelectsTheEdgesBetweenTwoPlanes) {
    // dmin < y < dmax: the edges with both ends at y = 1 (points 3, 4, 5): (4,3) and (5,4)
    auto s = build(
        replaced(kPlate, "LOAD", R"(<EdgePressureForceField pressure="0 0 1" normal="0 1 0" dmin="0.5" dmax="1.5"/>)"));
    s->step();
    const Vec3Object& x = state_of(*s);
    EXPECT_NEAR(x.velocity[3].z(), 0.1 * 0.5 / 0.5, 1e-12);
    EXPECT_NEAR(x.velocity[4].z(), 0.1 * 1.0 / 0.5, 1e-12);
    EXPECT_NEAR(x.velocity[5].z(), 0.1 * 0.5 / 0.5, 1e-12);
    EXPECT_EQ(x.velocity[0].z(), 0.0);
}

// The plate as two unit quads (0 1 4 3) and (1 2 5 4).
std::string quad_plate(const std::string& load) {
    return replaced(
        replaced(kPlate, R"(<TriangleSetTopologyContainer name="surface" triangles="0 1 4  0 4 3  1 2 5  1 5 4"/>)",
                 R"(<QuadSetTopologyContainer name="surface" quads="0 1 4 3  1 2 5 4"/>)"),
        "LOAD", load);
}

TEST(PressureComponents, QuadPressureOnAListedQuadPushesItsCornersByAQuarterOfPressureTimesArea) {
    auto s = build(quad_plate(R"(<QuadPressureForceField quadList="1" pressure="0 0 8"/>)"));
    s->step();
    const Vec3Object& x = state_of(*s);
    // quad 1 (1 2 5 4): 8 N/m² · 1 m² = 8 N, 2 N per corner; Δv = h·f/m = 0.1·2/0.5
    const std::vector<double> share = {0, 2, 2, 0, 2, 2};
    for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(x.velocity[i].z(), 0.1 * share[i] / 0.5, 1e-12) << i;
}

TEST(PressureComponents, QuadPressureSelectsBetweenPlanesAndReadsTheFirstPointsOfLinkedQuads) {
    // dmin < x < dmax: points 1, 2, 4, 5 (x in 1..2): quad 1
    auto planes =
        build(quad_plate(R"(<QuadPressureForceField pressure="0 0 8" normal="1 0 0" dmin="0.5" dmax="2.5"/>)"));
    planes->step();
    EXPECT_NEAR(state_of(*planes).velocity[2].z(), 0.1 * 2 / 0.5, 1e-12);
    EXPECT_EQ(state_of(*planes).velocity[0].z(), 0.0);
    // quadList linked to BoxROI's quadsInROI (alias quadInROI): SOFA's BaseData::genericCopyValueFrom
    // copies the FIRST POINT of each quad, then read as a quad index. Quads listed right then left:
    // the left box selects quad 1 (0 1 4 3), whose first point 0 names quad 0, the right one.
    const std::string swapped = R"(<QuadSetTopologyContainer name="surface" quads="1 2 5 4  0 1 4 3"/>)";
    const auto left_box = [&](const std::string& data) {
        return replaced(quad_plate(R"(<BoxROI name="left" box="-0.1 -0.1 -0.1 1.1 1.1 0.1"/>
            <QuadPressureForceField quadList="@left.)" +
                                   data + R"(" pressure="0 0 8"/>)"),
                        R"(<QuadSetTopologyContainer name="surface" quads="0 1 4 3  1 2 5 4"/>)", swapped);
    };
    for (const char* data : {"quadInROI", "quadsInROI"}) {
        auto linked = build(left_box(data));
        linked->step();
        EXPECT_NEAR(state_of(*linked).velocity[2].z(), 0.1 * 2 / 0.5, 1e-12) << data;  // the right quad
        EXPECT_EQ(state_of(*linked).velocity[3].z(), 0.0) << data;
    }
    auto indices = build(left_box("quadIndices"));  // the selected quad itself
    indices->step();
    EXPECT_NEAR(state_of(*indices).velocity[3].z(), 0.1 * 2 / 0.5, 1e-12);
    EXPECT_EQ(state_of(*indices).velocity[2].z(), 0.0);
}

TEST(PressureComponents, AStateReadsTheParentGridsPointsThroughALink) {
    // SofaPython3's advanced_timer.py: position="@../grid.position", the grid in the parent node
    // (GridTopology::computePointList at its init: x fastest, then y, then z)
    auto s = build(R"(<Node name="root" gravity="0 0 0">
      <RegularGridTopology name="grid" min="0 0 0" max="2 1 1" n="3 2 2"/>
      <Node name="meca"><MechanicalObject name="mo" position="@../grid.position"/></Node>
    </Node>)");
    const Vec3Object& x = state_of(*s);
    ASSERT_EQ(x.position.size(), 12u);
    EXPECT_EQ(x.position[1], Vec3(1, 0, 0));
    EXPECT_EQ(x.position[3], Vec3(0, 1, 0));
    EXPECT_EQ(x.position[11], Vec3(2, 1, 1));
}

// A closed tetrahedron surface, faces wound outward, 1 kg per point.
const std::string kBalloon = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Balloon"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="100" tolerance="1e-16" threshold="1e-30"/>
    <MechanicalObject position="0 0 0  1 0 0  0 1 0  0 0 1"/>
    <MeshTopology triangles="0 2 1  0 1 3  0 3 2  1 2 3"/>
    <UniformMass vertexMass="1"/>
    <SurfacePressureForceField PRESSURE/>
  </Node>
</Node>)";

TEST(PressureComponents, SurfacePressureInflatesAClosedSurfaceWithNoNetForce) {
    auto s = build(replaced(kBalloon, "PRESSURE", R"(pressure="6")"));
    s->step();
    const Vec3Object& x = state_of(*s);
    Vec3 momentum = Vec3::Zero();
    for (const Vec3& v : x.velocity) momentum += v;
    EXPECT_LT(momentum.norm(), 1e-12);
    // the slanted face's corner 1 moves out along +x (its faces' forces: (1,1,1) + (0,−1,0)
    // + (0,0,−1) from faces 3, 1, 0), the origin moves toward −(1,1,1)
    EXPECT_GT(x.velocity[1].x(), 0.0);
    EXPECT_LT(x.velocity[0].x(), 0.0);
    EXPECT_LT(x.velocity[0].y(), 0.0);
}

TEST(PressureComponents, SurfacePressurePulseStartsAtSpeedTimesDt) {
    // 6 Pa at 300 Pa/s and dt 0.01: 3 Pa at step 1, 6 at step 2, then back: 3 at step 3
    auto pulsed = build(replaced(kBalloon, "PRESSURE", R"(pressure="6" pulseMode="1" pressureSpeed="300")"));
    auto constant = build(replaced(kBalloon, "PRESSURE", R"(pressure="3")"));
    pulsed->step();
    constant->step();
    // the same first step as a constant 3 Pa (the stiffness scales with p too)
    for (std::size_t i = 0; i < 4; ++i)
        EXPECT_TRUE(state_of(*pulsed).velocity[i].isApprox(state_of(*constant).velocity[i], 1e-12)) << i;
}

// A 3×3×3 grid (spacing 1), gravity −y; points fixed by an ROI do not fall.
const std::string kPlaneRoiGrid = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Grid"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology nx="3" ny="3" nz="3" xmin="0" xmax="2" ymin="0" ymax="2" zmin="0" zmax="2"/>
    <MechanicalObject name="grid"/>
    <UniformMass totalMass="27"/>
    ROI
    <FixedProjectiveConstraint indices="@roi.indices"/>
  </Node>
</Node>)";

std::vector<int> fixed_points(const std::string& roi, const std::string& output = "indices") {
    auto s = build(replaced(replaced(kPlaneRoiGrid, "ROI", roi), "@roi.indices", "@roi." + output));
    const std::vector<Vec3> before = state_of(*s).position;
    s->step();
    std::vector<int> fixed;
    for (std::size_t i = 0; i < before.size(); ++i)
        if (state_of(*s).position[i] == before[i]) fixed.push_back(int(i));
    return fixed;
}

TEST(PressureComponents, PlaneRoiAndSphereRoiIndicesFixPoints) {
    // the plane box on (0,0,0) → (2,0,0) → (2,0,2), depth 0.2: the layer y = 0 (i + 9k)
    EXPECT_EQ(fixed_points(R"(<PlaneROI name="roi" plane="0 0 0  2 0 0  2 0 2  0.2" drawBoxes="1"/>)"),
              (std::vector<int>{0, 1, 2, 9, 10, 11, 18, 19, 20}));
    // two balls of radius 1 (one radius for both): around (0,0,0) and (2,2,2)
    EXPECT_EQ(fixed_points(R"(<SphereROI name="roi" centers="0 0 0  2 2 2" radii="1" drawSphere="1"/>)"),
              (std::vector<int>{0, 1, 3, 9, 17, 23, 25, 26}));
    // pointIndices is SphereROI's alias of indices
    EXPECT_EQ(fixed_points(R"(<SphereROI name="roi" centers="2 2 2" radii="0.5"/>)", "pointIndices"),
              (std::vector<int>{26}));
    EXPECT_THAT(error_of(replaced(kPlaneRoiGrid, "ROI", R"(<PlaneROI name="roi" plane="0 0 0 1 0 0"/>)")),
                HasSubstr("10 numbers per plane"));
}

TEST(PressureComponents, PlaneRoiTrianglesAndTetrahedraNeedAllTheirPointsInOneBox) {
    // a tetrahedron pair sharing the face (0,1,2) in z = 0; the box holds z ∈ [−0.1, 0.1]
    const std::string xml = R"(<Node name="root" dt="0.1" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-14" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 0 0  1 0 0  0 1 0  0 0 1  0 0 -1"/>
    <TetrahedronSetTopologyContainer name="volume" tetrahedra="0 1 2 3  0 2 1 4"/>
    <UniformMass vertexMass="1"/>
    <PlaneROI name="roi" plane="-1 -1 0  2 -1 0  2 2 0  0.2" tetrahedra="@volume.tetrahedra"/>
    <TrianglePressureForceField triangleList="@roi.triangleIndices" pressure="0 0 3"/>
  </Node>
</Node>)";
    auto s = build(xml);
    s->step();
    // the container's triangles: only the shared face (0,1,2) lies in z = 0 (area ½): ½ N per corner
    const Vec3Object& x = state_of(*s);
    for (std::size_t i : {0, 1, 2}) EXPECT_NEAR(x.velocity[i].z(), 0.1 * 0.5, 1e-12) << i;
    for (std::size_t i : {3, 4}) EXPECT_EQ(x.velocity[i].z(), 0.0) << i;
}

}  // namespace
