#pragma once
// The scenes and readers of the engine and mapping component tests (test_engine_and_mapping_components.cpp,
// test_transform_engines.cpp, test_selection_engines.cpp, test_frame_mappings.cpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <string>
#include "penalty/io/error.hpp"
#include "penalty/mechanics/frame_mappings.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/output/state_record.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

namespace penalty::test_engine_scenes {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

inline const Vec3Object& engine_state(const scene::Scene& s, std::size_t i = 0) {
    return dynamic_cast<const Vec3Object&>(*s.states()[i].state);
}

inline std::string with(std::string xml, const std::string& what, const std::string& by) {
    xml.replace(xml.find(what), what.size(), by);
    return xml;
}

// A state whose positions come from a data engine defined before it (or after it: SOFA's engines
// are evaluated when read).
inline const std::string kEngineScene = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    ENGINE
    <MechanicalObject name="dofs" position="@engine.output_position"/>
    <UniformMass vertexMass="1"/>
  </Node>
</Node>)";

// A unit cube surface (the ROI mesh) and points inside and outside it.
inline const std::string kMeshRoi = R"(<Node name="root" dt="0.01" gravity="0 0 0">
  <Node name="Body"><EulerImplicitSolver/><CGLinearSolver iterations="10" tolerance="1e-12" threshold="1e-20"/>
    <MechanicalObject name="dofs" position="0.2 0.3 0.45  2 2 2  0.7 0.1 0.9  -0.3 0.5 0.5"/>
    <UniformMass vertexMass="1"/>
    <MeshROI name="roi" ROIposition="0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1"
             ROItriangles="0 2 3 0 3 1 4 5 7 4 7 6 0 1 5 0 5 4 2 6 7 2 7 3 0 4 6 0 6 2 1 3 7 1 7 5" ATTR/>
    <FixedProjectiveConstraint indices="@roi.indices"/>
  </Node>
</Node>)";

// A rigid frame carrying mapped points that have a mass: the frame (1 kg) and 4 points (0.5 kg
// each) fall together under gravity, the points' mass acting through the mapping (Jᵀ M J).
inline const std::string kMappedMass = R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="Body"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
    <CGLinearSolver iterations="50" tolerance="1e-14" threshold="1e-30"/>
    <MechanicalObject template="Rigid3" name="frame" position="0 0 0 0 0 0 1"/>
    <UniformMass vertexMass="1"/>
    <Node name="Points"><MechanicalObject name="points" position="1 0 0  -1 0 0  0 0 1  0 0 -1"/>
      <UniformMass vertexMass="0.5"/>
      <ConstantForceField indices="0" forces="6 0 0"/>
      <RigidMapping/>
    </Node>
  </Node>
</Node>)";

}  // namespace penalty::test_engine_scenes
