// TetrahedronFEMForceField (mechanics/fem.cpp) in a built scene: its methods polar and svd make
// SOFA's operations in SOFA's order (tetrahedron_large_element.hpp: initPolar / initSVD,
// computeMaterialStiffness, accumulateForcePolar / accumulateForceSVD, computeForce,
// applyStiffnessCorotational), so the beam of twelve tetrahedra is SOFA HEAD's (2a278d8,
// `sofa-head SCENE 100 OUT --every 50`, %.17g) bit for bit at steps 50 and 100. (The common
// K^e product they used before parted from SOFA by 2.2e-16 m at step 50.) The beam does not
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

const std::vector<Vec3> kSofaPolar50 = {Vec3(0, 0, 0),
                                        Vec3(0.48297019809461, -0.060729191307034316, 0.0097158718428789967),
                                        Vec3(0.97587195330520604, -0.12335211229967505, 0.024937528816984991),
                                        Vec3(0, 0.5, 0),
                                        Vec3(0.52331664429513369, 0.44107605106030995, 0.0073581585869252654),
                                        Vec3(1.0238169665407055, 0.37659679877609054, 0.021045540114927808),
                                        Vec3(0, 0, 0.5),
                                        Vec3(0.47007115821655238, -0.057807141073933505, 0.50807066160704073),
                                        Vec3(0.95880694102799524, -0.11921175827801488, 0.52268082174430475),
                                        Vec3(0, 0.5, 0.5),
                                        Vec3(0.51167896670278135, 0.44755426169061291, 0.50458857159587511),
                                        Vec3(1.0100544681881598, 0.3832724693822126, 0.51925774903057453)};
const std::vector<Vec3> kSofaPolar100 = {Vec3(0, 0, 0),
                                         Vec3(0.48422183050026796, -0.056017255859617844, 0.0071862186326625685),
                                         Vec3(0.97812207042451693, -0.11254733664732108, 0.018866753130246779),
                                         Vec3(0, 0.5, 0),
                                         Vec3(0.52064002301689849, 0.44578742019741463, 0.0051013874687962464),
                                         Vec3(1.0210320262050623, 0.38751294077556808, 0.015447566766778716),
                                         Vec3(0, 0, 0.5),
                                         Vec3(0.47364322705342554, -0.053668032720560192, 0.50582723264444851),
                                         Vec3(0.96416973512196502, -0.1092622810060357, 0.51701532417618901),
                                         Vec3(0, 0.5, 0.5),
                                         Vec3(0.51128081854104024, 0.45140179224892812, 0.50282606970905386),
                                         Vec3(1.0102104173722608, 0.39314917530165738, 0.5141139731416049)};

const std::vector<Vec3>& beam_positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Beam/dofs", false}, "position").state).position;
}

TEST(TetrahedronFemMethods, PolarAndSvdAreSofaHeadsBeamBitForBit) {
    for (const char* method : {"polar", "svd"}) {
        SCOPED_TRACE(method);
        auto s = test::build(test::twelve_tetrahedra_beam(std::string("method=\"") + method + "\""));
        for (int k = 0; k < 50; ++k) s->step();
        EXPECT_EQ(beam_positions(*s), kSofaPolar50);
        for (int k = 0; k < 50; ++k) s->step();
        EXPECT_EQ(beam_positions(*s), kSofaPolar100);
    }
}

}  // namespace
