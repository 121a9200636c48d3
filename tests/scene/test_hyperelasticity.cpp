// TetrahedronHyperelasticityFEMForceField in a scene (scene/builder/hyperelasticity.cpp).
#include "force_field_family_scenes.hpp"
#include "penalty/mechanics/interaction_ellipsoid.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace {

using namespace penalty::test_family_scenes;
using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

TEST(HyperelasticityComponent, EveryMaterialBuildsAndBadAttributesNameTheAttribute) {
    for (const char* material : {"ArrudaBoyce", "StVenantKirchhoff", "NeoHookean"}) {
        auto s = build(with_text(kHyperelasticScene, "MATERIAL", material));
        for (int i = 0; i < 10; ++i) s->step();
        EXPECT_LT(family_state(*s, 0).position[11].y(), 1.0 - 1e-5) << material;  // the free end sags
    }
    auto ogden = build(with_text(with_text(kHyperelasticScene, "MATERIAL", "Ogden"), "3448 31034", "1500 500 5000"));
    ogden->step();
    EXPECT_THAT(error_of(with_text(kHyperelasticScene, "MATERIAL", "Costa")),
                HasSubstr("test.scn:9: TetrahedronHyperelasticityFEMForceField 'FEM': attribute 'materialName': "
                          "'Costa' is not supported"));
    EXPECT_THAT(error_of(with_text(kHyperelasticScene, "MATERIAL", "MooneyRivlin")),
                HasSubstr("attribute 'ParameterSet': MooneyRivlin needs 3 parameters, found 2"));
}

}  // namespace
