#pragma once
// The scenes and readers of the force-field family tests (test_force_field_family_components.cpp,
// test_hyperelasticity.cpp, test_interaction_force_fields.cpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <string>
#include "penalty/mechanics/interaction_ellipsoid.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

namespace penalty::test_family_scenes {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

inline std::string with_text(std::string xml, const std::string& what, const std::string& by) {
    xml.replace(xml.find(what), what.size(), by);
    return xml;
}

inline const Vec3Object& family_state(const scene::Scene& s, std::size_t i) {
    return dynamic_cast<const Vec3Object&>(*s.states()[i].state);
}

// Points falling onto a sphere carried by a rigid frame at (0, 0, 0) (SOFA's example scene's
// layout: the frame in its own node with an explicit solver, translations fixed).
inline const std::string kEllipsoidScene = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Obstacle"><EulerExplicitSolver/>
    <MechanicalObject name="frame" template="Rigid3" position="0 0 0 0 0 0 1"/>
    <UniformMass totalMass="1"/>
    <PartialFixedProjectiveConstraint indices="0" fixedDirections="1 1 1 0 0 0"/>
  </Node>
  <Node name="Points"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0 1.2 0  0.3 1.1 0  5 5 5"/>
    <UniformMass vertexMass="0.1"/>
    <InteractionEllipsoidForceField name="ellipsoid" template="Vec3,Rigid3" object1="@dofs" object2="@../Obstacle/frame"
        stiffness="100" damping="1" center="0 0 0" vradius="1 1 1" object2_forces="false"/>
  </Node>
</Node>)";

inline const std::string kHexahedronScene = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Block"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <RegularGridTopology nx="3" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="1" zmin="0" zmax="1"/>
    <MechanicalObject name="dofs"/>
    <UniformMass vertexMass="0.1"/>
    <HexahedronFEMForceField name="FEM" method="METHOD" youngModulus="2000" poissonRatio="0.3"/>
    <FixedProjectiveConstraint indices="0 3 6 9"/>
  </Node>
</Node>)";

// A hyperelastic cantilever: a grid's hexahedra split into tetrahedra by Hexa2TetraTopologicalMapping
// in a child node whose input links to the parent node (`input="@../"`, SOFA's example layout).
inline const std::string kHyperelasticScene = R"(<Node name="root" dt="0.005" gravity="0 -9 0">
  <Node name="Beam"><EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-20"/>
    <RegularGridTopology name="grid" min="0 0 0" max="1 1 2" n="2 2 3"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <Node name="tetras">
      <MeshTopology name="Container"/>
      <Hexa2TetraTopologicalMapping input="@../" output="@Container"/>
      <TetrahedronHyperelasticityFEMForceField name="FEM" ParameterSet="3448 31034" materialName="MATERIAL"/>
    </Node>
    <FixedProjectiveConstraint indices="0 1 2 3"/>
  </Node>
</Node>)";

}  // namespace penalty::test_family_scenes
