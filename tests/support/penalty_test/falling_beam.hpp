#pragma once
// The falling beam of the live-engine tests (tests/scene/test_live_engine*.cpp): a 5x2x2 grid of
// springs under gravity, implicit Euler, with the components `extra` (engines and their readers)
// appended to its node `/Beam`, whose state is `dofs`, and `before_springs` put before its
// MeshSpringForceField (SOFA sums the node's force fields before the springs, which are interaction
// force fields: a load placed there is summed in SOFA's order).
#include <string>

namespace penalty::test {

inline std::string falling_beam(const std::string& extra, const std::string& before_springs = "") {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="5" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="0.5" zmin="0" zmax="0.5"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
)" + before_springs +
           R"(    <MeshSpringForceField stiffness="200" damping="0.1"/>
)" + extra +
           R"(  </Node>
</Node>)";
}

}  // namespace penalty::test
