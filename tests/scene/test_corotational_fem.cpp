// TetrahedralCorotationalFEMForceField as a scene component: a clamped beam of 12 tetrahedra
// (a 3×2×2-vertex grid cut into Kuhn tetrahedra, written into the scene) built from a .scn,
// described, run, and compared with the same beam under TetrahedronFEMForceField.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/scene.hpp"

#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/scene_text.hpp"
#include "penalty_test/twelve_tetrahedra_beam.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace {

using namespace penalty;
using ::testing::HasSubstr;

/// A beam [0, 2]×[0, 0.5]×[0, 0.5] of tetrahedra, fixed at x = 0, with `force_field` (XML) in its
/// node, written before its UniformMass when `mass_last`.
std::string beam_scene(const std::string& force_field, bool mass_last = false) {
    const RegularGridTopology grid({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 0.5, 0.5));
    const MeshTopology topo = test::kuhn_tetrahedra(grid);
    std::ostringstream positions, tetrahedra, fixed;
    positions.precision(17);
    for (const Vec3& p : grid.points()) positions << p.x() << ' ' << p.y() << ' ' << p.z() << "  ";
    for (const auto& t : topo.tetrahedra()) tetrahedra << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << "  ";
    for (std::size_t i = 0; i < grid.points().size(); ++i)
        if (grid.points()[i].x() == 0) fixed << i << ' ';
    return R"(<Node name="root" dt="0.02" gravity="0 -9.81 0">
      <Node name="Beam"><EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
        <CGLinearSolver iterations="200" tolerance="1e-14" threshold="1e-14"/>
        <TetrahedronSetTopologyContainer name="topo" position=")" +
           positions.str() + R"(" tetrahedra=")" + tetrahedra.str() + R"("/>
        <MechanicalObject name="beam"/>
        )" +
           (mass_last ? force_field : std::string()) + R"(
        <UniformMass totalMass="2"/>
        <FixedProjectiveConstraint indices=")" +
           fixed.str() + R"("/>
        )" +
           (mass_last ? std::string() : force_field) + R"(
      </Node>
    </Node>)";
}

using penalty::test::build;

std::vector<Vec3> positions_after(scene::Scene& s, int steps) {
    for (int i = 0; i < steps; ++i) s.step();
    const auto& beam = dynamic_cast<const Vec3Object&>(*s.states()[0].state);
    for (const Vec3& p : beam.position) EXPECT_TRUE(p.allFinite());
    return beam.position;
}

double lowest_y(const std::vector<Vec3>& x) {
    double lowest = 0;
    for (const Vec3& p : x) lowest = std::min(lowest, p.y());
    return lowest;
}

double max_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double d = 0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
    return d;
}

