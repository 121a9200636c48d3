#pragma once
// The particles of the scene tests of projective constraints, rigid force fields, pressure and
// regions of interest (test_field_and_constraint_components.cpp, test_projective_constraints.cpp,
// test_rigid_force_fields.cpp, test_nonuniform_hexahedra.cpp, test_regions_of_interest.cpp,
// test_tait_pressure.cpp, test_sofa_renames.cpp): particles under gravity with components, a scene's
// Vec3 states.
#include "penalty/io/error.hpp"
#include "penalty/mechanics/beam_fem_force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/component_defaults.hpp"
#include "penalty_test/paths.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

namespace penalty::test_field_scenes {

using penalty::test::build;

inline std::string particles(const std::string& positions, const std::string& components,
                             const std::string& extra_root = "") {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">)" + extra_root + R"(
      <Node name="P"><EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
        <CGLinearSolver iterations="100" tolerance="1e-20" threshold="1e-30"/>
        <MechanicalObject name="dofs" position=")" +
           positions + R"("/>
        <UniformMass vertexMass="2"/>
        )" +
           components + R"(
      </Node>
    </Node>)";
}

inline const Vec3Object& vec3_dofs(const scene::Scene& s, std::size_t i = 0) {
    return dynamic_cast<const Vec3Object&>(*s.states()[i].state);
}

/// Every DOF coordinate of every state of a scene after `steps` steps.
inline std::vector<double> coordinates_after(const std::string& xml, int steps) {
    auto s = build(xml);
    for (int k = 0; k < steps; ++k) s->step();
    std::vector<double> out;
    for (const auto& r : s->states())
        for (const Vec3& p : dynamic_cast<const Vec3Object&>(*r.state).position)
            out.insert(out.end(), {p.x(), p.y(), p.z()});
    return out;
}

}  // namespace penalty::test_field_scenes
