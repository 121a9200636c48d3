// DiagonalMass and BoxROI built from scene files, and links to BoxROI's indices.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/diagonal_mass.hpp"
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

// A 3×3×3 grid of unit cells' corners (2×2×2 hexahedra of volume 1), points i + 3j + 9k.
const std::string kGrid = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Grid"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology nx="3" ny="3" nz="3" xmin="0" xmax="2" ymin="0" ymax="2" zmin="0" zmax="2"/>
    <MechanicalObject name="grid"/>
    MASS
    <BoxROI name="box" box="-0.1 -0.1 -0.1 2.1 0.1 2.1  1.9 1.9 1.9 2.1 2.1 2.1" drawBoxes="1"/>
    <FixedProjectiveConstraint indices="@box.indices"/>
  </Node>
</Node>)";

std::string grid_with(const std::string& mass) {
    std::string xml = kGrid;
    xml.replace(xml.find("MASS"), 4, mass);
    return xml;
}

TEST(MassAndRegionComponents, DiagonalMassLumpsTheGridsHexahedra) {
    auto s = build(grid_with(R"(<DiagonalMass massDensity="2"/>)"));
    const auto* mass = dynamic_cast<const DiagonalMass*>(s->states()[0].mass);
    ASSERT_NE(mass, nullptr);
    EXPECT_EQ(mass->element_kind(), LumpedElementKind::hexahedron);
    // 2·1/8 per hexahedron and vertex: a corner has 1 hexahedron, an edge middle 2, a face
    // centre 4, the centre 8.
    EXPECT_NEAR(mass->vertex_masses()[0], 0.25, 1e-15);
    EXPECT_NEAR(mass->vertex_masses()[1], 0.5, 1e-15);
    EXPECT_NEAR(mass->vertex_masses()[4], 1.0, 1e-15);
    EXPECT_NEAR(mass->vertex_masses()[13], 2.0, 1e-15);
    EXPECT_NEAR(mass->total_mass(), 16.0, 1e-13);
}

TEST(MassAndRegionComponents, FixedConstraintReadsTheBoxIndices) {
    auto s = build(grid_with(R"(<DiagonalMass totalMass="8"/>)"));
    const auto* mass = dynamic_cast<const DiagonalMass*>(s->states()[0].mass);
    ASSERT_NE(mass, nullptr);
    EXPECT_NEAR(mass->vertex_masses()[13], 1.0, 1e-15);
    const auto& grid = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    const std::vector<Vec3> before = grid.position;
    s->step();
    // Fixed: the bottom layer y = 0 (j = 0) and the corner (2, 2, 2); every other point falls.
    for (int i = 0; i < 27; ++i) {
        const bool fixed = (i / 3) % 3 == 0 || i == 26;
        if (fixed) EXPECT_EQ(grid.position[i], before[i]) << i;
        else EXPECT_LT(grid.position[i].y(), before[i].y()) << i;
    }
}

TEST(MassAndRegionComponents, UnsupportedDataAndLinksAreRefusedClearly) {
    EXPECT_THAT(error_of(grid_with(R"(<DiagonalMass massDensity="-1"/>)")), HasSubstr("massDensity"));
    std::string oriented = grid_with("");
    oriented.replace(oriented.find("drawBoxes"), 9, "orientedBox=\"0 0 0 1 0 0 0 1 0\" drawBoxes");
    EXPECT_THAT(error_of(oriented), HasSubstr("attribute 'orientedBox': expected 10 numbers per box"));
    std::string not_recorded = grid_with("<UniformMass totalMass=\"1\"/>");
    not_recorded.replace(not_recorded.find("@box.indices"), 12, "@box.pointsInROI");
    EXPECT_THAT(error_of(not_recorded), HasSubstr("pointsInROI"));
}

TEST(MassAndRegionComponents, FixedPlaneKeepsTheSelectedPointsInTheirPlaneAndBoxConstraintIsIgnored) {
    std::string xml = grid_with(R"(<DiagonalMass massDensity="1"/>
      <FixedPlaneProjectiveConstraint direction="0 1 0" dmin="-0.5" dmax="0.5"/>
      <BoxConstraint box="-1 -1 -1 3 3 3"/>)");
    xml.replace(xml.find("<FixedProjectiveConstraint"), 51, "");
    auto s = build(xml);
    EXPECT_EQ(scene::component_category("BoxConstraint"), scene::ComponentCategory::ignored);
    const auto& grid = dynamic_cast<const Vec3Object&>(*s->states()[0].state);
    const std::vector<Vec3> before = grid.position;
    for (int step = 0; step < 3; ++step) s->step();
    // The bottom layer (y = 0, inside -0.5 < y < 0.5) gets no response along y; the rest falls
    // (BoxConstraint, unknown to SOFA, fixes nothing).
    for (int i = 0; i < 27; ++i) {
        if ((i / 3) % 3 == 0) EXPECT_EQ(grid.position[i].y(), before[i].y()) << i;
        else EXPECT_LT(grid.position[i].y(), before[i].y()) << i;
    }
}

}  // namespace
