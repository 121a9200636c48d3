// TaitSurfacePressureForceField: a cube of outward quads (split as SOFA splits them) holding a
// fluid of Tait's equation of state. Closed forms: the pressure of a uniformly scaled cube, the
// force p·A on each face, Σ xᵢ·fᵢ = 3 p V (V is homogeneous of degree 3), the injection's ramp;
// derivatives: add_dforce and the assembled matrix against finite differences, f = −dE/dx.
#include "penalty/mechanics/tait_surface_pressure.hpp"

#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

/// A cube [0, a]³ of 8 points and 6 outward quads, at rest with side 1.
struct FluidCube {
    Vec3Object state;
    MeshTopology topology;
    double time = 0;
    explicit FluidCube(double side = 1.0) {
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) state.position.emplace_back(i, j, k);
        state.init();  // rest = side 1
        for (Vec3& x : state.position) x *= side;
        // point id = i + 2j + 4k; each quad counter-clockwise seen from outside
        topology.set_quads({{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}});
    }
    ContextClock clock() {
        return [this] { return time; };
    }
    Eigen::VectorXd force(BaseForceField& ff) {
        std::fill(state.force.begin(), state.force.end(), Vec3::Zero());
        ff.accumulate_force();
        return Vec3Object::flat(state.force);
    }
};

ContextClock step_of(double dt) {
    return [dt] { return dt; };
}

TEST(TaitSurfacePressureForceField, VolumeOfTheQuadCube) {
    FluidCube c(1.3);
    TaitSurfacePressureForceField ff(c.state, c.topology, {.p0 = 2, .bulk_modulus = 0, .gamma = 0}, c.clock(),
                                     step_of(0.01));
    ff.init();
    EXPECT_EQ(ff.triangles().size(), 12u);
    EXPECT_NEAR(ff.rest_volume(), 1.0, 1e-15);
    EXPECT_NEAR(ff.volume_of(c.state.position), 1.3 * 1.3 * 1.3, 1e-14);
}

TEST(TaitSurfacePressureForceField, PressureOfAScaledCubePushesEachFaceWithPTimesItsArea) {
    const double side = 1.1, p0 = 50, b = 1000, gamma = 5;
    FluidCube c(side);
    TaitSurfacePressureForceField ff(c.state, c.topology, {.p0 = p0, .bulk_modulus = b, .gamma = gamma}, c.clock(),
                                     step_of(0.01));
    ff.init();
    const Eigen::VectorXd f = c.force(ff);
    const double v = side * side * side;
    const double p = p0 - b * (std::pow(v, gamma) - 1);
    EXPECT_NEAR(ff.current_volume(), v, 1e-14);
    EXPECT_NEAR(ff.current_pressure(), p, 1e-9 * std::fabs(p));
    // the face x = side: points 1, 3, 5, 7 carry p·side² along +x in all (the other faces add no x)
    double fx = 0, work = 0;
    Vec3 total = Vec3::Zero();
    for (int i = 0; i < 8; ++i) {
        const Vec3 fi = f.segment<3>(3 * i);
        if (i % 2 == 1) fx += fi.x();
        total += fi;
        work += c.state.position[std::size_t(i)].dot(fi);
    }
    EXPECT_NEAR(fx, p * side * side, 1e-9 * std::fabs(p));
    EXPECT_LT(total.norm(), 1e-9 * std::fabs(p)) << "a pressure has no net force";
    EXPECT_NEAR(work, 3 * p * v, 1e-9 * std::fabs(p)) << "Σ x·∇V = 3V";
    // compressed below V0 the fluid pushes out (p > p0), expanded it pulls in
    EXPECT_LT(p, p0);
}

TEST(TaitSurfacePressureForceField, InjectionRampsAtTheMaximumRateOncePerStep) {
    FluidCube c;
    const double dt = 0.01, rate = 2.0, target = 0.05;
    TaitSurfacePressureForceField ff(
        c.state, c.topology,
        {.p0 = 0, .bulk_modulus = 100, .gamma = 1, .injected_volume = target, .max_injection_rate = rate}, c.clock(),
        step_of(dt));
    ff.init();
    for (int step = 1; step <= 4; ++step) {
        c.force(ff);
        c.force(ff);  // a second evaluation in the same step injects nothing more
        const double injected = std::min(step * rate * dt, target);
        EXPECT_NEAR(ff.injected_volume(), injected, 1e-15) << step;
        // V = 1 = V0 − injected: p = −B (V/V0 − 1) > 0
        EXPECT_NEAR(ff.current_pressure(), -100 * (1 / (1 + injected) - 1), 1e-12) << step;
        c.time += dt;
    }
    EXPECT_NEAR(ff.injected_volume(), target, 1e-15);
}

void deform(FluidCube& c) {
    for (std::size_t i = 0; i < c.state.position.size(); ++i) {
        const double s = double(i);
        c.state.position[i] = 1.05 * c.state.position[i] +
                              Vec3(0.03 * std::sin(s + 1), 0.04 * std::cos(2 * s), 0.02 * std::sin(3 * s + 0.5));
    }
}

TEST(TaitSurfacePressureForceField, DerivativesAreExactForEveryExponent) {
    for (const double gamma : {0.0, 1.0, 5.0}) {
        FluidCube c;
        TaitSurfacePressureForceField ff(c.state, c.topology, {.p0 = 30, .bulk_modulus = 1000, .gamma = gamma},
                                         c.clock(), step_of(0.01));
        ff.init();
        deform(c);
        const auto d = test::check_force_field_derivatives(
            ff, c.state, {.dforce_vs_fd = 1e-7, .assembled_vs_dforce = 1e-13, .force_vs_energy = 1e-7});
        EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 1.0) << gamma;
        // K = (dp/dV) ∇V∇Vᵀ + p ∂∇V/∂x is symmetric
        EXPECT_LT((d.k_dforce - d.k_dforce.transpose()).cwiseAbs().maxCoeff(), 1e-9 * d.k_dforce.cwiseAbs().maxCoeff())
            << gamma;
    }
}

TEST(TaitSurfacePressureForceField, RefusesASurfacePointOutsideTheState) {
    FluidCube c;
    MeshTopology t;
    t.set_triangles({{0, 1, 9}});
    TaitSurfacePressureForceField ff(c.state, t, {.p0 = 1}, c.clock(), step_of(0.01));
    EXPECT_THROW(ff.init(), std::invalid_argument);
}

}  // namespace
}  // namespace penalty
