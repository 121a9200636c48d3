#pragma once
// The hyperelastic laws the tests check, each with parameters of SOFA's examples.
#include "penalty/mechanics/hyperelastic_fem.hpp"

#include <vector>

namespace penalty::test_samples {

inline std::vector<HyperelasticLaw> every_law() {
    return {{HyperelasticMaterial::ArrudaBoyce, {3448.2759, 31034.483}},
            {HyperelasticMaterial::StVenantKirchhoff, {3448.2759, 31034.483}},
            {HyperelasticMaterial::NeoHookean, {3448.2759, 31034.483}},
            {HyperelasticMaterial::MooneyRivlin, {5000, 7000, 10}},
            {HyperelasticMaterial::Ogden, {1500, 500, 5000}}};
}

}  // namespace penalty::test_samples
