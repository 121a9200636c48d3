// The scene components of SOFA's MechanicalLoad: PlaneForceField, ConstantForceField and
// ConicalForceField built from a .scn, described, run, and checked against closed forms.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/external_loads.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/component_defaults.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using ::testing::HasSubstr;

/// One node of particles at `positions` (vertexMass 0.5 kg each) under `gravity`, an implicit
/// solver without Rayleigh damping (unless given), and the given components.
std::string particles_scene(const std::string& positions, const std::string& components,
                            const std::string& gravity = "0 -9.81 0", const std::string& rayleigh = "0") {
    return R"(<Node name="root" dt="0.01" gravity=")" + gravity + R"(">
      <Node name="P"><EulerImplicitSolver rayleighStiffness="0" rayleighMass=")" +
           rayleigh + R"("/>
        <CGLinearSolver iterations="100" tolerance="1e-16" threshold="1e-20"/>
        <MechanicalObject name="dofs" position=")" +
           positions + R"("/>
        <UniformMass vertexMass="0.5"/>
        )" +
           components + R"(
      </Node>
    </Node>)";
}

const Vec3Object& dofs(const scene::Scene& s) { return dynamic_cast<const Vec3Object&>(*s.states()[0].state); }

using penalty::test::default_number;

TEST(ExternalLoadComponents, RegistryDefaultsAgreeWithTheLibrary) {
    const PlaneForceFieldParameters plane;
    EXPECT_EQ(default_number("PlaneForceField", "d"), plane.offset);
    EXPECT_EQ(default_number("PlaneForceField", "stiffness"), plane.stiffness);
    EXPECT_EQ(default_number("PlaneForceField", "damping"), plane.damping);
    EXPECT_EQ(default_number("PlaneForceField", "maxForce"), plane.max_force);
    EXPECT_EQ(default_number("PlaneForceField", "bilateral"), double(plane.bilateral));
    const ConicalForceFieldParameters cone;
    EXPECT_EQ(default_number("ConicalForceField", "coneAngle"), cone.angle_deg);
    EXPECT_EQ(default_number("ConicalForceField", "stiffness"), cone.stiffness);
    EXPECT_EQ(default_number("ConicalForceField", "damping"), cone.damping);
}

TEST(ExternalLoadComponents, ParticleRestsOnThePlaneAtTheDepthWhereStiffnessBalancesGravity) {
    // m g = k depth: 0.5 kg · 9.81 m/s² / 1000 N/m = 4.905 mm below the plane y = −1
    auto s = build(particles_scene(
        "0 -0.5 0  3 2 1",
        R"(<PlaneForceField name="floor" normal="0 1 0" d="-1" stiffness="1000" damping="2" showPlane="1"/>)",
        "0 -9.81 0", "0.5"));
    EXPECT_THAT(scene::describe_scene(*s),
                HasSubstr("plane x.n = -1 m, n = (0, 1, 0), stiffness 1000 N/m, damping 2 N s/m"));
    for (int i = 0; i < 1500; ++i) s->step();
    const Vec3Object& x = dofs(*s);
    EXPECT_NEAR(x.position[0].y(), -1.0 - 0.5 * 9.81 / 1000.0, 1e-7);
    EXPECT_NEAR(x.position[0].x(), 0.0, 1e-12);
    EXPECT_NEAR(x.velocity[0].norm(), 0.0, 1e-6);
    EXPECT_LT(x.position[1].y(), -1.0);  // the second particle fell from 2 m and rests there too
    EXPECT_NEAR(x.position[1].y(), x.position[0].y(), 1e-6);
}

