#pragma once
// A beam of twelve tetrahedra under TetrahedronFEMForceField, its x = 0 end fixed, sagging under
// gravity: the scene of the tests that compare the field's methods with SOFA HEAD's states
// (tests/scene/test_fem.cpp, test_tetrahedron_plasticity.cpp).
#include <string>

namespace penalty::test {

/// The beam [0,1]×[0,0.5]×[0,0.5]: 3×2×2 points, two cubes of six tetrahedra; `fem` the
/// TetrahedronFEMForceField's extra attributes.
inline std::string twelve_tetrahedra_beam(const std::string& fem) {
    return R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="100" tolerance="1e-12" threshold="1e-12"/>
    <MeshTopology name="topo" position="0 0 0 0.5 0 0 1 0 0 0 0.5 0 0.5 0.5 0 1 0.5 0 0 0 0.5 0.5 0 0.5 1 0 0.5 0 0.5 0.5 0.5 0.5 0.5 1 0.5 0.5" tetrahedra="0 1 4 10 0 1 7 10 0 3 4 10 0 3 9 10 0 6 7 10 0 6 9 10 1 2 5 11 1 2 8 11 1 4 5 11 1 4 10 11 1 7 8 11 1 7 10 11"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="2"/>
    <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.3" )" +
           fem + R"(/>
    <FixedProjectiveConstraint indices="0 3 6 9"/>
  </Node>
</Node>)";
}

}  // namespace penalty::test
