// SOFA's plasticity of TetrahedronFEMForceField (tetrahedron_plasticity.cpp, method large with
// plasticMaxThreshold > 0): a beam of twelve tetrahedra, its x = 0 end fixed, sagging under
// gravity with a plastic strain that creeps past the yield threshold and is clamped to the
// maximum. Its trajectory is SOFA HEAD's (2a278d8, `sofa-head SCENE 100 OUT --every 50`,
// %.17g), bit for bit, at steps 50 and 100; the same beam without plasticity is SOFA's elastic
// one. The refusals name the file, line, component and attribute.
#include "penalty/mechanics/fem.hpp"
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/twelve_tetrahedra_beam.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace penalty;

const std::string kPlastic =
    R"(method="large" plasticYieldThreshold="0.001" plasticMaxThreshold="0.02" plasticCreep="0.5")";

const std::vector<Vec3> kSofaPlastic50 = {Vec3(0, 0, 0),
                                          Vec3(0.42821545970890623, -0.16268344649404154, 0.017222777385099183),
                                          Vec3(0.88825414734505825, -0.34310010700772342, 0.046015358373251658),
                                          Vec3(0, 0.5, 0),
                                          Vec3(0.54427900604829316, 0.33570571677671696, 0.011955418197295601),
                                          Vec3(1.0316935422066786, 0.13789050981206477, 0.03670723918690471),
                                          Vec3(0, 0, 0.5),
                                          Vec3(0.40425482558547254, -0.1505017163030411, 0.51250662281163317),
                                          Vec3(0.85611527038109758, -0.32706958678717807, 0.53936000672008955),
                                          Vec3(0, 0.5, 0.5),
                                          Vec3(0.52409078659925723, 0.35468912018251142, 0.50407059063061344),
                                          Vec3(1.0076247777393657, 0.15932426176805276, 0.53116071001484944)};
const std::vector<Vec3> kSofaPlastic100 = {Vec3(0, 0, 0),
                                           Vec3(0.41449220069034914, -0.16362928031239707, 0.016893329892698219),
                                           Vec3(0.85926934525634413, -0.37308697564320559, 0.045673089261079131),
                                           Vec3(0, 0.5, 0),
                                           Vec3(0.53525138548443352, 0.33988973899778224, 0.01065799686417985),
                                           Vec3(1.0093477522342496, 0.11775837232242231, 0.034220792996795049),
                                           Vec3(0, 0, 0.5),
                                           Vec3(0.3969878930324281, -0.15284777447702091, 0.51063669692392),
                                           Vec3(0.82714630098126229, -0.35353216068205212, 0.53370608166134303),
                                           Vec3(0, 0.5, 0.5),
                                           Vec3(0.51922359342312463, 0.35998044237568638, 0.50263029591367769),
                                           Vec3(0.98912754319761231, 0.1436112239717201, 0.52373866689141635)};
const std::vector<Vec3> kSofaElastic100 = {Vec3(0, 0, 0),
                                           Vec3(0.48353697821845926, -0.058625027473030326, 0.0071290059828784513),
                                           Vec3(0.9772355667205922, -0.11724809855493525, 0.01902834824938044),
                                           Vec3(0, 0.5, 0),
                                           Vec3(0.52204377350158848, 0.44319330963794057, 0.0048658097824556094),
                                           Vec3(1.0222939361113257, 0.3826605606366501, 0.015455835408270209),
                                           Vec3(0, 0, 0.5),
                                           Vec3(0.47271546908988504, -0.056086834054200181, 0.50573152606610405),
                                           Vec3(0.96309162584684627, -0.11370904992863255, 0.51716113839667022),
                                           Vec3(0, 0.5, 0.5),
                                           Vec3(0.51257419252521896, 0.44914248355020164, 0.50266588844874704),
                                           Vec3(1.0112817402752148, 0.38852756732503674, 0.51411982442752546)};

const std::vector<Vec3>& plastic_beam_positions(scene::Scene& s) {
    return dynamic_cast<const Vec3Object&>(*s.data({"/Beam/dofs", false}, "position").state).position;
}

TEST(TetrahedronPlasticity, ABeamCreepsAsSofaHeadsBitForBit) {
    auto s = test::build(test::twelve_tetrahedra_beam(kPlastic));
    for (int k = 0; k < 50; ++k) s->step();
    EXPECT_EQ(plastic_beam_positions(*s), kSofaPlastic50);
    for (int k = 0; k < 50; ++k) s->step();
    EXPECT_EQ(plastic_beam_positions(*s), kSofaPlastic100);
    // the plastic strain keeps the tip 0.26 m below the elastic beam's
    EXPECT_LT(kSofaPlastic100[2].y(), kSofaElastic100[2].y() - 0.25);
}

TEST(TetrahedronPlasticity, WithoutAMaximumTheBeamIsSofasElasticOne) {
    // plasticMaxThreshold 0 (SOFA's default) turns plasticity off, whatever the other two say
    auto s =
        test::build(test::twelve_tetrahedra_beam(R"(method="large" plasticYieldThreshold="0.001" plasticCreep="0.5")"));
    for (int k = 0; k < 100; ++k) s->step();
    EXPECT_EQ(plastic_beam_positions(*s), kSofaElastic100);
}

TEST(TetrahedronPlasticity, TheStrainIsClampedToTheMaximumAlongItsDirection) {
    // with creep 1 and a large load every element's plastic strain goes to its clamp:
    // |εp| ≤ plasticMaxThreshold = 0.02, reached by the elements at the fixed end
    auto s = test::build(test::twelve_tetrahedra_beam(
        R"(method="large" plasticYieldThreshold="0.0001" plasticMaxThreshold="0.02" plasticCreep="1")"));
    for (int k = 0; k < 30; ++k) s->step();
    const TetrahedronFEMForceField* fem = nullptr;
    for (const auto& field : s->simulation().root().children()[0]->force_fields())
        if ((fem = dynamic_cast<const TetrahedronFEMForceField*>(field.get())) != nullptr) break;
    ASSERT_NE(fem, nullptr);
    double largest = 0.0;
    for (std::size_t e = 0; e < 12; ++e) {
        double norm2 = 0.0;
        for (const double v : fem->plastic_strain(e)) norm2 += v * v;
        EXPECT_LE(std::sqrt(norm2), 0.02 * (1 + 1e-15)) << e;
        largest = std::max(largest, std::sqrt(norm2));
    }
    EXPECT_NEAR(largest, 0.02, 1e-15);
}

TEST(TetrahedronPlasticity, OtherMethodsAndNegativeThresholdsAreRefusedClearly) {
    const std::string small =
        test::error_of(test::twelve_tetrahedra_beam(R"(method="small" plasticMaxThreshold="0.02")"));
    EXPECT_EQ(small,
              "test.scn:9: TetrahedronFEMForceField: attribute 'plasticMaxThreshold': plasticity is supported "
              "with method large only");
    const std::string negative = test::error_of(
        test::twelve_tetrahedra_beam(R"(method="large" plasticMaxThreshold="0.02" plasticCreep="-0.5")"));
    EXPECT_EQ(negative, "test.scn:9: TetrahedronFEMForceField: attribute 'plasticCreep': must be >= 0, found '-0.5'");
}

}  // namespace
