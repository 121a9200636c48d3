#pragma once
// The large-scene benchmark's scene (issue 54): a tetrahedral soft body — a slab of tissue —
// dropped onto a static, curved, liver-sized triangle surface (the "organ") and sliding over it,
// as SOFA scene text (.scn) for scene::build_scene. Header-only, standard library only; used by
// bench/bench_large_scenes.cpp and tests/scene/test_large_scenes.cpp.
//
// The body: a box of n × n/8 × n hexahedral cells (x, y, z; n a multiple of 8), each split into 6
// tetrahedra (the Kuhn split of cubes_in_bowl.hpp), TetrahedronFEMForceField (corotational),
// UniformMass, a TriangleCollisionModel on its outer faces; one EulerImplicitSolver +
// CGLinearSolver. n = 64: 38 025 nodes, 114 075 DOFs, 196 608 tetrahedra; n = 136: 1 010 394 DOFs,
// 1 886 592 tetrahedra. Its bottom starts the alarm distance + `clearance` above the organ's highest point, its centre
// `offset` along −x from it: it lands on the organ's upper face, drapes over it and slides down
// its −x side (frictionless), off it after about 0.7 s.
// The organ: a deformed ellipsoid (semi-axes 0.13 × 0.05 × 0.08 m, thicker on its +x side like a
// liver's right lobe) triangulated as a spherified cube of `organ_subdivisions` quads per face
// edge (12·s² triangles: s = 64 gives 49 152), normals outward, a static TriangleCollisionModel
// (simulated="0" moving="0") outside the solver's subtree. NewProximity, SOFA's penalty response.
#include "penalty_test/cubes_in_bowl.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace penalty::test::soft_body_on_organ {

/// What scene_xml() builds. Units: m, kg, s, Pa.
/// The body's elastic force field (its young_modulus and poisson_ratio; the hyperelastic one St
/// Venant-Kirchhoff with the Lamé coefficients of E and ν; the springs of its tetrahedra's edges
/// with tetrasStiffness E·h, h the cell edge).
enum class Elasticity {
    tetrahedron_fem,
    tetrahedral_corotational,
    fast_tetrahedral_corotational,
    hyperelastic,
    mesh_springs
};

struct Setup {
    Elasticity elasticity = Elasticity::tetrahedron_fem;
    int cells = 16;              ///< n: cells along x and z; n/8 along y (a multiple of 8)
    double body_length = 0.12;   ///< edge of the slab along x and z (m); thickness length/8
    double body_mass = 0.216;    ///< kg (1000 kg/m³)
    double young_modulus = 2e4;  ///< Pa (soft tissue)
    double poisson_ratio = 0.45;
    /// body bottom above the organ's top at the start, beyond the alarm distance (m): the first
    /// step has no contact
    double clearance = 0.001;
    double offset = 0.01;         ///< body centre −x of the organ's highest point at the start (m)
    int organ_subdivisions = 64;  ///< s: quads per edge of each face of the spherified cube
    std::array<double, 3> organ_axes = {0.13, 0.05, 0.08};  ///< semi-axes of the ellipsoid (m)
    /// NewProximity alarmDistance and contactDistance as fractions of the body's cell edge h
    double alarm_cells = 0.6;
    double contact_cells = 0.3;
    double spring_stiffness = 50.0;    ///< ks of every contact spring (N/m); contactStiffness √(ks·C)
    double dt = 0.005;                 ///< s
    double rayleigh_stiffness = 0.05;  ///< s
    double rayleigh_mass = 2.0;        ///< 1/s
    int cg_iterations = 100;           ///< CGLinearSolver iterations (binds on the large bodies)
    double cg_tolerance = 1e-9;
    double cg_threshold = 1e-12;
};

using P3 = cubes_in_bowl::detail::P3;

