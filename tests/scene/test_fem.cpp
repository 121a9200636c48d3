// TetrahedronFEMForceField and HexahedronFEMForceField (mechanics/fem.cpp) in a built scene, each
// method against SOFA HEAD's states. TetrahedronFEMForceField's methods small, polar and svd
// make SOFA's operations in SOFA's order (tetrahedron_large_element.hpp: initSmall / initPolar /
// initSVD, computeMaterialStiffness, accumulateForceSmall / Polar / SVD, computeForce,
// applyStiffnessSmall / Corotational), so the beam of twelve tetrahedra is SOFA HEAD's (2a278d8,
// `sofa-head SCENE 100 OUT --every 50`, %.17g) bit for bit at steps 50 and 100. (The common
// K^e product they used before parted from SOFA by 2.2e-16 m at step 50 under polar, 1.8e-12
// summed over the steps under small.) The beam does not
// invert, so svd takes polar's rotation and SOFA's states for both are the same.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/twelve_tetrahedra_beam.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace penalty;

const std::vector<Vec3>& beam_positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Beam/dofs", false}, "position").state).position;
}

TEST(TetrahedronFemMethods, SmallPolarAndSvdAreSofaHeadsBeamBitForBit) {
    auto small = test::build(test::twelve_tetrahedra_beam(R"(method="small")"));
    for (int k = 0; k < 100; ++k) small->step();
    EXPECT_EQ(beam_positions(*small), test::kSofaHeadSmallBeam100);
    for (const char* method : {"polar", "svd"}) {
        SCOPED_TRACE(method);
        auto s = test::build(test::twelve_tetrahedra_beam(std::string("method=\"") + method + "\""));
        for (int k = 0; k < 50; ++k) s->step();
        EXPECT_EQ(beam_positions(*s), test::kSofaHeadPolarBeam50);
        for (int k = 0; k < 50; ++k) s->step();
        EXPECT_EQ(beam_positions(*s), test::kSofaHeadPolarBeam100);
    }
}

/// A beam of two hexahedra ([0,1]×[0,0.5]×[0,0.5], a 3×2×2 RegularGridTopology), its x = 0 end
/// fixed, under HexahedronFEMForceField with `method`.
std::string hexahedron_beam(const std::string& method) {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" n="3 2 2" min="0 0 0" max="1 0.5 0.5"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="2"/>
    <HexahedronFEMForceField youngModulus="2000" poissonRatio="0.3" method=")" +
           method + R"("/>
    <FixedProjectiveConstraint indices="0 3 6 9"/>
  </Node>
</Node>)";
}

// HexahedronFEMForceField in SOFA's operations (computeElementStiffness's Gauss-point loop with
// GENERIC_STIFFNESS_MATRIX, DN_USE_J and MAT_STIFFNESS_USE_W; initSmall / initLarge / initPolar;
// accumulateForce*; addDForce): SOFA HEAD's beam (2a278d8, `sofa-head SCENE 100 OUT`, %.17g) to
// the bit after 100 steps. (penalty's own quadrature parted at step 1: 8.6e-7 summed over the
// steps under small, 2.3e-14 under large.)
TEST(HexahedronFemMethods, SmallLargeAndPolarAreSofaHeadsBeamBitForBit) {
    const std::vector<std::pair<std::string, std::vector<Vec3>>> sofa = {
        {"small",
         {Vec3(0, 0, 0), Vec3(0.45569390550237715, -0.076621632682430704, -0.0066861792998793058),
          Vec3(0.94318829428163975, -0.19349167268005499, -0.00014335065061211799), Vec3(0, 0.5, 0),
          Vec3(0.54430609388363949, 0.42337837532121614, 0.0066861712962324026),
          Vec3(1.056811708021947, 0.30650833005351913, 0.00014334791703778967), Vec3(0, 0, 0.5),
          Vec3(0.45569390550237732, -0.076621632682430621, 0.50668617929987936),
          Vec3(0.94318829428163986, -0.1934916726800549, 0.50014335065061211), Vec3(0, 0.5, 0.5),
          Vec3(0.54430609388363937, 0.42337837532121619, 0.4933138287037675),
          Vec3(1.056811708021947, 0.30650833005351935, 0.49985665208296204)}},
        {"large",
         {Vec3(0, 0, 0), Vec3(0.45386731776728245, -0.072038869983492043, -0.0062900697374729071),
          Vec3(0.93052035972918945, -0.18313577971753567, 0.00010397114901959046), Vec3(0, 0.5, 0),
          Vec3(0.54042466114368559, 0.42063546644289979, 0.0067712099395898506),
          Vec3(1.0407612348641659, 0.30423061919546912, 0.00034573446498234993), Vec3(0, 0, 0.5),
          Vec3(0.4538673177672824, -0.072038869983492043, 0.50629006973747281),
          Vec3(0.93052035972918934, -0.18313577971753561, 0.49989602885098056), Vec3(0, 0.5, 0.5),
          Vec3(0.54042466114368559, 0.42063546644289979, 0.49322879006041015),
          Vec3(1.0407612348641659, 0.30423061919546907, 0.49965426553501774)}},
        {"polar",
         {Vec3(0, 0, 0), Vec3(0.45336123201750261, -0.071898767286981607, -0.006395921581668928),
          Vec3(0.92974499346024653, -0.18338763639868111, 0.00010890757414326888), Vec3(0, 0.5, 0),
          Vec3(0.54006335669423344, 0.42042653284586651, 0.0067182152741971047),
          Vec3(1.0402941369834628, 0.30386761750388058, 0.00035448264416481072), Vec3(0, 0, 0.5),
          Vec3(0.45336123201750256, -0.07189876728698158, 0.50639592158166891),
          Vec3(0.92974499346024653, -0.18338763639868105, 0.49989109242585683), Vec3(0, 0.5, 0.5),
          Vec3(0.54006335669423344, 0.42042653284586651, 0.49328178472580292),
          Vec3(1.0402941369834628, 0.30386761750388058, 0.49964551735583518)}}};
    for (const auto& [method, positions] : sofa) {
        SCOPED_TRACE(method);
        auto s = test::build(hexahedron_beam(method));
        for (int k = 0; k < 100; ++k) s->step();
        EXPECT_EQ(beam_positions(*s), positions);
    }
}

}  // namespace
