// SOFA's renamed components: a scene written with a component's name of before a rename builds the
// component of the new name, as SOFA's ObjectFactory::createObject does (it looks the class name up
// in sofa::helper::lifecycle::renamedComponents, ComponentChange.cpp, and creates the new class).
#include "penalty/scene/components.hpp"

#include <array>
#include <string_view>
#include <utility>

namespace penalty::scene {
namespace {

struct SofaRename {
    std::string_view old_name, new_name, since;
};

// SOFA's renamedComponents table (old name, new name, version of the rename).
constexpr std::array<SofaRename, 31> kSofaRenames = {{
    {"AffineMovementConstraint", "AffineMovementProjectiveConstraint", "v24.06"},
    {"AttachConstraint", "AttachProjectiveConstraint", "v24.06"},
    {"FixedConstraint", "FixedProjectiveConstraint", "v24.06"},
    {"FixedPlaneConstraint", "FixedPlaneProjectiveConstraint", "v24.06"},
    {"FixedRotationConstraint", "FixedRotationProjectiveConstraint", "v24.06"},
    {"FixedTranslationConstraint", "FixedTranslationProjectiveConstraint", "v24.06"},
    {"HermiteSplineConstraint", "HermiteSplineProjectiveConstraint", "v24.06"},
    {"LinearMovementConstraint", "LinearMovementProjectiveConstraint", "v24.06"},
    {"LinearVelocityConstraint", "LinearVelocityProjectiveConstraint", "v24.06"},
    {"OscillatorConstraint", "OscillatorProjectiveConstraint", "v24.06"},
    {"ParabolicConstraint", "ParabolicProjectiveConstraint", "v24.06"},
    {"PartialFixedConstraint", "PartialFixedProjectiveConstraint", "v24.06"},
    {"PartialLinearMovementConstraint", "PartialLinearMovementProjectiveConstraint", "v24.06"},
    {"PatchTestMovementConstraint", "PatchTestMovementProjectiveConstraint", "v24.06"},
    {"PositionBasedDynamicsConstraint", "PositionBasedDynamicsProjectiveConstraint", "v24.06"},
    {"SkeletalMotionConstraint", "SkeletalMotionProjectiveConstraint", "v24.06"},
    {"ProjectToLineConstraint", "LineProjectiveConstraint", "v24.06"},
    {"ProjectToPlaneConstraint", "PlaneProjectiveConstraint", "v24.06"},
    {"ProjectToPointConstraint", "PointProjectiveConstraint", "v24.06"},
    {"ProjectDirectionConstraint", "DirectionProjectiveConstraint", "v24.06"},
    {"BilateralInteractionConstraint", "BilateralLagrangianConstraint", "v24.06"},
    {"SlidingConstraint", "SlidingLagrangianConstraint", "v24.06"},
    {"StopperConstraint", "StopperLagrangianConstraint", "v24.06"},
    {"UniformConstraint", "UniformLagrangianConstraint", "v24.06"},
    {"UnilateralInteractionConstraint", "UnilateralLagrangianConstraint", "v24.06"},
    {"StiffSpringForceField", "SpringForceField", "v24.06"},
    {"ParallelStiffSpringForceField", "ParallelSpringForceField", "v24.06"},
    {"ShewchukPCGLinearSolver", "PCGLinearSolver", "v24.12"},
    {"OglCylinderModel", "CylinderVisualModel", "v24.12"},
    {"TriangleOctreeModel", "TriangleOctreeCollisionModel", "v25.12"},
    {"VolumeFromTetrahedrons", "VolumeFromVolumetricElements", "v26.12"},
}};

void rename_in(io::SceneNode& node, std::vector<std::string>& notes) {
    for (auto& c : node.components) {
        if (find_component(c->type) != nullptr) continue;  // penalty knows the name itself
        for (const SofaRename& r : kSofaRenames) {
            if (c->type != r.old_name || find_component(r.new_name) == nullptr) continue;
            notes.push_back(c->file + ":" + std::to_string(c->line) + ": " + std::string(r.old_name) +
                            " is SOFA's name before " + std::string(r.since) + " of " + std::string(r.new_name) +
                            ", which SOFA creates in its place (renamedComponents): so does penalty");
            c->type = std::string(r.new_name);
            break;
        }
    }
    for (auto& child : node.children) rename_in(*child, notes);
}

}  // namespace

std::vector<std::string> apply_sofa_renames(io::SceneFile& scene) {
    std::vector<std::string> notes;
    if (scene.root) rename_in(*scene.root, notes);
    return notes;
}

}  // namespace penalty::scene
