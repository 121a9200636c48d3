#include "penalty/io/scene_mesh.hpp"

#include "penalty/io/data_path.hpp"

#include <cmath>
#include <set>
#include <utility>

#include <cstdlib>

namespace penalty::io {

// ---------------------------------------------------------------------------------------------
// loading the mesh of a component

namespace {

void refuse_if_set(const SceneComponent& c, std::string_view attr, bool value_that_is_unsupported) {
    if (c.has(attr) && get_bool_or(c, attr, !value_that_is_unsupported) == value_that_is_unsupported) {
        throw_attribute_error(c, attr, "not supported by penalty (it changes the point list)");
    }
}

/// GridMeshCreator::doLoad: resolution (nx, ny) points x/(nx−1), y/(ny−1), row by row; the
/// elements of `pattern` in SOFA's order; the edges of the elements once each, in the order of
/// SOFA's std::set<Edge> (lexicographic), each as first inserted (a, b) unless (b, a) was.
MeshData grid_mesh_creator(const SceneComponent& c) {
    std::vector<double> res{2.0, 2.0};
    if (c.has("resolution")) res = get_doubles(c, "resolution");
    if (res.size() != 2) throw_attribute_error(c, "resolution", "must be 2 integers (points along x and y)");
    for (const double r : res)
        if (!(r >= 2.0) || r > 1e6 || r != std::floor(r))
            throw_attribute_error(c, "resolution", "each count must be an integer >= 2 (SOFA divides by count - 1)");
    if (res[0] * res[1] > 1e7) throw_attribute_error(c, "resolution", "more than 10^7 points");
    const std::int64_t pattern = get_int_or(c, "trianglePattern", 2);
    if (pattern < 0 || pattern > 3) throw_attribute_error(c, "trianglePattern", "must be 0, 1, 2 or 3");
    const auto nx = static_cast<std::size_t>(res[0]), ny = static_cast<std::size_t>(res[1]);
    MeshData mesh;
    for (std::size_t y = 0; y < ny; ++y)
        for (std::size_t x = 0; x < nx; ++x)
            mesh.positions.emplace_back(double(x) / double(nx - 1), double(y) / double(ny - 1), 0.0);
    const auto vert = [nx](std::size_t x, std::size_t y) { return static_cast<PointId>(x + y * nx); };
    std::set<std::pair<PointId, PointId>> edges;
    const auto edge = [&edges](PointId a, PointId b) {
        if (!edges.contains({b, a})) edges.insert({a, b});
    };
    const auto triangle = [&](PointId a, PointId b, PointId d) {
        mesh.triangles.push_back({a, b, d});
        edge(a, b);
        edge(b, d);
        edge(d, a);
    };
    for (std::size_t y = 0; y + 1 < ny; ++y)
        for (std::size_t x = 0; x + 1 < nx; ++x) {
            const PointId p00 = vert(x, y), p10 = vert(x + 1, y), p11 = vert(x + 1, y + 1), p01 = vert(x, y + 1);
            if (pattern == 0) {
                mesh.quads.push_back({p00, p10, p11, p01});
                edge(p00, p10);
                edge(p10, p11);
                edge(p11, p01);
                edge(p01, p00);
            } else if (pattern == 2 || (pattern == 1 && (x + y) % 2 == 0)) {
                triangle(p00, p10, p11);
                triangle(p00, p11, p01);
            } else {
                triangle(p00, p10, p01);
                triangle(p10, p11, p01);
            }
        }
    for (const auto& [a, b] : edges) mesh.edges.push_back({a, b});
    return mesh;
}

}  // namespace

double mesh_loader_scale(const SceneComponent& c, bool* read_whole, bool in_double) {
    if (read_whole != nullptr) *read_whole = true;
    const auto text = get_string(c, "scale");
    if (!text) return 1.0;
    const char* begin = text->c_str();
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end != begin + text->size()) {
        if (read_whole != nullptr) *read_whole = false;
        return 1.0;
    }
    if (in_double) return value;
    // MeshLoader::parse: BaseObjectDescription::getAttributeAsFloat (strtof)
    const float as_float = std::strtof(begin, nullptr);
    if (!std::isfinite(as_float))
        throw_attribute_error(c, "scale",
                              "'" + *text +
                                  "' is beyond float range, and SOFA reads this attribute as a float "
                                  "(--fix-sofa-quirk mesh_loader_float_scale reads it in double)");
    return double(as_float);
}