TEST(ExternalLoadComponents, ConstantForceAcceleratesParticlesAsImplicitEulerPredicts) {
    // no gravity, K = 0: v_n = n h F/m, x_n = x_0 + h² (F/m) n(n+1)/2 (implicit Euler, exact)
    auto s = build(particles_scene("0 0 0  1 0 0  2 0 0",
                                   R"(<ConstantForceField indices="0 2" totalForce="0.5 -1 0"/>)", "0 0 0"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("constant force on 2 points, total (0.5, -1, 0) N"));
    const int steps = 20;
    for (int i = 0; i < steps; ++i) s->step();
    const Vec3Object& x = dofs(*s);
    const Vec3 acceleration = Vec3(0.25, -0.5, 0.0) / 0.5;  // half of the total on each of 2 points
    const double h = 0.01;
    const Vec3 travelled = h * h * acceleration * (steps * (steps + 1) / 2.0);
    EXPECT_LT((x.position[0] - travelled).norm(), 1e-12);
    EXPECT_LT((x.position[2] - (Vec3(2, 0, 0) + travelled)).norm(), 1e-12);
    EXPECT_EQ(x.position[1], Vec3(1, 0, 0));
    EXPECT_LT((x.velocity[0] - steps * h * acceleration).norm(), 1e-12);
}

TEST(ExternalLoadComponents, ConstantForceOnTheIndicesOfABoxRoi) {
    auto s = build(particles_scene("0 0 0  1 0 0  2 0 0",
                                   R"(<BoxROI name="box" box="0.5 -1 -1  2.5 1 1"/>
                                      <ConstantForceField indices="@box.indices" forces="0 1 0"/>)",
                                   "0 0 0"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("constant force on 2 points, total (0, 2, 0) N"));
    s->step();
    const Vec3Object& x = dofs(*s);
    EXPECT_EQ(x.position[0], Vec3(0, 0, 0));
    EXPECT_GT(x.position[1].y(), 0.0);
    EXPECT_EQ(x.position[1].y(), x.position[2].y());
}

TEST(ExternalLoadComponents, ConeHoldsParticlesInside) {
    // particles start beside the cone, behind its apex and beyond its cap; the cone pushes them in
    auto s = build(particles_scene("3 1 0  0 -0.5 0  0 2.5 0  0.2 1 0",
                                   R"(<ConicalForceField coneCenter="0 0 0" coneHeight="0 2 0" coneAngle="30"
                                          stiffness="2000" damping="1"/>)",
                                   "0 0 0", "3"));
    EXPECT_THAT(
        scene::describe_scene(*s),
        HasSubstr("cone apex (0, 0, 0) m, axis (0, 2, 0) m, half-angle 30 deg, stiffness 2000 N/m, damping 1 N s/m"));
    for (int i = 0; i < 600; ++i) s->step();  // Rayleigh mass damping e^(−3 t) settles them
    const Vec3Object& x = dofs(*s);
    // the depth outside the cone of each particle: |f| of a unit-stiffness cone at rest
    ConicalForceFieldParameters unit_cone;
    unit_cone.height = Vec3(0, 2, 0);
    unit_cone.angle_deg = 30.0;
    unit_cone.stiffness = 1.0;
    Vec3Object probe;
    probe.position = x.position;
    probe.init();
    ConicalForceField depth_of(probe, unit_cone);
    depth_of.accumulate_force();
    for (std::size_t i = 0; i < x.position.size(); ++i) {
        EXPECT_TRUE(x.position[i].allFinite());
        EXPECT_LT(probe.force[i].norm(), 1e-4) << "particle " << i << " at " << x.position[i].transpose();
        EXPECT_LT(x.velocity[i].norm(), 1e-3);
    }
    EXPECT_EQ(x.position[3], Vec3(0.2, 1, 0));  // never outside: never moved
}

TEST(ExternalLoadComponents, SofaFallbacksAndErrors) {
    // negative stiffness: SOFA's init warns and uses 500
    auto s = build(particles_scene("0 0 0", R"(<PlaneForceField stiffness="-3" localRange="4 2"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("stiffness 500 N/m, damping 5 N s/m"));
    const std::vector<std::string> w = s->warnings();
    EXPECT_TRUE(std::any_of(w.begin(), w.end(),
                            [](const std::string& x) { return x.find("SOFA uses 500") != std::string::npos; }));
    EXPECT_TRUE(std::any_of(w.begin(), w.end(),
                            [](const std::string& x) { return x.find("localRange") != std::string::npos; }));
    // ends that are not ints are the attribute's error, never a conversion out of range
    for (const char* range : {"0 1e19", "-1e10 2", "0.5 2"}) {
        try {
            (void)build(particles_scene("0 0 0", "<PlaneForceField localRange=\"" + std::string(range) + "\"/>"));
            ADD_FAILURE() << range << " was accepted";
        } catch (const io::SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(
                          "PlaneForceField: attribute 'localRange': expected integers from -2147483648 to 2147483647"),
                      std::string::npos)
                << e.what();
        }
    }
    // no force given, a count mismatch, an index out of range, a Rigid3d template
    EXPECT_THROW(build(particles_scene("0 0 0", "<ConstantForceField indices='0'/>")), io::SceneError);
    EXPECT_THROW(
        build(particles_scene("0 0 0  1 1 1", "<ConstantForceField indices='0 1' forces='1 0 0  0 1 0  0 0 1'/>")),
        io::SceneError);
    EXPECT_THROW(build(particles_scene("0 0 0", "<ConstantForceField indices='1' forces='1 0 0'/>")), io::SceneError);
    EXPECT_THROW(build(particles_scene("0 0 0", "<PlaneForceField template='Rigid3d'/>")), io::SceneError);
    EXPECT_THROW(build(particles_scene("0 0 0", "<PlaneForceField localRange='1 2 3'/>")), io::SceneError);
}

}  // namespace
