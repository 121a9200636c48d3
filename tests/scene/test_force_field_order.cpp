// A node sums its force fields in SOFA's visiting order (Node::for_each_force_field): the fields
// that are not SOFA interaction force fields first, then the interaction ones (SpringForceField and
// the fields made of it), each group in scene order, as BaseMechanicalVisitor::processNodeTopDown
// visits a node's forceField list before its interactionForceField list. The trajectory is SOFA
// HEAD's (2a278d8, `sofa-head SCENE 100 OUT`, %.17g), bit for bit.
#include "penalty/scene/live_data.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

using namespace penalty;

/// A cantilever of springs (5x2x2, its x = 0 end fixed) under gravity and a ConstantForceField,
/// written before or after the MeshSpringForceField, the UniformMass first or last.
std::string loaded_cantilever(bool load_after_springs, bool mass_last = false) {
    const std::string mass = R"(    <UniformMass totalMass="1"/>
)";
    const std::string load = R"(    <ConstantForceField totalForce="0.3 0.7 0.1"/>
)";
    const std::string springs = R"(    <MeshSpringForceField stiffness="200" damping="0.1"/>
)";
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="5" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="0.5" zmin="0" zmax="0.5"/>
    <MechanicalObject name="dofs"/>
)" + (mass_last ? "" : mass) +
           (load_after_springs ? springs + load : load + springs) + (mass_last ? mass : "") +
           R"(    <FixedProjectiveConstraint indices="0 5 10 15"/>
  </Node>
</Node>)";
}

std::vector<Vec3> after_100_steps(bool load_after_springs, bool mass_last = false) {
    auto s = test::build(loaded_cantilever(load_after_springs, mass_last));
    for (int k = 0; k < 100; ++k) s->step();
    return dynamic_cast<const Vec3Object&>(*s->data({"/Beam/dofs", false}, "position").state).position;
}

TEST(ForceFieldOrder, ALoadWrittenAfterTheSpringsIsSummedBeforeThemAsSofaHead) {
    const std::vector<Vec3> x = after_100_steps(/*load_after_springs=*/true);
    // SOFA HEAD's states are the same bits for both orders
    EXPECT_EQ(x[4], Vec3(1.9669772746110656, -0.16710226356998234, 0.0019035163793548672));
    EXPECT_EQ(x[9], Vec3(2.019543701763174, 0.33011205482735045, 0.0018122412780767116));
    EXPECT_EQ(x[19], Vec3(2.0189666402939697, 0.33014119351452675, 0.5019153655836591));
    EXPECT_EQ(x, after_100_steps(/*load_after_springs=*/false));
}

TEST(ForceFieldOrder, TheSpringsAreAGroupOfTheirOwnInSofaHeadsMappingGraph) {
    // SOFA HEAD's MappingGraph sums each node's mass and force fields as written, grouped by the
    // states each lists (getMechanicalStates): a SOFA interaction field lists its state twice, so
    // the springs form their own group and a mass written after them (load, springs, mass) is
    // summed with the load before them: SOFA HEAD's states are the mass-first test's bits
    EXPECT_EQ(after_100_steps(/*load_after_springs=*/false, /*mass_last=*/true),
              after_100_steps(/*load_after_springs=*/true));
}

}  // namespace
