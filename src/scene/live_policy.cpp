// When a write of a Data after init takes effect (LiveWrite): one table for every component type,
// from SOFA's behaviour (its Data callbacks, what its components read every step, what only their
// init()/reinit() read), checked against SOFA HEAD through SofaPython3 for the Data of
// tests/python/test_live_data.py (docs/python.md, "Writing a Data after init").
#include "scene/live_policy.hpp"

#include "penalty/scene/components.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <string>

namespace penalty::scene {

namespace {

using namespace std::string_view_literals;

struct Rule {
    std::string_view type;  ///< component type ("*": any)
    std::string_view name;  ///< Data name
    LiveWrite live;
};

/// Data SOFA's component takes at the next step, by itself: read every step (solvers, constant
/// loads, contact parameters), a Data callback (UniformMass, DiagonalMass, SpringForceField,
/// ConstantForceField), an engine's update (BoxROI's inputs), a constraint reading its indices at
/// each projection. Every other Data penalty reads is taken at the component's reinit() (the FEM
/// force fields' youngModulus: SOFA HEAD leaves the element stiffnesses as they are until
/// reinit()), except those of kRefused.
constexpr Rule kNextStep[] = {
    {"EulerImplicitSolver", "rayleighStiffness", LiveWrite::next_step},
    {"EulerImplicitSolver", "rayleighMass", LiveWrite::next_step},
    {"EulerImplicitSolver", "vdamping", LiveWrite::next_step},
    {"EulerImplicitSolver", "firstOrder", LiveWrite::next_step},
    {"EulerImplicitSolver", "trapezoidalScheme", LiveWrite::next_step},
    {"EulerImplicitSolver", "solveConstraint", LiveWrite::next_step},
    {"EulerImplicitSolver", "newton", LiveWrite::next_step},
    {"EulerImplicitSolver", "newtonIterations", LiveWrite::next_step},
    {"EulerImplicitSolver", "newtonTolerance", LiveWrite::next_step},
    {"EulerExplicitSolver", "symplectic", LiveWrite::next_step},
    {"CGLinearSolver", "iterations", LiveWrite::next_step},
    {"CGLinearSolver", "tolerance", LiveWrite::next_step},
    {"CGLinearSolver", "threshold", LiveWrite::next_step},
    {"UniformMass", "totalMass", LiveWrite::next_step},
    {"UniformMass", "vertexMass", LiveWrite::next_step},
    {"DiagonalMass", "totalMass", LiveWrite::next_step},
    {"DiagonalMass", "massDensity", LiveWrite::next_step},
    {"MeshSpringForceField", "stiffness", LiveWrite::next_step},
    {"MeshSpringForceField", "damping", LiveWrite::next_step},
    {"SpringForceField", "stiffness", LiveWrite::next_step},
    {"SpringForceField", "damping", LiveWrite::next_step},
    {"SpringForceField", "length", LiveWrite::next_step},
    {"SpringForceField", "lengths", LiveWrite::next_step},
    {"SpringForceField", "indices1", LiveWrite::next_step},
    {"SpringForceField", "indices2", LiveWrite::next_step},
    {"ConstantForceField", "force", LiveWrite::next_step},
    {"ConstantForceField", "forces", LiveWrite::next_step},
    {"ConstantForceField", "totalForce", LiveWrite::next_step},
    {"ConstantForceField", "indices", LiveWrite::next_step},
    {"PlaneForceField", "normal", LiveWrite::next_step},
    {"PlaneForceField", "d", LiveWrite::next_step},
    {"PlaneForceField", "stiffness", LiveWrite::next_step},
    {"PlaneForceField", "damping", LiveWrite::next_step},
    {"PlaneForceField", "maxForce", LiveWrite::next_step},
    {"PlaneForceField", "bilateral", LiveWrite::next_step},
    {"FixedProjectiveConstraint", "indices", LiveWrite::next_step},
    {"FixedProjectiveConstraint", "fixAll", LiveWrite::next_step},
    {"FixedConstraint", "indices", LiveWrite::next_step},
    {"FixedConstraint", "fixAll", LiveWrite::next_step},
    {"FixedProjectiveConstraint", "activate_projectVelocity", LiveWrite::next_step},  // read by projectVelocity
    {"FixedConstraint", "activate_projectVelocity", LiveWrite::next_step},
    {"FixedPlaneProjectiveConstraint", "indices", LiveWrite::next_step},
    {"FixedPlaneProjectiveConstraint", "direction", LiveWrite::next_step},
    {"FixedPlaneProjectiveConstraint", "dmin", LiveWrite::next_step},
    {"FixedPlaneProjectiveConstraint", "dmax", LiveWrite::next_step},
    {"FixedPlaneConstraint", "indices", LiveWrite::next_step},
    {"FixedPlaneConstraint", "direction", LiveWrite::next_step},
    {"FixedPlaneConstraint", "dmin", LiveWrite::next_step},
    {"FixedPlaneConstraint", "dmax", LiveWrite::next_step},
    {"Gravity", "gravity", LiveWrite::next_step},
    {"CollisionResponse", "response", LiveWrite::next_step},
    {"CollisionResponse", "responseParams", LiveWrite::next_step},
};

/// Data of the families whose components read them at every step: collision models (SOFA's
/// contacts take the models' contactStiffness when they are made, each step), intersection
/// methods and engines (BoxROI's, TransformEngine's inputs make their outputs dirty, read again by
/// the components and states linked to them: live_links.cpp).
constexpr std::array kNextStepFamilies = {ComponentFamily::collision_model, ComponentFamily::intersection,
                                          ComponentFamily::engine, ComponentFamily::data_engine};

/// Data SOFA reads at init only (its reinit() too keeps what init made): RegularGridSpringForceField
/// keeps the springs its init() made from the grid (SOFA HEAD ignores a write of its stiffness, even
/// after reinit()).
constexpr Rule kRefused[] = {
    {"RegularGridSpringForceField", "stiffness", LiveWrite::refused},
    {"RegularGridSpringForceField", "damping", LiveWrite::refused},
    {"RegularGridSpringForceField", "linesStiffness", LiveWrite::refused},
    {"RegularGridSpringForceField", "linesDamping", LiveWrite::refused},
    {"RegularGridSpringForceField", "quadsStiffness", LiveWrite::refused},
    {"RegularGridSpringForceField", "quadsDamping", LiveWrite::refused},
    {"RegularGridSpringForceField", "cubesStiffness", LiveWrite::refused},
    {"RegularGridSpringForceField", "cubesDamping", LiveWrite::refused},
};

/// The state vectors of a MechanicalObject.
constexpr std::array kStateVectors = {"position"sv, "velocity"sv, "force"sv, "rest_position"sv, "externalForce"sv};

/// Data of every component that change nothing simulated.
bool is_cosmetic(std::string_view name) {
    static constexpr std::array names = {"printLog"sv, "tags"sv,     "bbox"sv,    "listening"sv, "componentState"sv,
                                         "color"sv,    "drawMode"sv, "verbose"sv, "isToPrint"sv, "group"sv};
    if (std::find(names.begin(), names.end(), name) != names.end()) return true;
    for (std::string_view prefix : {"show"sv, "draw"sv, "display"sv})
        if (name.substr(0, prefix.size()) == prefix) return true;
    return false;
}

const Rule* find_rule(std::span<const Rule> rules, std::string_view type, std::string_view name) {
    for (const Rule& r : rules)
        if ((r.type == type || r.type == "*") && r.name == name) return &r;
    return nullptr;
}

}  // namespace

LiveWrite live_policy(std::string_view type, bool node, std::string_view name, const AttributeSpec* spec,
                      const CatalogEntry* sofa, std::string& refusal) {
    if (node) {
        if (name == "dt" || name == "gravity") return LiveWrite::next_step;
        if (name == "time") return LiveWrite::state;
        if (name == "name") {
            refusal = "a node keeps its name after init (penalty finds nodes by their path)";
            return LiveWrite::refused;
        }
        if (name == "activated" || name == "sleeping") {
            refusal = "penalty does not deactivate nodes";
            return LiveWrite::refused;
        }
        return LiveWrite::no_effect;
    }
    if (name == "name") {
        refusal = "a component keeps its name after init (penalty finds components by their path)";
        return LiveWrite::refused;
    }
    if (is_cosmetic(name)) return LiveWrite::no_effect;
    if (type == "MechanicalObject" &&
        std::find(kStateVectors.begin(), kStateVectors.end(), name) != kStateVectors.end())
        return LiveWrite::state;
    if (find_rule(kRefused, type, name) != nullptr) {
        refusal = "SOFA's " + std::string(type) + " reads it at init only (its reinit() keeps what init made)";
        return LiveWrite::refused;
    }
    const bool link = (sofa != nullptr && sofa->link) ||
                      (spec != nullptr && (spec->kind == AttributeKind::link || spec->kind == AttributeKind::links));
    if (link) {
        refusal = "links are resolved at init; SOFA does not re-resolve them";
        return LiveWrite::refused;
    }
    if (spec == nullptr) {
        refusal =
            "penalty does not simulate it (SOFA's " + std::string(type) + " declares it; penalty reads none such)";
        return LiveWrite::refused;
    }
    if (name == "template" || name == "filename" || name == "src" || spec->kind == AttributeKind::elements) {
        refusal = "SOFA reads it at init only (a file, a template or the elements of a topology)";
        return LiveWrite::refused;
    }
    if (find_rule(kNextStep, type, name) != nullptr) return LiveWrite::next_step;
    if (const ComponentSpec* c = find_component(type))
        if (std::find(kNextStepFamilies.begin(), kNextStepFamilies.end(), c->family) != kNextStepFamilies.end())
            return LiveWrite::next_step;
    if (const ComponentSpec* c = find_component(type); c != nullptr && c->family == ComponentFamily::state) {
        refusal = "SOFA's MechanicalObject reads it at init only (write position or rest_position instead)";
        return LiveWrite::refused;
    }
    if (const ComponentSpec* c = find_component(type); c != nullptr && c->family == ComponentFamily::topology) {
        refusal = "SOFA reads a topology's shape at init only";
        return LiveWrite::refused;
    }
    return LiveWrite::reinit;
}

}  // namespace penalty::scene
