// TriangleFEMForceField through a topological change: SOFA's keeps no topology data (init sizes its
// per-triangle vectors, its loops read the topology's current triangles), so a slot keeps the rest
// data of the triangle first there; `--fix-sofa-quirk triangle_fem_slot_data` makes every
// triangle's data again, as a fresh scene.
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/triangular_fem.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace penalty {
namespace {

/// A 3 × 2 sheet under TriangleFEMForceField (large) losing triangles 0 and 4 at t = 0.03 (the
/// last two move into their slots; point 3 goes, point 11 takes its index).
std::string slot_data_sheet() {
    const auto file =
        std::filesystem::temp_directory_path() / ("penalty_triangle_fem_slots_" + std::to_string(::getpid()) + ".txt");
    std::ofstream(file) << "T= 0.03\n  REMOVE= 2\n0 4\n";
    return R"(<Node name="root" gravity="0 0 -9.81" dt="0.01">
  <DefaultAnimationLoop/>
  <Node name="sheet">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <TriangleSetTopologyContainer name="surface" position="0 0 0 1 0 0 2 0 0 3 0 0 0 1 0 1 1 0 2 1 0 3 1 0 0 2 0 1 2 0 2 2 0 3 2 0"
      triangles="0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 4 5 9 4 9 8 5 6 10 5 10 9 6 7 11 6 11 10"/>
    <TriangleSetTopologyModifier/>
    <MechanicalObject name="dofs"/>
    <UniformMass vertexMass="0.1"/>
    <FixedProjectiveConstraint indices="0 8"/>
    <TriangleFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>
    <TopologicalChangeProcessor filename=")" +
           file.string() + R"("/>
  </Node>
</Node>)";
}

Vec3Object& slot_state(scene::Scene& s) { return dynamic_cast<Vec3Object&>(*s.states().at(0).state); }

TriangularFEMForceField& slot_fem(scene::Scene& s) {
    for (const auto& child : s.simulation().root().children())
        for (const auto& f : child->force_fields())
            if (auto* t = dynamic_cast<TriangularFEMForceField*>(f.get())) return *t;
    throw std::logic_error("no TriangleFEMForceField");
}

// SOFA HEAD (2a278d8), the same scene and change file, `sofa-head SCENE 20 OUT --every 1`, after
// 10 steps: bit for bit (a rebuild of the moved triangles' data parted by 1.7e-2 at step 4).
TEST(TriangleFemSlotData, SlotsKeepTheirDataAsSofaHead) {
    auto s = test::build(slot_data_sheet());
    for (int k = 0; k < 10; ++k) s->step();
    const std::vector<Vec3>& x = slot_state(*s).position;
    ASSERT_EQ(x.size(), 11U);
    EXPECT_EQ(slot_fem(*s).triangles().size(), 10U);
    EXPECT_EQ(slot_fem(*s).rest_areas().size(), 12U);  // init's slots
    EXPECT_EQ(x[3], Vec3(2.9209885981129124, 1.8590530306166404, -0.05373799223538319));
    EXPECT_EQ(x[10], Vec3(2.0005862154723264, 2.0682021002650286, -0.053620450423295524));
}

TEST(TriangleFemSlotData, TheQuirkFixMakesTheDataOfTheChangedTriangles) {
    scene::BuildOptions fixed;
    fixed.sofa_quirk_fixes.fix_triangle_fem_slot_data = true;
    auto s = test::build(slot_data_sheet(), fixed);
    for (int k = 0; k < 4; ++k) s->step();
    TriangularFEMForceField& changed = slot_fem(*s);
    Vec3Object& x = slot_state(*s);
    ASSERT_EQ(changed.triangles().size(), 10U);
    ASSERT_EQ(changed.rest_areas().size(), 10U);
    // the forces of the same force field built on the changed sheet
    TriangularFEMForceField fresh(x, s->topology_container("surface").mesh(), changed.parameters());
    fresh.init();
    std::vector<Vec3> f1(x.num_dofs(), Vec3::Zero()), f2(x.num_dofs(), Vec3::Zero());
    changed.add_force(f1, x.position, x.velocity);
    fresh.add_force(f2, x.position, x.velocity);
    EXPECT_EQ(f1, f2);
}

}  // namespace
}  // namespace penalty
