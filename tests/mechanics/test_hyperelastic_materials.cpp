// The five hyperelastic materials (mechanics/hyperelastic_materials.cpp): S = 2∂W/∂C and dS[H]
// against finite differences; St Venant-Kirchhoff under a stretch in closed form.
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/hyperelastic_fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "hyperelastic_laws.hpp"
#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <random>

namespace penalty {
namespace {

using namespace test_samples;

/// A deformation gradient away from the identity (fixed), with J > 0.
Mat3 sample_deformation() {
    Mat3 f;
    f << 1.08, 0.05, -0.03, 0.02, 0.95, 0.04, -0.06, 0.01, 1.03;
    return f;
}

TEST(HyperelasticMaterials, StressIsTwiceTheEnergyGradientAndItsDerivativeMatchesFiniteDifferences) {
    const Mat3 f = sample_deformation();
    const Mat3 c = f.transpose() * f;
    const double j = f.determinant();
    Mat3 h;
    h << 0.3, -0.1, 0.2, -0.1, 0.5, 0.05, 0.2, 0.05, -0.4;  // symmetric
    for (const HyperelasticLaw& law : every_law()) {
        SCOPED_TRACE(std::string(material_name(law.material)));
        const auto energy = [&](const Mat3& cc) { return law.energy_density(cc, std::sqrt(cc.determinant())); };
        const Mat3 s = law.second_piola(c, j);
        const double step = 1e-6;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) {
                Mat3 e = Mat3::Zero();  // symmetric unit perturbation of C_ab and C_ba
                e(a, b) += 0.5;
                e(b, a) += 0.5;
                const double dw = (energy(c + step * e) - energy(c - step * e)) / (2 * step);
                EXPECT_NEAR(2 * dw, s(a, b), 1e-6 * (1 + s.cwiseAbs().maxCoeff())) << a << b;
            }
        const auto stress = [&](const Mat3& cc) { return law.second_piola(cc, std::sqrt(cc.determinant())); };
        const Mat3 fd = (stress(c + step * h) - stress(c - step * h)) / (2 * step);
        const Mat3 ds = law.stress_derivative(c, j, h);
        EXPECT_LT((fd - ds).cwiseAbs().maxCoeff(), 1e-6 * (1 + ds.cwiseAbs().maxCoeff()));
        EXPECT_GT(ds.cwiseAbs().maxCoeff(), 1.0);
        // stress-free at rest
        EXPECT_LT(law.second_piola(Mat3::Identity(), 1.0).cwiseAbs().maxCoeff(), 1e-9 * law.parameters[0]);
    }
}

TEST(HyperelasticMaterials, StVenantKirchhoffUnderAStretchIsLameTimesGreenStrain) {
    // F = diag(s, 1, 1): E = diag((s² − 1)/2, 0, 0), S = λ tr E·I + 2μE
    const double mu = 300, lambda = 700, s = 1.2;
    const HyperelasticLaw law{HyperelasticMaterial::StVenantKirchhoff, {mu, lambda}};
    const Mat3 c = Vec3(s * s, 1, 1).asDiagonal();
    const double exx = (s * s - 1) / 2;
    const Mat3 expected = Vec3(lambda * exx + 2 * mu * exx, lambda * exx, lambda * exx).asDiagonal();
    EXPECT_LT((law.second_piola(c, s) - expected).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_NEAR(law.energy_density(c, s), lambda / 2 * exx * exx + mu * exx * exx, 1e-10);
}

}  // namespace
}  // namespace penalty
