// Readers of a live engine's output beyond the projective constraints (src/scene/live_engines.cpp):
// a ConstantForceField whose `indices` link a BoxROI over moving positions takes them at each
// addForce and runs SOFA's update callbacks when they change (ConstantForceField::updateFromIndices,
// updateFromForcesVector, updateFromTotalForce): one `forces` value, spread over the count of init,
// no longer fits a new count and the component is Invalid (no force); a `totalForce` is spread
// again. The trajectories are SOFA HEAD's (2a278d8, `sofa-head SCENE 40 OUT --every 1`, %.17g), bit
// for bit, on a cantilever whose free end sags out of the box (20, then 18, 16 and 14 points in it).
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/falling_beam.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace penalty;

/// The beam held at x = 0; a BoxROI around its points at init feeds a ConstantForceField `load`.
std::string cantilever_pushed_in_box(const std::string& load) {
    return test::falling_beam(R"(    <FixedProjectiveConstraint indices="0 5 10 15"/>
)",
                              R"(    <BoxROI name="box" box="-0.1 -0.05 -0.1  2.1 0.6 0.6" position="@dofs.position"/>
    <ConstantForceField name="push" indices="@box.indices" )" +
                                  load + R"(/>
)");
}

const std::vector<Vec3>& beam_positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Beam/dofs", false}, "position").state).position;
}

std::size_t points_in_box(scene::Scene& s) { return s.data({"/Beam/box", false}, "indices").numbers.size(); }

TEST(LiveEngineReaders, ConstantForceFieldWithOneForceIsInvalidOnceTheFollowedIndicesChangeCount) {
    auto s = test::build(cantilever_pushed_in_box(R"(forces="0 -0.5 0")"));
    const std::vector<Vec3>& x = beam_positions(*s);
    for (int k = 0; k < 10; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 16U);
    // SOFA HEAD: the 20 forces of init no longer fit (updateFromForcesVector: Invalid, no force)
    EXPECT_EQ(x[4], Vec3(1.9849291851993416, -0.091178249334574302, 3.9602148622416299e-05));
    EXPECT_EQ(x[19], Vec3(2.0116790262214672, 0.40817041300676549, 0.50003212730506674));
    for (int k = 10; k < 40; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 14U);
    // without the force the beam springs back up
    EXPECT_EQ(x[4], Vec3(1.9474345206662571, -0.23551976738219282, 9.7205503432081167e-05));
    EXPECT_EQ(x[19], Vec3(2.0228286138950953, 0.25876609876646894, 0.50007240501292971));
}

TEST(LiveEngineReaders, ConstantForceFieldSpreadsItsTotalForceOverTheFollowedIndices) {
    auto s = test::build(cantilever_pushed_in_box(R"(totalForce="0 -3 0")"));
    const std::vector<Vec3>& x = beam_positions(*s);
    for (int k = 0; k < 10; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 18U);
    // SOFA HEAD: T / 18 on each point in the box, then T / 16, T / 14 (updateFromTotalForce)
    EXPECT_EQ(x[4], Vec3(1.9901306309339966, -0.06305369382870285, 2.4666572693337988e-05));
    EXPECT_EQ(x[19], Vec3(2.0083003288498449, 0.43663448631303647, 0.50002400089920895));
    for (int k = 10; k < 40; ++k) s->step();
    EXPECT_EQ(points_in_box(*s), 14U);
    EXPECT_EQ(x[4], Vec3(1.9364712726168873, -0.27310608332049879, 9.3116151874950314e-05));
    EXPECT_EQ(x[19], Vec3(2.0237778737312744, 0.21906614328469079, 0.50009358434268136));
}

}  // namespace
