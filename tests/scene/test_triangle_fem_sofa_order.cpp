// TriangleFEMForceField in SOFA's operation order (triangle_fem_sofa_order.cpp: the element
// frames, strain-displacement, strain, stress and forces as TriangleFEMForceField computes them):
// a 1 × 1 sheet of eight triangles, its x = 0 side fixed, sagging out of its plane (method
// large) and stretched in its plane (method small). Its states are SOFA HEAD's (2a278d8,
// `sofa-head SCENE 40 OUT --every 20`, %.17g), bit for bit, at steps 20 and 40.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace penalty;

/// The sheet [0,1]² of 3×3 points (index i + 3j), two triangles a cell, under `gravity`.
std::string fem_sheet(const std::string& method, const std::string& gravity) {
    return R"(<Node name="root" dt="0.01" gravity=")" + gravity + R"(">
  <DefaultAnimationLoop/>
  <Node name="Sheet">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <MeshTopology name="topo" position="0 0 0  0.5 0 0  1 0 0  0 0.5 0  0.5 0.5 0  1 0.5 0  0 1 0  0.5 1 0  1 1 0"
        triangles="0 1 4  0 4 3  1 2 5  1 5 4  3 4 7  3 7 6  4 5 8  4 8 7"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <TriangleFEMForceField youngModulus="3000" poissonRatio="0.3" method=")" +
           method + R"("/>
    <FixedProjectiveConstraint indices="0 3 6"/>
  </Node>
</Node>)";
}

/// Points 2, 5, 8 (the free side) and 4 (the centre) after `steps` more steps.
std::vector<Vec3> sheet_points(scene::Scene& s, int steps) {
    for (int k = 0; k < steps; ++k) s.step();
    const auto& x = dynamic_cast<const Vec3Object&>(*s.data({"/Sheet/dofs", false}, "position").state).position;
    return {x[2], x[5], x[8], x[4]};
}

TEST(TriangleFemSofaOrder, ALargeSheetSagsAsSofaHeadsBitForBit) {
    auto s = test::build(fem_sheet("large", "0 0 -9.81"));
    EXPECT_EQ(sheet_points(*s, 20),
              (std::vector<Vec3>{Vec3(0.96374508843205831, 0.00012890420637563381, -0.20440548610197984),
                                 Vec3(0.96367342843936332, 0.50002535458699182, -0.20438861131438452),
                                 Vec3(0.96369396576871047, 0.9999817688270769, -0.2044048777640875),
                                 Vec3(0.46362318064653735, 0.50000696593160454, -0.19249090758072659)}));
    EXPECT_EQ(sheet_points(*s, 20),
              (std::vector<Vec3>{Vec3(0.60858273454157419, 0.00045950714389679037, -0.75760972398366955),
                                 Vec3(0.60856380549888633, 0.50010546015531832, -0.75717285514357957),
                                 Vec3(0.6083682639288458, 0.99996743686981493, -0.75756914097539796),
                                 Vec3(0.19752191787932316, 0.50003621033505818, -0.46444916683562865)}));
}

TEST(TriangleFemSofaOrder, ASmallSheetStretchesInItsPlaneAsSofaHeadsBitForBit) {
    auto s = test::build(fem_sheet("small", "3 -9.81 0"));
    EXPECT_EQ(sheet_points(*s, 20), (std::vector<Vec3>{Vec3(0.99889616806213266, -0.0053900734701483148, 0),
                                                       Vec3(0.99976949169974061, 0.49482078677300073, 0),
                                                       Vec3(1.0007987037187518, 0.99481884049100444, 0),
                                                       Vec3(0.50020281225162655, 0.49712713614665849, 0)}));
    EXPECT_EQ(sheet_points(*s, 20), (std::vector<Vec3>{Vec3(0.99874127544666125, -0.0061619660863651638, 0),
                                                       Vec3(0.99973889051736897, 0.49407668505368918, 0),
                                                       Vec3(1.0009154361022607, 0.99407266174947728, 0),
                                                       Vec3(0.50023340472651345, 0.49671208868905331, 0)}));
}

}  // namespace