/// Body cell edge h (m).
inline double cell_edge(const Setup& s) { return s.body_length / s.cells; }
inline int cells_y(const Setup& s) { return s.cells / 8; }
inline double alarm_distance(const Setup& s) { return s.alarm_cells * cell_edge(s); }
inline double contact_distance(const Setup& s) { return s.contact_cells * cell_edge(s); }
inline double contact_stiffness(const Setup& s) { return std::sqrt(s.spring_stiffness * contact_distance(s)); }

/// Body nodes (n+1)²(n/8+1), tetrahedra 6·n²·n/8, outer triangles 4n² + 8n·n/8.
inline long body_nodes(const Setup& s) { return long(s.cells + 1) * (s.cells + 1) * (cells_y(s) + 1); }
inline long body_tetrahedra(const Setup& s) { return 6L * s.cells * s.cells * cells_y(s); }
inline long organ_triangles(const Setup& s) { return 12L * s.organ_subdivisions * s.organ_subdivisions; }

/// Radial scale of the ellipsoid in direction d (unit): s(d) = 1 + 0.15·dx + 0.06·dx·dz, in
/// [0.79, 1.21] (positive: the surface is star-shaped about the origin).
inline double organ_scale(const P3& d) { return 1.0 + 0.15 * d[0] + 0.06 * d[0] * d[2]; }

/// The organ's surface point in direction d (unit): s(d)·(a·dx, b·dy, c·dz).
inline P3 organ_point(const Setup& s, const P3& d) {
    const double k = organ_scale(d);
    return {k * s.organ_axes[0] * d[0], k * s.organ_axes[1] * d[1], k * s.organ_axes[2] * d[2]};
}

/// How far q is inside the smooth organ surface along its ray from the origin (m; > 0 inside):
/// the ray through q meets the surface at organ_point(d) with d ∝ (qx/a, qy/b, qz/c).
inline double organ_depth(const Setup& s, const P3& q) {
    P3 d = {q[0] / s.organ_axes[0], q[1] / s.organ_axes[1], q[2] / s.organ_axes[2]};
    const double l = std::sqrt(cubes_in_bowl::detail::dot(d, d));
    if (l == 0.0) return 1.0;
    for (double& c : d) c /= l;
    const P3 p = organ_point(s, d);
    return std::sqrt(cubes_in_bowl::detail::dot(p, p)) - std::sqrt(cubes_in_bowl::detail::dot(q, q));
}

struct Mesh {
    std::vector<P3> points;
    std::vector<std::array<int, 4>> tetrahedra;
    std::vector<std::array<int, 3>> triangles;
};

/// The organ: each face of the cube [−1, 1]³ as s × s quads (2 triangles each), its points
/// projected on the unit sphere (direction d) and mapped to organ_point(d); shared points once.
inline Mesh organ_mesh(const Setup& s) {
    const int n = s.organ_subdivisions;
    Mesh m;
    std::map<std::array<int, 3>, int> index;  // lattice point of [0, n]³ → point
    const auto point = [&](std::array<int, 3> g) {
        const auto [it, added] = index.emplace(g, int(m.points.size()));
        if (added) {
            P3 d = {2.0 * g[0] / n - 1.0, 2.0 * g[1] / n - 1.0, 2.0 * g[2] / n - 1.0};
            const double l = std::sqrt(cubes_in_bowl::detail::dot(d, d));
            for (double& c : d) c /= l;
            m.points.push_back(organ_point(s, d));
        }
        return it->second;
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            for (int u = 0; u < n; ++u)
                for (int v = 0; v < n; ++v) {
                    const auto node = [&](int du, int dv) {
                        std::array<int, 3> g{};
                        g[std::size_t(axis)] = side == 0 ? 0 : n;
                        g[std::size_t((axis + 1) % 3)] = u + du;
                        g[std::size_t((axis + 2) % 3)] = v + dv;
                        return point(g);
                    };
                    const int q[4] = {node(0, 0), node(1, 0), node(1, 1), node(0, 1)};
                    for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
                        const auto& p = m.points;
                        P3 mid{};
                        for (int c = 0; c < 3; ++c)
                            mid[std::size_t(c)] =
                                (p[std::size_t(t[0])][std::size_t(c)] + p[std::size_t(t[1])][std::size_t(c)] +
                                 p[std::size_t(t[2])][std::size_t(c)]) /
                                3.0;
                        m.triangles.push_back(cubes_in_bowl::detail::oriented(p, t[0], t[1], t[2], mid));  // outward
                    }
                }
    return m;
}

