// HexahedralFEMForceField, the …FEMForceFieldAndMass components and SubsetTopology built from
// scene files made here.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/hexahedral_fem.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

const Vec3Object& vec3_state(const scene::Scene& s, std::size_t i) {
    return dynamic_cast<const Vec3Object&>(*s.states().at(i).state);
}

// A cantilever of 2×2×4 unit cubes along z, clamped at z = 0 (points 0..8), under gravity.
std::string cantilever(const std::string& fem) {
    return R"(<Node name="root" dt="0.02" gravity="0 -10 0">
  <Node name="Beam"><EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="200" tolerance="1e-14" threshold="1e-14"/>
    <MechanicalObject name="dofs"/>
    <RegularGridTopology nx="3" ny="3" nz="5" xmin="0" xmax="2" ymin="0" ymax="2" zmin="0" zmax="4"/>
    <FixedProjectiveConstraint indices="0 1 2 3 4 5 6 7 8"/>
    )" + fem +
           R"(
  </Node>
</Node>)";
}

std::vector<Vec3> run(scene::Scene& s, int steps) {
    for (int i = 0; i < steps; ++i) s.step();
    return vec3_state(s, 0).position;
}

TEST(HexahedraComponents, FemAndMassVariantsAgreeOnCubes) {
    // On cubes the two stiffness formulas agree (to float rounding) and the masses are the same:
    // the two components give the same motion.
    auto hexahedral =
        build(cantilever(R"(<HexahedralFEMForceFieldAndMass youngModulus="2000" poissonRatio="0.3" density="2"/>)"));
    auto hexahedron =
        build(cantilever(R"(<HexahedronFEMForceFieldAndMass youngModulus="2000" poissonRatio="0.3" density="2"/>)"));
    const auto* mass = dynamic_cast<const HexahedronElementMass*>(hexahedral->states()[0].mass);
    ASSERT_NE(mass, nullptr);
    EXPECT_DOUBLE_EQ(mass->total_mass(), 2.0 * 16.0);  // ρ·V
    EXPECT_EQ(mass->element_weights().size(), 16u);
    const std::vector<Vec3> a = run(*hexahedral, 20);
    const std::vector<Vec3> b = run(*hexahedron, 20);
    ASSERT_EQ(a.size(), 45u);
    const Vec3 tip0(2, 2, 4);
    EXPECT_LT(a[44].y() - tip0.y(), -1e-3);  // the free end falls
    for (std::size_t i = 0; i < 9; ++i) EXPECT_EQ(a[i], vec3_state(*hexahedral, 0).rest_position[i]);  // clamped
    double diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i) diff = std::max(diff, (a[i] - b[i]).norm());
    EXPECT_LT(diff, 1e-6);
}

TEST(HexahedraComponents, HexahedralFemWithADiagonalMassFalls) {
    auto s = build(cantilever(R"(<HexahedralFEMForceField youngModulus="2000" poissonRatio="0.3" method="polar"/>
    <DiagonalMass massDensity="2"/>)"));
    const std::vector<Vec3> x = run(*s, 10);
    EXPECT_LT(x[44].y() - 2.0, -1e-4);
    for (const Vec3& p : x) EXPECT_TRUE(p.allFinite());
}

TEST(HexahedraComponents, RefusesUnsupportedMethodsAndTopologies) {
    EXPECT_THAT(error_of(cantilever(R"(<HexahedralFEMForceField method="small"/>)")), HasSubstr("large or polar"));
    EXPECT_THAT(error_of(cantilever(R"(<HexahedronFEMForceFieldAndMass method="polar"/>)")),
                HasSubstr("large or small"));
    EXPECT_THAT(error_of(R"(<Node name="root"><Node name="A"><MechanicalObject position="0 0 0 1 0 0 0 1 0"/>
      <MeshTopology triangles="0 1 2"/><HexahedralFEMForceField/></Node></Node>)"),
                HasSubstr("hexahedra"));
}

// A 4×3 sheet of points z = 0 (point i + 4j at (i, j, 0)), 2 triangles per cell, split by a
// SubsetTopology at x = 1.5 into two bodies, each with its own topology (local indices).
const std::string kSheet = R"(<Node name="root" dt="0.01" gravity="0 0 -10">
  <Node name="Sheet"><EulerImplicitSolver/><CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <MeshTopology name="mesh" position="0 0 0 1 0 0 2 0 0 3 0 0  0 1 0 1 1 0 2 1 0 3 1 0  0 2 0 1 2 0 2 2 0 3 2 0"
        triangles="0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 4 5 9 4 9 8 5 6 10 5 10 9 6 7 11 6 11 10"/>
    <SubsetTopology name="subset" box="1.5 -1 -1 3 3 1" rest_position="@mesh.position" triangles="@mesh.triangles"
        LOCAL/>
    <Node name="In">
      <MechanicalObject name="in" position="POINTS_IN"/>
      <TriangleSetTopologyContainer name="t" triangles="@../subset.trianglesInROI"/>
      <DiagonalMass massDensity="1"/>
      <FixedProjectiveConstraint indices="0 1 2"/>
    </Node>
    <Node name="Out">
      <MechanicalObject name="out" position="POINTS_OUT"/>
      <TriangleSetTopologyContainer name="t" triangles="@../subset.trianglesOutROI"/>
      <DiagonalMass massDensity="1"/>
    </Node>
  </Node>
</Node>)";