TEST(CorotationalFemComponent, BuildsDescribesAndRunsLikeTetrahedronFem) {
    auto s = build(beam_scene(
        R"(<TetrahedralCorotationalFEMForceField name="fem" youngModulus="2000" poissonRatio="0.3" method="large" assembling="0"/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("12 tetrahedra, E = 2000 Pa, nu = 0.3, corotational (large)"));
    const std::vector<Vec3> x = positions_after(*s, 60);
    const double sag = lowest_y(x);
    EXPECT_LT(sag, -0.01);  // it bends under gravity
    EXPECT_GT(sag, -1.0);   // and the elasticity holds it
    // with method large, SOFA's two tetrahedral FEMs make the same operations in the same order
    // (initLarge, computeMaterialStiffness, accumulateForceLarge, computeForce, and
    // applyStiffnessLarge / applyStiffnessCorotational): the same bits
    auto reference =
        build(beam_scene(R"(<TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>)"));
    EXPECT_EQ(x, positions_after(*reference, 60)) << "sag " << sag;
}

TEST(CorotationalFemComponent, DefaultsMethodsAndOptions) {
    auto s = build(beam_scene(R"(<TetrahedralCorotationalFEMForceField/>)"));
    EXPECT_THAT(scene::describe_scene(*s), HasSubstr("12 tetrahedra, E = 5000 Pa, nu = 0.45, corotational (large)"));
    for (const char* method : {"small", "polar"}) {
        auto m = build(beam_scene(std::string(R"(<TetrahedralCorotationalFEMForceField youngModulus="2000" method=")") +
                                  method + R"("/>)"));
        EXPECT_THAT(scene::describe_scene(*m), HasSubstr(std::string("(") + method + ")"));
        EXPECT_LT(lowest_y(positions_after(*m, 20)), -1e-3);
    }
    // updateStiffnessMatrix changes the trajectory (J of the current shape), localStiffnessFactor stiffens it
    auto plain = build(beam_scene(R"(<TetrahedralCorotationalFEMForceField youngModulus="500"/>)"));
    auto updated =
        build(beam_scene(R"(<TetrahedralCorotationalFEMForceField youngModulus="500" updateStiffnessMatrix="1"/>)"));
    auto stiffer =
        build(beam_scene(R"(<TetrahedralCorotationalFEMForceField youngModulus="500" localStiffnessFactor="4"/>)"));
    EXPECT_THAT(scene::describe_scene(*updated), HasSubstr("stiffness updated each step"));
    const std::vector<Vec3> x_plain = positions_after(*plain, 40);
    const std::vector<Vec3> x_updated = positions_after(*updated, 40);
    const std::vector<Vec3> x_stiffer = positions_after(*stiffer, 40);
    EXPECT_GT(max_distance(x_plain, x_updated), 1e-6);
    EXPECT_LT(max_distance(x_plain, x_updated), 0.1 * std::abs(lowest_y(x_plain)));
    EXPECT_GT(lowest_y(x_stiffer), lowest_y(x_plain));  // 4× stiffer: less sag
    // unknown method text is large, as SOFA (with a build note)
    auto odd = build(beam_scene(R"(<TetrahedralCorotationalFEMForceField youngModulus="500" method="qr"/>)"));
    EXPECT_LT(max_distance(positions_after(*odd, 40), x_plain), 1e-15);
    EXPECT_THROW(build(beam_scene(R"(<TetrahedralCorotationalFEMForceField poissonRatio="0.5"/>)")), io::SceneError);
    EXPECT_THROW(build(beam_scene(R"(<TetrahedralCorotationalFEMForceField youngModulus="-3"/>)")), io::SceneError);
}

TEST(CorotationalFemComponent, MethodLargeIsSofaHeadBitForBit) {
    // SOFA HEAD's states (2a278d8, `sofa-head SCENE 50 OUT`, %.17g) after 50 steps of the beam
    // with its field written before its mass: SOFA's operations in SOFA's order
    // (tetrahedron_large_element.hpp), the mass summed at its place among the node's force fields
    // (Node::for_each_mass_and_force_field)
    auto s = build(beam_scene(
        R"(<TetrahedralCorotationalFEMForceField name="fem" youngModulus="2000" poissonRatio="0.3" method="large"/>)",
        /*mass_last=*/true));
    const std::vector<Vec3> x = positions_after(*s, 50);
    EXPECT_EQ(x[2], Vec3(1.924841317292595, -0.3760443121576634, 0.05820315594375248));
    EXPECT_EQ(x[5], Vec3(2.026678477432562, 0.11717442855410949, 0.0534493529609775));
    EXPECT_EQ(x[7], Vec3(0.9425930874346609, -0.15158111379640754, 0.5203399201911084));
    EXPECT_EQ(x[11], Vec3(2.0090436289539686, 0.12676949854579228, 0.5512625353183959));
}

TEST(CorotationalFemComponent, MethodsSmallAndPolarAreSofaHeadBitForBit) {
    // the twelve-tetrahedra beam, SOFA HEAD's states (2a278d8, `sofa-head SCENE 100 OUT`, %.17g)
    // after 100 steps: initSmall / accumulateForceSmall / applyStiffnessSmall and initPolar /
    // accumulateForcePolar / applyStiffnessPolar in SOFA's order (tetrahedron_large_element.hpp)
    for (const auto& [method, sofa] :
         {std::pair{"small", &test::kSofaHeadSmallBeam100}, std::pair{"polar", &test::kSofaHeadPolarBeam100}}) {
        SCOPED_TRACE(method);
        auto s = build(test::twelve_tetrahedra_beam(std::string("method=\"") + method + "\"",
                                                    "TetrahedralCorotationalFEMForceField"));
        EXPECT_EQ(positions_after(*s, 100), *sofa);
    }
}

}  // namespace