/// The organ's highest point (m): the first point of the mesh of largest y.
inline P3 organ_top(const Mesh& organ) {
    P3 top = organ.points.front();
    for (const P3& p : organ.points)
        if (p[1] > top[1]) top = p;
    return top;
}

/// The body's mesh in its own frame: x, z ∈ [−L/2, L/2], y ∈ [0, L/8] (bottom at y = 0).
inline Mesh body_mesh(const Setup& s) {
    const int nx = s.cells, ny = cells_y(s), nz = s.cells;
    const double h = cell_edge(s);
    const auto id = [&](int i, int j, int l) { return i + (nx + 1) * (j + (ny + 1) * l); };
    Mesh m;
    for (int l = 0; l <= nz; ++l)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i)
                m.points.push_back({-0.5 * s.body_length + i * h, j * h, -0.5 * s.body_length + l * h});
    // hexahedron corners in SOFA's order, 6 tetrahedra each (cubes_in_bowl's pattern), positive volume
    constexpr int kTets[6][4] = {{0, 5, 1, 6}, {0, 1, 3, 6}, {1, 3, 6, 2}, {6, 3, 0, 7}, {6, 7, 0, 5}, {7, 5, 4, 0}};
    using cubes_in_bowl::detail::cross, cubes_in_bowl::detail::dot, cubes_in_bowl::detail::sub;
    for (int l = 0; l < nz; ++l)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const int c[8] = {id(i, j, l),     id(i + 1, j, l),     id(i + 1, j + 1, l),     id(i, j + 1, l),
                                  id(i, j, l + 1), id(i + 1, j, l + 1), id(i + 1, j + 1, l + 1), id(i, j + 1, l + 1)};
                for (const auto& t : kTets) {
                    std::array<int, 4> tet = {c[t[0]], c[t[1]], c[t[2]], c[t[3]]};
                    const auto& p = m.points;
                    const P3 e1 = sub(p[std::size_t(tet[1])], p[std::size_t(tet[0])]);
                    const P3 e2 = sub(p[std::size_t(tet[2])], p[std::size_t(tet[0])]);
                    const P3 e3 = sub(p[std::size_t(tet[3])], p[std::size_t(tet[0])]);
                    if (dot(cross(e1, e2), e3) < 0) std::swap(tet[2], tet[3]);
                    m.tetrahedra.push_back(tet);
                }
            }
    // outer faces: 2 triangles per boundary quad, normals outward
    const int size[3] = {nx, ny, nz};
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            P3 out{0, 0, 0};
            out[std::size_t(axis)] = side == 0 ? -1.0 : 1.0;
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            for (int u = 0; u < size[a1]; ++u)
                for (int v = 0; v < size[a2]; ++v) {
                    const auto node = [&](int du, int dv) {
                        std::array<int, 3> g{};
                        g[std::size_t(axis)] = side == 0 ? 0 : size[axis];
                        g[std::size_t(a1)] = u + du;
                        g[std::size_t(a2)] = v + dv;
                        return id(g[0], g[1], g[2]);
                    };
                    const int q0 = node(0, 0), q1 = node(1, 0), q2 = node(1, 1), q3 = node(0, 1);
                    m.triangles.push_back(cubes_in_bowl::detail::oriented(m.points, q0, q1, q2, out));
                    m.triangles.push_back(cubes_in_bowl::detail::oriented(m.points, q0, q2, q3, out));
                }
        }
    return m;
}

