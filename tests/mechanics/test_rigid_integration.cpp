// Rigid3 Coord + Deriv·h (rigid_add): SOFA HEAD's exponential integration of the orientation
// (RigidCoord::operator+=), against the closed form and SOFA's own digits.
#include "penalty/mechanics/mechanical_object.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

TEST(RigidIntegration, ASteadySpinIsTheExactRotationWhateverTheStep) {
    // ω constant: N steps of h rotate by |ω|·N·h about ω exactly (exp(a)·exp(b) = exp(a + b) on
    // one axis); the first-order update q + ½(ω h ⊗ q), normalised, lags by O(h³) a step.
    const Vec3 axis = Vec3(1, -2, 2).normalized();
    RigidDeriv v;
    v.angular = 3.0 * axis;
    v.linear = Vec3(0.5, 0, -1);
    const Quat start(Eigen::AngleAxisd(0.3, Vec3(0, 1, 0)));
    RigidFrame x{Vec3(1, 2, 3), start};
    const double h = 0.05;
    for (int i = 0; i < 40; ++i) x = rigid_add(x, v, h);
    const Quat expected = Quat(Eigen::AngleAxisd(3.0 * 40 * h, axis)) * start;
    EXPECT_LT(std::abs(std::abs(x.orientation.dot(expected)) - 1.0), 1e-14);
    EXPECT_LT((x.center - Vec3(2, 2, 1)).norm(), 1e-13);
    EXPECT_NEAR(x.orientation.norm(), 1.0, 1e-14);
}

TEST(RigidIntegration, OneStepGivesSofasDigits) {
    // SOFA HEAD (2a278d8): a Rigid3d frame at the identity spinning at ω = (0, 0, 2) rad/s, one
    // implicit Euler step of 0.01 s with no torque: x = 0 0 0  0 0 0.0099998333341666645
    // 0.99995000041666526 (sofa-head's state file, %.17g).
    RigidDeriv v;
    v.angular = Vec3(0, 0, 2);
    const RigidFrame x = rigid_add(RigidFrame{}, v, 0.01);
    EXPECT_EQ(x.orientation.z(), 0.0099998333341666645);
    EXPECT_EQ(x.orientation.w(), 0.99995000041666526);
    EXPECT_EQ(x.orientation.x(), 0.0);
    // no rotation: the gnomonic branch leaves the orientation's bits
    const RigidFrame still = rigid_add(RigidFrame{Vec3::Zero(), Quat(0.5, 0.5, 0.5, 0.5)}, RigidDeriv{}, 0.01);
    EXPECT_EQ(still.orientation.coeffs(), Quat(0.5, 0.5, 0.5, 0.5).coeffs());
}

}  // namespace
}  // namespace penalty
