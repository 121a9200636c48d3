// TetrahedronFEMForceField (mechanics/fem.cpp) in a built scene: its methods small, polar and svd
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

}  // namespace
