// The component registry (include/penalty/scene/components.hpp): the family tables of
// src/scene/builder/, the loaders and the visual-only types, and what reads them (the scene
// check, the unread-attribute notes, `penalty info --components`).
#include "penalty/scene/components.hpp"

#include "scene/builder/families.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <sstream>

namespace penalty::scene {

namespace {

using F = ComponentFamily;
using K = AttributeKind;

// ---- loaders: read by io::load_scene_mesh (src/io/scene_mesh.cpp), SOFA's MeshLoader Data ----
/// What every mesh loader reads (SOFA's MeshLoader Data).
constexpr AttributeSpec kMeshLoaderAttributes[] = {
    {"filename", K::text, "", "", ValueCheck::none, "mesh file, found next to the scene or in --data-dir"},
    {"translation", K::vector3, "0 0 0", "m", ValueCheck::none, "applied after rotation and scale"},
    {"rotation", K::vector3, "0 0 0", "deg", ValueCheck::none, "Euler angles, X then Y then Z"},
    {"scale3d", K::vector3, "1 1 1", "", ValueCheck::none, "per-axis scale, times `scale`"},
    {"scale", K::text, "1", "", ValueCheck::none,
     "uniform scale, read as a float (SOFA's MeshLoader::parse); not one number: 1, with a note"},
    {"triangulate", K::boolean, "0", "", ValueCheck::none, "split quads into triangles"},
    {"transformation", K::numbers, "(identity)", "", ValueCheck::none, "4x4 matrix; only the identity"},
    {"onlyAttachedPoints", K::boolean, "0", "", ValueCheck::none, "only 0"},
    {"handleSeams", K::boolean, "0", "", ValueCheck::none,
     "OBJ: one point per (texture coordinate, normal) pair of each point; unused points dropped"},
};
constexpr AttributeSpec kObjVtkLoaderAttributes[] = {
    {"flipNormals", K::boolean, "0", "", ValueCheck::none, "reverse the triangles' orientation"},
    {"createSubelements", K::boolean, "0", "", ValueCheck::none, "derive edges and triangles of the volumes"},
};
constexpr AttributeSpec kGmshLoaderAttributes[] = {
    {"flipNormals", K::boolean, "0", "", ValueCheck::none, "ignored for Gmsh, as SOFA"},
    {"createSubelements", K::boolean, "1", "", ValueCheck::none, "derive edges and triangles of the volumes"},
};
constexpr AttributeSpec kTrianLoaderAttributes[] = {
    {"flipNormals", K::boolean, "0", "", ValueCheck::none, "reverse the triangles' orientation"},
    {"createSubelements", K::boolean, "0", "", ValueCheck::none, "derive the edges of the triangles"},
    {"trian2", K::boolean, "0", "", ValueCheck::none, "only 0 (the older trian format)"},
};
constexpr AttributeSpec kSphereLoaderAttributes[] = {
    {"filename", K::text, "", "", ValueCheck::none, ".sph file of centres and radii"},
    {"translation", K::vector3, "0 0 0", "m", ValueCheck::none, "of the centres"},
    {"rotation", K::vector3, "0 0 0", "deg", ValueCheck::none, "of the centres"},
    {"scale", K::vector3, "1 1 1", "", ValueCheck::none, "of the centres (radii unchanged)"},
    {"scale3d", K::vector3, "1 1 1", "", ValueCheck::none, "alias of scale"},
};

/// GridMeshCreator (SOFA's MeshLoader without a file: GridMeshCreator::doLoad).
constexpr AttributeSpec kGridMeshCreatorAttributes[] = {
    {"resolution", K::numbers, "2 2", "", ValueCheck::none, "points along x and y (each >= 2)"},
    {"trianglePattern", K::integer, "2", "", ValueCheck::none,
     "0: quads, 1: alternate triangles, 2: upward triangles, 3: downward triangles"},
    {"translation", K::vector3, "0 0 0", "m", ValueCheck::none, "applied after rotation and scale"},
    {"rotation", K::vector3, "0 0 0", "deg", ValueCheck::none, "Euler angles, X then Y then Z"},
    {"scale3d", K::vector3, "1 1 1", "", ValueCheck::none, "per-axis scale, times `scale`"},
    {"scale", K::real, "1", "", ValueCheck::none, "uniform scale"},
};

constexpr ComponentSpec kLoaders[] = {
    {.type = "GridMeshCreator",
     .family = F::loader,
     .summary = "unit square grid of points, quads or triangles",
     .attributes = kGridMeshCreatorAttributes},
    {.type = "MeshOBJLoader",
     .family = F::loader,
     .summary = "Wavefront OBJ mesh",
     .attributes = kObjVtkLoaderAttributes,
     .shared_attributes = kMeshLoaderAttributes},
    {.type = "MeshGmshLoader",
     .family = F::loader,
     .summary = "Gmsh v1/v2/v4 ASCII mesh",
     .attributes = kGmshLoaderAttributes,
     .shared_attributes = kMeshLoaderAttributes},
    {.type = "MeshOffLoader",
     .family = F::loader,
     .summary = "OFF mesh (triangles and quads)",
     .attributes = kObjVtkLoaderAttributes,
     .shared_attributes = kMeshLoaderAttributes},
    {.type = "MeshTrianLoader",
     .family = F::loader,
     .summary = "SOFA .trian triangle mesh",
     .attributes = kTrianLoaderAttributes,
     .shared_attributes = kMeshLoaderAttributes},
    {.type = "SphereLoader",
     .family = F::loader,
     .summary = "sphere list (.sph)",
     .attributes = kSphereLoaderAttributes},
    {.type = "MeshVTKLoader",
     .family = F::loader,
     .summary = "legacy ASCII VTK mesh",
     .attributes = kObjVtkLoaderAttributes,
     .shared_attributes = kMeshLoaderAttributes},
};

constexpr std::string_view kInertWithoutConstraintSolver =
    "constraint correction: acts only under a constraint solver (FreeMotionAnimationLoop), inert here";
constexpr ComponentSpec kVisual[] = {
    {.type = "RequiredPlugin", .summary = "plugin loading"},
    {.type = "VisualStyle", .summary = "display flags"},
    {.type = "OglModel", .summary = "OpenGL visual model"},
    {.type = "VisualModel", .summary = "visual model"},
    {.type = "VisualModelImpl", .summary = "visual model"},
    {.type = "OglSceneFrame", .summary = "frame drawn in a corner"},
    {.type = "OglLabel", .summary = "text label"},
    {.type = "OglGrid", .summary = "drawn grid"},
    {.type = "VisualGrid", .summary = "drawn grid"},
    {.type = "LineAxis", .summary = "drawn axes"},
    {.type = "InteractiveCamera", .summary = "camera"},
    {.type = "Camera", .summary = "camera"},
    {.type = "LightManager", .summary = "lights"},
    {.type = "DirectionalLight", .summary = "light"},
    {.type = "PositionalLight", .summary = "light"},
    {.type = "SpotLight", .summary = "light"},
    {.type = "BackgroundSetting", .summary = "background colour"},
    {.type = "DefaultVisualManagerLoop", .summary = "visual loop"},
    {.type = "ClipPlane", .summary = "clipping plane"},
    {.type = "RecordedCamera", .summary = "camera path"},
    {.type = "MeshExporter", .summary = "writes mesh files (output only; penalty run writes VTK with --vtk DIR)"},
    {.type = "VisualModelOBJExporter", .summary = "writes the visual models as OBJ (output only)"},
    {.type = "CompositingVisualLoop", .summary = "visual loop of render passes"},
    {.type = "DataDisplay", .summary = "colours a visual model by data values"},
    {.type = "MergeVisualModels", .summary = "merges visual models for drawing"},
    {.type = "OglColorMap", .summary = "colour map for drawing"},
    {.type = "OglOITShader", .summary = "order-independent transparency shader"},
    {.type = "OglRenderingSRGB", .summary = "sRGB rendering switch"},
    {.type = "OglShader", .summary = "GLSL shader"},
    {.type = "OglShaderDefineMacro", .summary = "GLSL shader macro"},
    {.type = "OglShaderVisualModel", .summary = "visual model drawn by a shader"},
    {.type = "OglShadowShader", .summary = "shadow shader"},
    {.type = "OglTexture", .summary = "texture"},
    {.type = "OglTexture2D", .summary = "texture"},
    {.type = "OglTexturePointer", .summary = "texture reference"},
    {.type = "OglViewport", .summary = "viewport"},
    {.type = "OrderIndependentTransparencyManager", .summary = "transparency rendering"},
    {.type = "PointSplatModel", .summary = "point splats drawn from a state"},
    {.type = "PostProcessManager", .summary = "post-processing of the rendering"},
    {.type = "SlicedVolumetricModel", .summary = "volume rendering"},
    {.type = "TextureInterpolation", .summary = "texture coordinates from data values, for drawing"},
    {.type = "VisualManagerPass", .summary = "render pass"},
    {.type = "VisualManagerSecondaryPass", .summary = "render pass"},
    {.type = "CylinderVisualModel", .summary = "cylinders drawn along edges"},
    {.type = "TrailRenderer", .summary = "drawn trail of a point"},
    {.type = "Visual3DText", .summary = "drawn text"},
    {.type = "VisualBoundingBox", .summary = "drawn bounding box"},
    {.type = "VisualMesh", .summary = "drawn mesh"},
    {.type = "VisualPointCloud", .summary = "drawn points"},
    {.type = "VisualTransform", .summary = "transform of the drawing"},
    {.type = "VisualVectorField", .summary = "drawn vectors"},
    {.type = "AddFrameButtonSetting", .summary = "GUI mouse setting"},
    {.type = "AddRecordedCameraButtonSetting", .summary = "GUI mouse setting"},
    {.type = "AttachBodyButtonSetting", .summary = "GUI mouse setting"},
    {.type = "ConstraintAttachButtonSetting", .summary = "GUI mouse setting"},
    {.type = "FixPickedParticleButtonSetting", .summary = "GUI mouse setting"},
    {.type = "SofaDefaultPathSetting", .summary = "GUI setting"},
    {.type = "StatsSetting", .summary = "GUI setting"},
    {.type = "ViewerSetting", .summary = "GUI setting"},
    {.type = "MouseInteractor", .summary = "GUI mouse interaction"},
    {.type = "MechanicalStateController",
     .summary = "moves a state from mouse or haptic-device events (MechanicalStateController::applyController), "
                "none in a headless run: inert"},
    {.type = "PauseAnimationOnEvent", .summary = "pauses the GUI's animation on an event"},
    {.type = "MessageHandlerComponent", .summary = "message routing (logging)"},
    {.type = "VTKExporter", .summary = "writes VTK files (output only; penalty run writes VTK with --vtk DIR)"},
    {.type = "STLExporter", .summary = "writes STL files (output only)"},
    {.type = "OglIntVariable", .summary = "GLSL shader variable"},
    {.type = "OglInt2Variable", .summary = "GLSL shader variable"},
    {.type = "OglInt3Variable", .summary = "GLSL shader variable"},
    {.type = "OglInt4Variable", .summary = "GLSL shader variable"},
    {.type = "OglFloatVariable", .summary = "GLSL shader variable"},
    {.type = "OglFloat2Variable", .summary = "GLSL shader variable"},
    {.type = "OglFloat3Variable", .summary = "GLSL shader variable"},
    {.type = "OglFloat4Variable", .summary = "GLSL shader variable"},
    {.type = "OglIntVectorVariable", .summary = "GLSL shader variable"},
    {.type = "OglIntVector2Variable", .summary = "GLSL shader variable"},
    {.type = "OglIntVector3Variable", .summary = "GLSL shader variable"},
    {.type = "OglIntVector4Variable", .summary = "GLSL shader variable"},
    {.type = "OglFloatVectorVariable", .summary = "GLSL shader variable"},
    {.type = "OglFloatVector2Variable", .summary = "GLSL shader variable"},
    {.type = "OglFloatVector3Variable", .summary = "GLSL shader variable"},
    {.type = "OglFloatVector4Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix2Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix3Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix4Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix2x3Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix3x2Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix2x4Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix4x2Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix3x4Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix4x3Variable", .summary = "GLSL shader variable"},
    {.type = "OglMatrix4VectorVariable", .summary = "GLSL shader variable"},
    {.type = "OglFloatAttribute", .summary = "GLSL vertex attribute"},
    {.type = "OglFloat2Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglFloat3Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglFloat4Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglIntAttribute", .summary = "GLSL vertex attribute"},
    {.type = "OglInt2Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglInt3Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglInt4Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglUIntAttribute", .summary = "GLSL vertex attribute"},
    {.type = "OglUInt2Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglUInt3Attribute", .summary = "GLSL vertex attribute"},
    {.type = "OglUInt4Attribute", .summary = "GLSL vertex attribute"},
    // constraint corrections act only under a constraint solver (FreeMotionAnimationLoop with a
    // constraint solver), which a penalty-contact scene does not run: inert in it
    {.type = "UncoupledConstraintCorrection", .summary = kInertWithoutConstraintSolver},
    {.type = "LinearSolverConstraintCorrection", .summary = kInertWithoutConstraintSolver},
    {.type = "GenericConstraintCorrection", .summary = kInertWithoutConstraintSolver},
    {.type = "PrecomputedConstraintCorrection", .summary = kInertWithoutConstraintSolver},
};

// Old SOFA names that SOFA today neither knows nor lists as renamed (no class, no entry in its
// ComponentChange table): its object factory creates nothing, logs an error and runs the scene
// without them (the shared examples' SOFA states show it: a BoxConstraint's points fall). penalty
// does the same: the component is ignored, and `penalty info` / `penalty run` say so.
constexpr AttributeSpec kBoxConstraint[] = {
    {"box", K::numbers, "", "m", ValueCheck::none, "ignored (SOFA creates no BoxConstraint)"},
};
constexpr std::string_view kUnknownToSofa =
    "unknown to SOFA today, which creates nothing and runs the scene without it";
constexpr ComponentSpec kAbsentFromSofa[] = {
    {.type = "BoxConstraint", .summary = kUnknownToSofa, .attributes = kBoxConstraint},
    {.type = "PlaneConstraint", .summary = kUnknownToSofa},
    {.type = "CGImplicit", .summary = kUnknownToSofa},
    {.type = "CGImplicitSolver", .summary = kUnknownToSofa},
};

constexpr AttributeSpec kNodeAttributes[] = {
    {"dt", K::real, "0.01", "s", ValueCheck::positive, "time step; the root's only (SOFA copies it over a child's)"},
    {"gravity", K::vector3, "0 -9.81 0", "m/s^2", ValueCheck::none, "the root's only (SOFA copies it over a child's)"},
};

// SOFA Data that never change the numbers (logging, display, bookkeeping).
constexpr std::string_view kHarmless[] = {"printLog",
                                          "tags",
                                          "listening",
                                          "draw",
                                          "verbose",
                                          "bbox",
                                          "componentState",
                                          "showObject",
                                          "showObjectScale",
                                          "drawMode",
                                          "color",
                                          "showIndices",
                                          "showIndicesScale",
                                          "showColor",
                                          "showVectors",
                                          "showVectorsScale",
                                          "drawArrows",
                                          "drawSize",
                                          "showImpostors",
                                          "displayFreePosition",
                                          "showEdges",
                                          "showTriangles",
                                          "drawEdges",
                                          "drawTriangles",
                                          "drawHeterogeneousTetra",
                                          "showStressColorMap",
                                          "showStressAlpha",
                                          "showVonMisesStressPerNode",
                                          "computeVonMisesStress",
                                          "showWireFrame",
                                          "showAxisSizeFactor",
                                          "showGravity",
                                          "showLines",
                                          "drawElements",
                                          "activated",
                                          "depth",
                                          "handleSeams"};

const std::vector<ComponentSpec>& registry() {
    static const std::vector<ComponentSpec> all = [] {
        std::vector<ComponentSpec> out;
        for (std::span<const ComponentSpec> family : {builder::solver_components(),
                                                      builder::state_and_topology_components(),
                                                      builder::mass_and_force_field_components(),
                                                      builder::mapping_and_constraint_components(),
                                                      builder::collision_components(),
                                                      builder::topology_container_components(),
                                                      builder::surface_force_field_components(),
                                                      builder::mass_and_region_components(),
                                                      builder::sparse_grid_components(),
                                                      builder::pressure_load_components(),
                                                      builder::region_of_interest_components(),
                                                      builder::external_load_components(),
                                                      builder::hexahedra_and_subset_components(),
                                                      builder::bending_spring_components(),
                                                      builder::corotational_fem_components(),
                                                      builder::topology_change_components(),
                                                      builder::direct_solver_components(),
                                                      builder::integrator_components(),
                                                      builder::matrix_mass_and_rest_spring_components(),
                                                      builder::transform_engine_components(),
                                                      builder::selection_engine_components(),
                                                      builder::frame_mapping_components(),
                                                      builder::python_components(),
                                                      builder::projective_constraint_components(),
                                                      builder::rigid_force_field_components(),
                                                      builder::interaction_force_field_components(),
                                                      builder::hyperelasticity_components(),
                                                      builder::shell_force_field_components(),
                                                      builder::nonuniform_hexahedra_components(),
                                                      builder::tait_pressure_components(),
                                                      builder::multi_mapping_components(),
                                                      builder::drawing_components(),
                                                      builder::shape_matching_components(),
                                                      builder::diffusion_components(),
                                                      std::span<const ComponentSpec>(kLoaders),
                                                      std::span<const ComponentSpec>(kVisual),
                                                      std::span<const ComponentSpec>(kAbsentFromSofa)})
            out.insert(out.end(), family.begin(), family.end());
        return out;
    }();
    return all;
}

std::string_view kind_name(AttributeKind k) {
    switch (k) {
        case K::boolean:
            return "bool";
        case K::integer:
            return "integer";
        case K::real:
            return "number";
        case K::vector3:
            return "3 numbers";
        case K::numbers:
            return "numbers";
        case K::indices:
            return "indices";
        case K::points:
            return "points";
        case K::frames:
            return "rigid frames";
        case K::elements:
            return "elements";
        case K::text:
            return "text";
        case K::link:
            return "link";
        case K::links:
            return "links";
    }
    return "?";
}

std::string_view family_name(ComponentFamily f) {
    switch (f) {
        case F::gravity:
            return "context";
        case F::topology:
            return "topologies";
        case F::topology_helper:
            return "topology modifiers and algorithms (accepted; only topological changes use them)";
        case F::state:
            return "states";
        case F::mapping:
            return "mappings";
        case F::mass:
            return "masses";
        case F::force_field:
            return "force fields";
        case F::constraint:
            return "constraints";
        case F::engine:
            return "engines";
        case F::data_engine:
            return "data engines (run when an output is first read)";
        case F::ode_solver:
            return "ODE solvers";
        case F::linear_solver:
            return "linear solvers";
        case F::solver_part:
            return "parts of solvers (linear systems, orderings, Newton-Raphson)";
        case F::collision_model:
            return "collision models";
        case F::animation_loop:
            return "animation loops";
        case F::collision_pipeline:
            return "collision pipelines";
        case F::composite_pipeline:
            return "composite collision pipelines";
        case F::sub_pipeline:
            return "sub-pipelines of a composite";
        case F::broad_phase:
            return "broad phases";
        case F::narrow_phase:
            return "narrow phases";
        case F::intersection:
            return "intersection methods";
        case F::contact_manager:
            return "contact managers";
        case F::loader:
            return "loaders";
        case F::visual:
            return "visual or editor only (ignored)";
    }
    return "?";
}

void describe_one(const ComponentSpec& spec, std::ostringstream& out) {
    out << "  " << spec.type << ": " << spec.summary << "\n";
    for (std::span<const AttributeSpec> list : {spec.attributes, spec.shared_attributes}) {
        for (const AttributeSpec& a : list) {
            out << "    " << a.name << " (" << kind_name(a.kind);
            if (!a.unit.empty()) out << ", " << a.unit;
            if (a.check == ValueCheck::nonnegative) out << ", >= 0";
            if (a.check == ValueCheck::positive) out << ", > 0";
            out << ")";
            if (!a.default_value.empty()) out << " default " << a.default_value;
            if (!a.meaning.empty()) out << ": " << a.meaning;
            out << "\n";
        }
    }
}

}  // namespace

ComponentCategory category_of(ComponentFamily family) {
    if (family == F::loader) return ComponentCategory::loader;
    if (family == F::visual) return ComponentCategory::ignored;
    return ComponentCategory::physics;
}

std::span<const ComponentSpec> component_registry() { return registry(); }

const ComponentSpec* find_component(std::string_view type) {
    for (const ComponentSpec& spec : registry())
        if (spec.type == type) return &spec;
    return nullptr;
}

std::optional<ComponentCategory> component_category(std::string_view type) {
    const ComponentSpec* spec = find_component(type);
    if (spec == nullptr) return std::nullopt;
    return category_of(spec->family);
}

const AttributeSpec* find_attribute(const ComponentSpec& spec, std::string_view name) {
    for (std::span<const AttributeSpec> list : {spec.attributes, spec.shared_attributes})
        for (const AttributeSpec& a : list)
            if (a.name == name) return &a;
    return nullptr;
}

std::span<const AttributeSpec> node_attributes() { return kNodeAttributes; }

std::vector<std::string> read_attributes(std::string_view type) {
    std::vector<std::string> out;
    if (type == "Node") {
        for (const AttributeSpec& a : kNodeAttributes) out.emplace_back(a.name);
        return out;
    }
    if (const ComponentSpec* spec = find_component(type))
        for (std::span<const AttributeSpec> list : {spec->attributes, spec->shared_attributes})
            for (const AttributeSpec& a : list) out.emplace_back(a.name);
    return out;
}

std::vector<std::string> unread_attributes(const io::SceneElement& element) {
    std::vector<std::string> out;
    const ComponentSpec* spec = element.type == "Node" ? nullptr : find_component(element.type);
    if (element.type != "Node" && (spec == nullptr || spec->family == F::visual)) return out;
    for (const io::SceneAttribute& a : element.attributes) {
        if (std::find(std::begin(kHarmless), std::end(kHarmless), a.name) != std::end(kHarmless)) continue;
        const bool read = spec != nullptr ? find_attribute(*spec, a.name) != nullptr
                                          : std::any_of(std::begin(kNodeAttributes), std::end(kNodeAttributes),
                                                        [&](const AttributeSpec& n) { return n.name == a.name; });
        if (!read) out.push_back(a.name);
    }
    return out;
}

std::string describe_components(std::string_view type) {
    std::ostringstream out;
    if (!type.empty()) {
        const ComponentSpec* spec = find_component(type);
        if (spec == nullptr)
            throw io::SceneError("unknown component '" + std::string(type) +
                                 "' (penalty info --components lists them)");
        out << family_name(spec->family) << ":\n";
        describe_one(*spec, out);
        return out.str();
    }
    std::map<int, std::vector<const ComponentSpec*>> by_family;
    for (const ComponentSpec& spec : registry()) by_family[int(spec.family)].push_back(&spec);
    out << registry().size() << " component types (attributes: kind, unit, check, default)\n";
    for (const auto& [family, specs] : by_family) {
        out << "\n" << family_name(ComponentFamily(family)) << ":\n";
        for (const ComponentSpec* spec : specs) describe_one(*spec, out);
    }
    return out.str();
}

// ---- the scene check ------------------------------------------------------------------------

std::vector<std::string> detach_unresolved_data_links(io::SceneFile& scene) {
    std::vector<std::string> notes;
    if (!scene.root) return notes;
    // a link to a Data (`@name.data`, the last path segment holding a '.' that is not `.` or `..`)
    const auto is_data_link = [](std::string_view text) {
        const std::string_view last = text.substr(text.rfind('/') == std::string_view::npos ? 1 : text.rfind('/') + 1);
        return last != "." && last != ".." && last.find('.') != std::string_view::npos;
    };
    std::vector<io::SceneComponent*> all;
    const auto collect = [&all](auto& self, io::SceneNode& node) -> void {
        for (auto& c : node.components) all.push_back(c.get());
        for (auto& child : node.children) self(self, *child);
    };
    collect(collect, *scene.root);
    const auto trimmed = [](std::string_view t) {
        const auto first = t.find_first_not_of(" \t\r\n");
        if (first == std::string_view::npos) return std::string_view();
        return t.substr(first, t.find_last_not_of(" \t\r\n") - first + 1);
    };
    for (io::SceneComponent* c : all) {
        const ComponentSpec* spec = find_component(c->type);
        if (spec == nullptr || category_of(spec->family) != ComponentCategory::physics) continue;
        for (auto a = c->attributes.begin(); a != c->attributes.end();) {
            const std::string_view value = trimmed(a->value);
            // a region's points keep their link: SOFA's Data is then set and empty, so the region
            // does not fall back to its state's points (BoxROI::init tests d_X0.isSet(); roi_points)
            const bool region_points =
                spec->family == F::engine && (a->name == "position" || a->name == "rest_position");
            if (!io::is_link(a->value) || value.find_first_of(" \t\r\n") != std::string_view::npos ||
                !is_data_link(value) || region_points) {
                ++a;
                continue;
            }
            try {
                (void)io::resolve_link(*c, a->name);
                ++a;
            } catch (const io::SceneError& e) {
                notes.push_back(std::string(e.what()) +
                                "; SOFA leaves that Data unset (BaseData::setParent finds no "
                                "parent), and so does penalty: the attribute is ignored");
                a = c->attributes.erase(a);
            }
        }
    }
    return notes;
}

SceneCheck validate(const io::SceneFile& scene) {
    SceneCheck check;
    if (!scene.root) return check;

    std::vector<const io::SceneComponent*> all;
    io::for_each_component(*scene.root, [&](const io::SceneComponent& c) { all.push_back(&c); });

    // 1. every type is known
    for (const io::SceneComponent* c : all) {
        if (find_component(c->type) == nullptr) {
            throw io::SceneError(c->file + ":" + std::to_string(c->line) + ": unknown component '" + c->type +
                                 "' (not supported by penalty)" + c->included_from);
        }
    }

    // 2. classify; resolve the links of physics components
    const auto is_ignored = [](const io::SceneComponent& c) {
        return component_category(c.type) == ComponentCategory::ignored;
    };
    std::map<std::string, int> ignored_counts;
    std::set<const io::SceneComponent*> used_loaders;
    std::vector<const io::SceneComponent*> loaders;
    for (const io::SceneComponent* c : all) {
        const ComponentSpec& spec = *find_component(c->type);
        const ComponentCategory category = category_of(spec.family);
        if (category == ComponentCategory::ignored) {
            check.ignored.push_back(c);
            ++ignored_counts[c->type + (spec.summary == kUnknownToSofa ? " (unknown to SOFA, which drops it)" : "")];
            continue;
        }
        if (category == ComponentCategory::loader) {
            loaders.push_back(c);
            continue;
        }
        if (spec.family == F::mapping && c->has("output") && io::is_link(c->find("output")->value)) {
            const io::LinkTarget out = io::resolve_link(*c, "output");
            if (out.component != nullptr && is_ignored(*out.component)) {
                check.ignored.push_back(c);
                ++ignored_counts[c->type + " (visual output)"];
                continue;
            }
            // `output="@."` naming a node without a MechanicalObject: SOFA's link finds no state
            // there, Mapping::canCreate fails and the mapping is not created
            const auto is_state = [](const auto& x) { return x->type == "MechanicalObject"; };
            if (out.node != nullptr &&
                std::none_of(out.node->components.begin(), out.node->components.end(), is_state)) {
                check.ignored.push_back(c);
                ++ignored_counts[c->type + " (output node without a state: SOFA does not create it)"];
                continue;
            }
        }
        // no `output`: SOFA's Mapping::create links the first State<Out> of the mapping's node
        // ("@./"), which is a visual model (OglModel, a State<Vec3>) in a node without a
        // MechanicalObject: the mapping only moves what is drawn
        if (spec.family == F::mapping && !c->has("output") && c->node != nullptr) {
            const auto& in_node = c->node->components;
            const auto of_type = [&](std::initializer_list<std::string_view> types) {
                return std::any_of(in_node.begin(), in_node.end(), [&](const auto& x) {
                    return std::find(types.begin(), types.end(), x->type) != types.end();
                });
            };
            if (!of_type({"MechanicalObject"}) && of_type({"OglModel", "VisualModel", "VisualModelImpl"})) {
                check.ignored.push_back(c);
                ++ignored_counts[c->type + " (visual output)"];
                continue;
            }
        }
        check.physics.push_back(c);
        for (const io::SceneAttribute& a : c->attributes) {
            if (!io::is_link(a.value)) continue;
            // a region's points whose link finds nothing: SOFA's empty Data (roi_points warns)
            const bool may_break = spec.family == F::engine && (a.name == "position" || a.name == "rest_position");
            std::vector<io::LinkTarget> targets;
            try {
                targets = io::resolve_links(*c, a.name);
            } catch (const io::SceneError&) {
                if (!may_break) throw;
            }
            for (const io::LinkTarget& t : targets) {
                if (t.component != nullptr && component_category(t.component->type) == ComponentCategory::loader) {
                    used_loaders.insert(t.component);
                }
            }
        }
    }
    for (const io::SceneComponent* c : loaders) {
        if (used_loaders.count(c) != 0) {
            check.loaders.push_back(c);
        } else {
            check.ignored.push_back(c);
            ++ignored_counts[c->type + " (visual only)"];
        }
    }

    std::string list;
    for (const auto& [type, count] : ignored_counts) {
        list += (list.empty() ? "" : ", ") + type + " x" + std::to_string(count);
    }
    check.summary = "ignored " + std::to_string(check.ignored.size()) +
                    (check.ignored.size() == 1 ? " component that does not" : " components that do not") +
                    " change the numbers" + (list.empty() ? "" : ": " + list);
    return check;
}

}  // namespace penalty::scene