/// Where the body's frame starts (m): its bottom centre, `offset` −x of the organ's highest point
/// and alarm distance + `clearance` above it.
inline P3 body_translation(const Setup& s, const Mesh& organ) {
    const P3 top = organ_top(organ);
    return {top[0] - s.offset, top[1] + alarm_distance(s) + s.clearance, top[2]};
}

/// The body's mesh as a legacy ASCII VTK unstructured grid (SOFA's MeshVTKLoader): its points, then
/// its tetrahedra (cell type 10) and surface triangles (type 5), in the orders scene_xml writes inline.
inline void write_body_vtk(std::ostream& o, const Mesh& body) {
    namespace d = cubes_in_bowl::detail;
    o << "# vtk DataFile Version 2.0\nsoft body (tests/support/penalty_test/soft_body_on_organ.hpp)\nASCII\n"
      << "DATASET UNSTRUCTURED_GRID\nPOINTS " << body.points.size() << " double\n";
    for (const P3& p : body.points) o << d::num(p[0]) << ' ' << d::num(p[1]) << ' ' << d::num(p[2]) << '\n';
    const std::size_t cells = body.tetrahedra.size() + body.triangles.size();
    o << "CELLS " << cells << ' ' << 5 * body.tetrahedra.size() + 4 * body.triangles.size() << '\n';
    for (const auto& t : body.tetrahedra) o << "4 " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
    for (const auto& t : body.triangles) o << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    o << "CELL_TYPES " << cells << '\n';
    for (std::size_t i = 0; i < body.tetrahedra.size(); ++i) o << "10\n";
    for (std::size_t i = 0; i < body.triangles.size(); ++i) o << "5\n";
}

/// True when the body's lists are too long to be written inline: a scene attribute holds at most
/// 10⁶ values (the positions from n = 136 on, 1 010 394 DOFs), so scene_xml needs a mesh file.
inline bool body_needs_mesh_file(const Setup& s) {
    return 3 * body_nodes(s) > 1'000'000 || 4 * body_tetrahedra(s) > 1'000'000;
}

/// The scene as SOFA .scn text. Nodes `Organ` (state `organ`, model `organ_triangles`) and
/// The body's elastic force field element (Setup::elasticity).
inline std::string elasticity_xml(const Setup& s) {
    namespace d = cubes_in_bowl::detail;
    const std::string material =
        "youngModulus=\"" + d::num(s.young_modulus) + "\" poissonRatio=\"" + d::num(s.poisson_ratio) + "\"";
    switch (s.elasticity) {
        case Elasticity::tetrahedral_corotational:
            return "    <TetrahedralCorotationalFEMForceField " + material + " method=\"large\"/>\n";
        case Elasticity::fast_tetrahedral_corotational:
            return "    <FastTetrahedralCorotationalForceField " + material + " method=\"polar\"/>\n";
        case Elasticity::hyperelastic: {
            // Lamé: μ = E/(2(1+ν)), λ = Eν/((1+ν)(1−2ν))
            const double e = s.young_modulus, nu = s.poisson_ratio;
            return "    <TetrahedronHyperelasticityFEMForceField materialName=\"StVenantKirchhoff\" ParameterSet=\"" +
                   d::num(e / (2 * (1 + nu))) + " " + d::num(e * nu / ((1 + nu) * (1 - 2 * nu))) + "\"/>\n";
        }
        case Elasticity::mesh_springs:
            return "    <MeshSpringForceField tetrasStiffness=\"" + d::num(s.young_modulus * s.body_length / s.cells) +
                   "\" tetrasDamping=\"0\"/>\n";
        case Elasticity::tetrahedron_fem:
            break;
    }
    return "    <TetrahedronFEMForceField " + material + " method=\"large\"/>\n";
}

