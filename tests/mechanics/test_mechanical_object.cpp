// MechanicalObject (mechanics/mechanical_object.cpp): the initial transform (scale, rotate, translate).
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace penalty {
namespace {

TEST(MechanicalObject, InitialTransformScaleRotateTranslate) {
    Vec3Object s;
    s.position = {Vec3(1, 0, 0)};
    s.transform.scale3d = Vec3(2, 1, 1);
    s.transform.rotation_deg = Vec3(0, 0, 90);
    s.transform.translation = Vec3(0, 0, 5);
    s.init();
    EXPECT_TRUE(s.position[0].isApprox(Vec3(0, 2, 5), 1e-14));
    EXPECT_TRUE(s.rest_position[0].isApprox(Vec3(0, 2, 5), 1e-14));
    // Given rest positions are not transformed (SOFA); velocities completed with the last one.
    Vec3Object given;
    given.position = {Vec3(1, 0, 0), Vec3(2, 0, 0)};
    given.rest_position = {Vec3(1, 0, 0), Vec3(2, 0, 0)};
    given.velocity = {Vec3(0, 3, 0)};
    given.transform.translation = Vec3(0, 0, 1);
    given.init();
    EXPECT_EQ(given.position[1], Vec3(2, 0, 1));
    EXPECT_EQ(given.rest_position[1], Vec3(2, 0, 0));
    EXPECT_EQ(given.velocity[1], Vec3(0, 3, 0));
    Vec3Object rest_only;
    rest_only.rest_position = {Vec3(4, 5, 6)};
    rest_only.init();
    EXPECT_EQ(rest_only.position[0], Vec3(4, 5, 6));
    Vec3Object bad;
    bad.position = {Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)};
    EXPECT_THROW(bad.init(), std::invalid_argument);
    Rigid3Object r;
    r.position.resize(1);
    r.transform.rotation_deg = Vec3(90, 0, 0);
    r.init();
    EXPECT_TRUE((r.position[0].orientation * Vec3::UnitY()).isApprox(Vec3::UnitZ(), 1e-14));
}

}  // namespace
}  // namespace penalty
