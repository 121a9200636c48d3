#include "penalty/io/components.hpp"

#include "penalty/io/data_path.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace penalty::io {

namespace {

using C = ComponentCategory;

constexpr std::array kComponents{
    // animation loop, collision pipeline
    ComponentInfo{"DefaultAnimationLoop", C::physics, "time loop: collision, then one solver step per solver node"},
    ComponentInfo{"CollisionPipeline", C::physics, "collision pipeline (broad phase, narrow phase, response)"},
    ComponentInfo{"CompositeCollisionPipeline", C::physics, "runs several SubCollisionPipelines"},
    ComponentInfo{"SubCollisionPipeline", C::physics, "collision pipeline restricted to listed models"},
    ComponentInfo{"BruteForceBroadPhase", C::physics, "broad phase over all model pairs"},
    ComponentInfo{"BVHNarrowPhase", C::physics, "bounding-volume narrow phase"},
    ComponentInfo{"CollisionResponse", C::physics, "contact manager (response=PenalityContactForceField)"},
    ComponentInfo{"MinProximityIntersection", C::physics, "proximity intersection (MinProximity)"},
    ComponentInfo{"NewProximityIntersection", C::physics, "proximity intersection (NewProximity)"},
    ComponentInfo{"DiscreteIntersection", C::physics, "discrete (overlap-only) intersection"},
    ComponentInfo{"LocalMinDistance", C::physics, "proximity intersection (LocalMinDistance)"},
    // solvers
    ComponentInfo{"EulerImplicitSolver", C::physics, "implicit Euler ODE solver"},
    ComponentInfo{"EulerExplicitSolver", C::physics, "explicit Euler ODE solver"},
    ComponentInfo{"CGLinearSolver", C::physics, "conjugate gradient linear solver"},
    // states, topologies, masses, force fields, constraints
    ComponentInfo{"MechanicalObject", C::physics, "state (Vec3d or Rigid3d)"},
    ComponentInfo{"MeshTopology", C::physics, "mesh topology (element lists or filename)"},
    ComponentInfo{"RegularGridTopology", C::physics, "regular grid topology"},
    ComponentInfo{"UniformMass", C::physics, "uniform mass"},
    ComponentInfo{"Gravity", C::physics, "gravity of its node's context"},
    ComponentInfo{"MeshSpringForceField", C::physics, "springs on the mesh edges"},
    ComponentInfo{"RegularGridSpringForceField", C::physics, "springs on a regular grid"},
    ComponentInfo{"TetrahedronFEMForceField", C::physics, "linear tetrahedral FEM"},
    ComponentInfo{"HexahedronFEMForceField", C::physics, "linear hexahedral FEM"},
    ComponentInfo{"FixedProjectiveConstraint", C::physics, "fixed points"},
    ComponentInfo{"FixedConstraint", C::physics, "fixed points (older name)"},
    // collision models
    ComponentInfo{"PointCollisionModel", C::physics, "point collision model"},
    ComponentInfo{"LineCollisionModel", C::physics, "edge collision model"},
    ComponentInfo{"TriangleCollisionModel", C::physics, "triangle collision model"},
    ComponentInfo{"SphereCollisionModel", C::physics, "sphere collision model (Vec3d or Rigid3d)"},
    ComponentInfo{"CylinderCollisionModel", C::physics, "cylinder collision model (Rigid3d)"},
    ComponentInfo{"TetrahedronCollisionModel", C::physics, "tetrahedron collision model"},
    // mappings
    ComponentInfo{"IdentityMapping", C::physics, "identity mapping"},
    ComponentInfo{"BarycentricMapping", C::physics, "barycentric mapping"},
    ComponentInfo{"SubsetMapping", C::physics, "subset mapping"},
    ComponentInfo{"RigidMapping", C::physics, "rigid mapping"},
    // loaders
    ComponentInfo{"MeshOBJLoader", C::loader, "Wavefront OBJ mesh"},
    ComponentInfo{"MeshGmshLoader", C::loader, "Gmsh v1/v2 ASCII mesh"},
    ComponentInfo{"SphereLoader", C::loader, "sphere list (.sph)"},
    ComponentInfo{"MeshVTKLoader", C::loader, "legacy ASCII VTK mesh"},
    // visual or editor only
    ComponentInfo{"RequiredPlugin", C::ignored, "plugin loading"},
    ComponentInfo{"VisualStyle", C::ignored, "display flags"},
    ComponentInfo{"OglModel", C::ignored, "OpenGL visual model"},
    ComponentInfo{"VisualModel", C::ignored, "visual model"},
    ComponentInfo{"OglSceneFrame", C::ignored, "frame drawn in a corner"},
    ComponentInfo{"OglLabel", C::ignored, "text label"},
    ComponentInfo{"OglGrid", C::ignored, "drawn grid"},
    ComponentInfo{"VisualGrid", C::ignored, "drawn grid"},
    ComponentInfo{"LineAxis", C::ignored, "drawn axes"},
    ComponentInfo{"InteractiveCamera", C::ignored, "camera"},
    ComponentInfo{"Camera", C::ignored, "camera"},
    ComponentInfo{"LightManager", C::ignored, "lights"},
    ComponentInfo{"DirectionalLight", C::ignored, "light"},
    ComponentInfo{"PositionalLight", C::ignored, "light"},
    ComponentInfo{"SpotLight", C::ignored, "light"},
    ComponentInfo{"BackgroundSetting", C::ignored, "background colour"},
    ComponentInfo{"DefaultVisualManagerLoop", C::ignored, "visual loop"},
    ComponentInfo{"ClipPlane", C::ignored, "clipping plane"},
};

constexpr std::array kMappings{std::string_view("IdentityMapping"), std::string_view("BarycentricMapping"),
                               std::string_view("SubsetMapping"), std::string_view("RigidMapping")};

bool is_ignored(const SceneComponent& c) { return component_category(c.type) == ComponentCategory::ignored; }

}  // namespace