/// `Body` (state `body`, model `body_triangles`). With `mesh_file` (a .vtk path), the body's mesh
/// is written there (write_body_vtk) and read by a MeshVTKLoader whose `filename` is `mesh_name`
/// (default: mesh_file as given): the same topology as the inline lists.
inline std::string scene_xml(const Setup& s, const std::filesystem::path& mesh_file = {},
                             const std::string& mesh_name = {}) {
    namespace d = cubes_in_bowl::detail;
    const Mesh organ = organ_mesh(s);
    const Mesh body = body_mesh(s);
    const P3 t = body_translation(s, organ);
    std::ostringstream o;
    o << "<?xml version=\"1.0\"?>\n"
      << "<!-- generated by tests/support/penalty_test/soft_body_on_organ.hpp: n = " << s.cells << ", "
      << body_tetrahedra(s) << " tetrahedra, " << 3 * body_nodes(s) << " DOFs, " << organ.triangles.size()
      << " organ triangles -->\n"
      << "<Node name=\"root\" dt=\"" << d::num(s.dt) << "\" gravity=\"0 -9.81 0\">\n"
      << "  <DefaultAnimationLoop/>\n  <CollisionPipeline/>\n  <BruteForceBroadPhase/>\n  <BVHNarrowPhase/>\n"
      << "  <NewProximityIntersection alarmDistance=\"" << d::num(alarm_distance(s)) << "\" contactDistance=\""
      << d::num(contact_distance(s)) << "\"/>\n"
      << "  <CollisionResponse response=\"PenalityContactForceField\"/>\n";
    o << "  <Node name=\"Organ\">\n    <MeshTopology position=\"";
    d::write_points(o, organ.points);
    o << "\" triangles=\"";
    d::write_elements(o, organ.triangles);
    o << "\"/>\n    <MechanicalObject name=\"organ\"/>\n"
      << "    <TriangleCollisionModel name=\"organ_triangles\" simulated=\"0\" moving=\"0\" contactStiffness=\""
      << d::num(contact_stiffness(s)) << "\"/>\n  </Node>\n";
    o << "  <Node name=\"Body\">\n"
      << "    <EulerImplicitSolver rayleighStiffness=\"" << d::num(s.rayleigh_stiffness) << "\" rayleighMass=\""
      << d::num(s.rayleigh_mass) << "\"/>\n"
      << "    <CGLinearSolver iterations=\"" << s.cg_iterations << "\" tolerance=\"" << d::num(s.cg_tolerance)
      << "\" threshold=\"" << d::num(s.cg_threshold) << "\"/>\n";
    if (mesh_file.empty()) {
        o << "    <MeshTopology position=\"";
        d::write_points(o, body.points);
        o << "\" tetrahedra=\"";
        d::write_elements(o, body.tetrahedra);
        o << "\" triangles=\"";
        d::write_elements(o, body.triangles);
        o << "\"/>\n";
    } else {
        std::ofstream file(mesh_file);
        write_body_vtk(file, body);
        if (!file) throw std::runtime_error("cannot write the body's mesh " + mesh_file.string());
        o << "    <MeshVTKLoader name=\"body_mesh\" filename=\"" << (mesh_name.empty() ? mesh_file.string() : mesh_name)
          << "\"/>\n"
          << "    <MeshTopology src=\"@body_mesh\"/>\n";
    }
    o << "    <MechanicalObject name=\"body\" translation=\"" << d::num(t[0]) << ' ' << d::num(t[1]) << ' '
      << d::num(t[2]) << "\"/>\n"
      << "    <UniformMass totalMass=\"" << d::num(s.body_mass) << "\"/>\n"
      << elasticity_xml(s) << "    <TriangleCollisionModel name=\"body_triangles\" contactStiffness=\""
      << d::num(contact_stiffness(s)) << "\"/>\n  </Node>\n</Node>\n";
    return o.str();
}

}  // namespace penalty::test::soft_body_on_organ