std::string sheet(bool local) {
    std::string xml = kSheet;
    xml.replace(xml.find("LOCAL"), 5, local ? R"(localIndices="1")" : "");
    xml.replace(xml.find("POINTS_IN"), 9, local ? "@../subset.pointsInROI" : "@../mesh.position");
    xml.replace(xml.find("POINTS_OUT"), 10, local ? "@../subset.pointsOutROI" : "@../mesh.position");
    return xml;
}

TEST(SubsetTopologyComponent, SplitsASheetIntoTwoBodiesWithLocalIndices) {
    auto s = build(sheet(true));
    ASSERT_EQ(s->states().size(), 2u);
    const Vec3Object& in = vec3_state(*s, 0);
    const Vec3Object& out = vec3_state(*s, 1);
    ASSERT_EQ(in.position.size(), 6u);   // border 2, 6, 10 then 3, 7, 11
    ASSERT_EQ(out.position.size(), 9u);  // border 2, 6, 10 then 0, 1, 4, 5, 8, 9
    EXPECT_EQ(in.position[3], Vec3(3, 0, 0));
    EXPECT_EQ(out.position[3], Vec3(0, 0, 0));
    // DiagonalMass lumps each body's own triangles: areas 2 (in) and 4 (out)
    EXPECT_NEAR(s->states()[0].mass->total_mass(), 2.0, 1e-12);
    EXPECT_NEAR(s->states()[1].mass->total_mass(), 4.0, 1e-12);
    run(*s, 3);
    // the border points (local 0, 1, 2) are fixed in the inside body; the rest falls
    EXPECT_EQ(vec3_state(*s, 0).position[2], Vec3(2, 2, 0));
    EXPECT_LT(vec3_state(*s, 0).position[3].z(), -1e-4);
    EXPECT_LT(vec3_state(*s, 1).position[0].z(), -1e-4);
}

TEST(SubsetTopologyComponent, GlobalIndicesKeepTheWholePointSet) {
    auto s = build(sheet(false));
    const Vec3Object& in = vec3_state(*s, 0);
    ASSERT_EQ(in.position.size(), 12u);
    // only the vertices of the inside triangles carry mass: x = 2 and x = 3, area 2
    EXPECT_NEAR(s->states()[0].mass->total_mass(), 2.0, 1e-12);
    EXPECT_NEAR(s->states()[1].mass->total_mass(), 4.0, 1e-12);
}

TEST(SubsetTopologyComponent, ATopologyMayLinkToItsNodesStateBuiltAfterIt) {
    // SOFA's SubsetTopology.scn: the container's `position` links to the MechanicalObject of its
    // node, which penalty builds after the topology; the state's own `position` data (here a link
    // to the sheet's points) gives the points.
    auto s = build(R"(<Node name="root" dt="0.01" gravity="0 0 -10">
  <Node name="Sheet"><EulerImplicitSolver/><CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <MeshTopology name="mesh" position="0 0 0 1 0 0 0 1 0 1 1 0" triangles="0 1 3 0 3 2"/>
    <Node name="Body">
      <MechanicalObject name="dofs" position="@../mesh.position"/>
      <TriangleSetTopologyContainer name="t" position="@dofs.position" triangles="@../mesh.triangles"/>
      <DiagonalMass massDensity="3"/>
    </Node>
  </Node>
</Node>)");
    ASSERT_EQ(vec3_state(*s, 0).position.size(), 4u);
    EXPECT_NEAR(s->states()[0].mass->total_mass(), 3.0, 1e-12);
}

TEST(HexahedraComponents, SparseGridCellsWeighStiffnessAndMassAlike) {
    // HexahedronFEMForceFieldAndMass on a SparseGridTopology (a unit cube surface voxelised in
    // 4³ cells): SOFA's getMassCoef equals getStiffnessCoef (0.5 for boundary cells,
    // fillWeighted) and scales the element matrices and the particle masses.
    const auto dir = std::filesystem::temp_directory_path() /
                     ("penalty_hexa_sparse_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "cube.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
                                       "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::ofstream(dir / "scene.scn") << R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <Node name="Cube"><EulerImplicitSolver/><CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <SparseGridTopology fileTopology="cube.obj" n="5 5 5"/>
    <MechanicalObject name="grid"/>
    <HexahedronFEMForceFieldAndMass youngModulus="1000" poissonRatio="0.3" density="2"/>
  </Node>
</Node>)";
    auto s = scene::build_scene(io::parse_scene_file(dir / "scene.scn"));
    std::filesystem::remove_all(dir);
    const Node& cube = *s->simulation().root().children().at(0);
    const auto* ff = dynamic_cast<const HexahedronFEMForceField*>(cube.force_fields().at(0).get());
    const auto* mass = dynamic_cast<const HexahedronElementMass*>(s->states().at(0).mass);
    ASSERT_NE(ff, nullptr);
    ASSERT_NE(mass, nullptr);
    const std::vector<double>& c = ff->stiffness_factors();
    ASSERT_EQ(c.size(), 64u);
    ASSERT_EQ(mass->element_weights().size(), 64u);
    const double cell = std::pow(1.02 / 4, 3);  // the box [-0.01, 1.01]³ in 4³ cells
    double expected_total = 0;
    for (std::size_t e = 0; e < c.size(); ++e) {
        EXPECT_NEAR(mass->element_weights()[e], c[e] * 2.0 * cell * 8.0 / 27.0, 1e-14) << e;
        expected_total += c[e] * 2.0 * cell;
    }
    EXPECT_NEAR(mass->total_mass(), expected_total, 1e-12);
    EXPECT_EQ(std::count(c.begin(), c.end(), 0.5), 56);  // the outer shell: boundary cells
    EXPECT_EQ(std::count(c.begin(), c.end(), 1.0), 8);
}

}  // namespace