std::span<const ComponentInfo> known_components() { return kComponents; }

std::optional<ComponentCategory> component_category(std::string_view type) {
    for (const auto& info : kComponents) {
        if (info.type == type) return info.category;
    }
    return std::nullopt;
}

bool is_mapping_type(std::string_view type) {
    return std::find(kMappings.begin(), kMappings.end(), type) != kMappings.end();
}

SceneCheck validate(const SceneFile& scene) {
    SceneCheck check;
    if (!scene.root) return check;

    std::vector<const SceneComponent*> all;
    for_each_component(*scene.root, [&](const SceneComponent& c) { all.push_back(&c); });

    // 1. every type is known
    for (const SceneComponent* c : all) {
        if (!component_category(c->type)) {
            throw SceneError(c->file + ":" + std::to_string(c->line) + ": unknown component '" + c->type +
                             "' (not supported by penalty)");
        }
    }

    // 2. classify; resolve the links of physics components
    std::map<std::string, int> ignored_counts;
    std::set<const SceneComponent*> used_loaders;
    std::vector<const SceneComponent*> loaders;
    for (const SceneComponent* c : all) {
        const ComponentCategory category = *component_category(c->type);
        if (category == ComponentCategory::ignored) {
            check.ignored.push_back(c);
            ++ignored_counts[c->type];
            continue;
        }
        if (category == ComponentCategory::loader) {
            loaders.push_back(c);
            continue;
        }
        if (is_mapping_type(c->type) && c->has("output") && is_link(c->find("output")->value)) {
            const LinkTarget out = resolve_link(*c, "output");
            if (out.component != nullptr && is_ignored(*out.component)) {
                check.ignored.push_back(c);
                ++ignored_counts[c->type + " (visual output)"];
                continue;
            }
        }
        check.physics.push_back(c);
        for (const SceneAttribute& a : c->attributes) {
            if (!is_link(a.value)) continue;
            for (const LinkTarget& t : resolve_links(*c, a.name)) {
                if (t.component != nullptr && component_category(t.component->type) == ComponentCategory::loader) {
                    used_loaders.insert(t.component);
                }
            }
        }
    }
    for (const SceneComponent* c : loaders) {
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
    check.summary = "ignored " + std::to_string(check.ignored.size()) + " visual-only component" +
                    (check.ignored.size() == 1 ? "" : "s") + (list.empty() ? "" : ": " + list);
    return check;
}

// ---------------------------------------------------------------------------------------------
// loading the mesh of a component

namespace {

void refuse_if_set(const SceneComponent& c, std::string_view attr, bool value_that_is_unsupported) {
    if (c.has(attr) && get_bool_or(c, attr, !value_that_is_unsupported) == value_that_is_unsupported) {
        throw_attribute_error(c, attr, "not supported by penalty (it changes the point list)");
    }
}

}  // namespace

MeshData load_scene_mesh(const SceneComponent& c, const std::filesystem::path& scene_dir,
                         const std::vector<std::filesystem::path>& data_dirs) {
    const bool is_mesh_loader = c.type == "MeshOBJLoader" || c.type == "MeshGmshLoader" || c.type == "MeshVTKLoader";
    const bool is_sphere_loader = c.type == "SphereLoader";
    const bool is_topology_file = c.type == "MeshTopology" || c.type == "MechanicalObject";
    if (!is_mesh_loader && !is_sphere_loader && !is_topology_file) {
        throw_element_error(c, "is not a mesh loader");
    }
    const auto filename = get_string(c, "filename");
    if (!filename || filename->empty()) throw_attribute_error(c, "filename", "missing (a mesh file name is required)");
    if (is_link(*filename)) throw_attribute_error(c, "filename", "links are not supported here");

    // options that change the point list and that penalty does not implement
    if (is_mesh_loader) {
        refuse_if_set(c, "handleSeams", true);
        refuse_if_set(c, "onlyAttachedPoints", true);
        if (c.has("transformation")) {
            const std::vector<double> m = get_doubles(c, "transformation");
            const bool identity = m.size() == 16 && [&] {
                for (std::size_t i = 0; i < 16; ++i) {
                    if (m[i] != (i % 5 == 0 ? 1.0 : 0.0)) return false;
                }
                return true;
            }();
            if (!identity) throw_attribute_error(c, "transformation", "not supported by penalty (use translation, rotation, scale3d)");
        }
    }
    // validate the transform attributes before reading the file
    const Vec3 translation = get_vec3_or(c, "translation", Vec3::Zero());
    const Vec3 rotation = get_vec3_or(c, "rotation", Vec3::Zero());
    Vec3 scale3d = Vec3::Ones();
    if (is_mesh_loader) {
        scale3d = get_vec3_or(c, "scale3d", Vec3::Ones()) * get_double_or(c, "scale", 1.0);
    } else if (is_sphere_loader) {
        if (c.has("scale") && c.has("scale3d")) throw_attribute_error(c, "scale3d", "'scale' and its alias 'scale3d' are both set");
        scale3d = get_vec3_or(c, c.has("scale3d") ? "scale3d" : "scale", Vec3::Ones());
    }
    const bool triangulate = is_mesh_loader && get_bool_or(c, "triangulate", false);
    const bool flip = is_mesh_loader && get_bool_or(c, "flipNormals", false);
    const bool subelements = is_mesh_loader && get_bool_or(c, "createSubelements", c.type == "MeshGmshLoader");

    MeshData mesh;
    try {
        const std::filesystem::path file = resolve_data_file(*filename, scene_dir, data_dirs);
        if (c.type == "MeshOBJLoader") {
            mesh = load_obj(file, triangulate);
        } else if (c.type == "MeshGmshLoader") {
            mesh = load_gmsh(file);
        } else if (c.type == "MeshVTKLoader") {
            mesh = load_vtk_legacy(file);
        } else if (is_sphere_loader) {
            mesh = load_sph(file);
        } else {
            mesh = load_mesh_file(file);
        }
    } catch (const SceneError&) {
        throw;
    } catch (const LoadError& e) {
        throw_attribute_error(c, "filename", e.what());
    }
    if (is_topology_file) return mesh;

    // SOFA MeshLoader order: transform of the points, then element post-processing
    apply_transform(mesh, translation, rotation, scale3d);
    if (is_mesh_loader) {
        if (flip && c.type != "MeshGmshLoader") flip_normals(mesh);
        if (triangulate) triangulate_quads(mesh);
        if (subelements) create_subelements(mesh);
    }
    return mesh;
}

}  // namespace penalty::io