MeshData load_scene_mesh(const SceneComponent& c, const std::filesystem::path& scene_dir,
                         const std::vector<std::filesystem::path>& data_dirs, bool scale_in_double) {
    const bool is_mesh_loader = c.type == "MeshOBJLoader" || c.type == "MeshGmshLoader" || c.type == "MeshVTKLoader" ||
                                c.type == "MeshOffLoader" || c.type == "MeshTrianLoader";
    const bool is_sphere_loader = c.type == "SphereLoader";
    if (c.type == "GridMeshCreator") {
        const Vec3 scale3d = get_vec3_or(c, "scale3d", Vec3::Ones()) * mesh_loader_scale(c, nullptr, scale_in_double);
        MeshData mesh = grid_mesh_creator(c);
        apply_transform(mesh, get_vec3_or(c, "translation", Vec3::Zero()), get_vec3_or(c, "rotation", Vec3::Zero()),
                        scale3d);
        return mesh;
    }
    const bool is_topology_file = c.type == "MeshTopology" || c.type == "MechanicalObject" ||
                                  c.type.ends_with("SetTopologyContainer");  // BaseMeshTopology::load
    if (!is_mesh_loader && !is_sphere_loader && !is_topology_file) {
        throw_element_error(c, "is not a mesh loader");
    }
    const auto filename = get_string(c, "filename");
    if (!filename || filename->empty()) throw_attribute_error(c, "filename", "missing (a mesh file name is required)");
    if (is_link(*filename)) throw_attribute_error(c, "filename", "links are not supported here");

    // options that change the point list and that penalty does not implement
    if (is_mesh_loader) {
        refuse_if_set(c, "onlyAttachedPoints", true);
        if (c.has("transformation")) {
            const std::vector<double> m = get_doubles(c, "transformation");
            const bool identity = m.size() == 16 && [&] {
                for (std::size_t i = 0; i < 16; ++i) {
                    if (m[i] != (i % 5 == 0 ? 1.0 : 0.0)) return false;
                }
                return true;
            }();
            if (!identity)
                throw_attribute_error(c, "transformation",
                                      "not supported by penalty (use translation, rotation, scale3d)");
        }
    }
    // validate the transform attributes before reading the file
    const Vec3 translation = get_vec3_or(c, "translation", Vec3::Zero());
    const Vec3 rotation = get_vec3_or(c, "rotation", Vec3::Zero());
    Vec3 scale3d = Vec3::Ones();
    if (is_mesh_loader) {
        scale3d = get_vec3_or(c, "scale3d", Vec3::Ones()) * mesh_loader_scale(c, nullptr, scale_in_double);
    } else if (is_sphere_loader) {
        if (c.has("scale") && c.has("scale3d"))
            throw_attribute_error(c, "scale3d", "'scale' and its alias 'scale3d' are both set");
        scale3d = get_vec3_or(c, c.has("scale3d") ? "scale3d" : "scale", Vec3::Ones());
    }
    const bool triangulate = is_mesh_loader && get_bool_or(c, "triangulate", false);
    const bool flip = is_mesh_loader && get_bool_or(c, "flipNormals", false);
    const bool subelements = is_mesh_loader && get_bool_or(c, "createSubelements", c.type == "MeshGmshLoader");

    MeshData mesh;
    try {
        const std::filesystem::path file = resolve_data_file(*filename, scene_dir, data_dirs);
        if (c.type == "MeshOBJLoader") {
            mesh = load_obj(file, triangulate, get_bool_or(c, "handleSeams", false));
        } else if (c.type == "MeshGmshLoader") {
            mesh = load_gmsh(file);
        } else if (c.type == "MeshVTKLoader") {
            mesh = load_vtk(file);
        } else if (c.type == "MeshOffLoader") {
            mesh = load_off(file);
        } else if (c.type == "MeshTrianLoader") {
            if (get_bool_or(c, "trian2", false))
                throw_attribute_error(c, "trian2", "the trian2 format is not supported by penalty");
            mesh = load_trian(file);
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
    apply_transform(mesh, translation, rotation, scale3d,
                    is_sphere_loader ? LoaderKind::sphere_loader : LoaderKind::mesh_loader);
    if (is_mesh_loader) {
        if (flip && c.type != "MeshGmshLoader") flip_normals(mesh);
        if (triangulate) triangulate_quads(mesh);
        if (subelements) create_subelements(mesh);
    }
    return mesh;
}

}  // namespace penalty::io
