#pragma once
// The whole-scene scaling scene (issue 17): k×k×k small deformable cubes in a lattice above a
// static bowl (a spherical cap), as SOFA scene text (.scn) for scene::build_scene. Header-only,
// standard library only; used by bench/bench_scaling.cpp and tests/scene/test_cubes_in_bowl.cpp.
//
// Each cube: `cells`³ hexahedral cells of 6 tetrahedra (TetrahedronFEMForceField, corotational),
// UniformMass, and a TriangleCollisionModel on its outer faces (2 triangles per boundary quad,
// normals outward), all on the cube's own MechanicalObject (no mapping). Cube i is the same local
// mesh (centred at the origin), turned by a small pinned pseudo-random rotation and translated to
// its lattice site by the MechanicalObject's `rotation` / `translation`.
// The bowl: the cap (polar angle ≤ 70° from straight down) of a sphere of radius R centred at
// (0, R, 0) (bottom at the origin), triangles of edge ≈ 0.1 m with normals toward the centre, a static
// TriangleCollisionModel (simulated="0" moving="0") outside every solver's subtree.
// One EulerImplicitSolver + CGLinearSolver over the node `Cubes` (every cube), NewProximity,
// SOFA's penalty response. Gravity −9.81 along y.
//
// Sizes: the bowl radius grows with the lattice so that the lattice starts inside the bowl, its
// lowest layer just above the bowl (bowl_radius, lattice_bottom): the cubes fall a few
// centimetres (the upper layers of large k up to about half a metre), slide toward the bottom and
// pile up; the contacts per step grow with k.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace penalty::test::cubes_in_bowl {

/// What scene_xml() builds. Units: m, kg, s, Pa.
struct Setup {
    int k = 1;                   ///< cubes per lattice edge (k³ cubes)
    int cells = 1;               ///< FEM cells per cube edge: (cells + 1)³ nodes, 6·cells³ tetrahedra
    double cube_size = 0.1;      ///< edge length a (m)
    double gap = 0.03;           ///< free space between neighbouring cubes of the lattice (m)
    double clearance = 0.02;     ///< free space between the lattice's bounding spheres and the bowl (m)
    double bowl_ratio = 1.5;     ///< bowl radius / horizontal extent of the lattice (bowl_radius)
    double cube_mass = 1.0;      ///< kg per cube (1000 kg/m³ at a = 0.1 m)
    double young_modulus = 2e5;  ///< Pa
    double poisson_ratio = 0.3;
    double spring_stiffness = 5e3;  ///< ks of every contact spring (N/m); see contact_stiffness()
    /// NewProximity alarmDistance A (m): element pairs closer than A get a spring, active closer than C
    double alarm_distance = 0.015;
    /// NewProximity contactDistance C (m): more than twice the static penetration under a column of
    /// 8 cubes (about 20 N per corner spring / ks = 4 mm); with C = 5 mm loaded corners were seen
    /// to sink through the bowl's triangles in piles of k ≥ 3
    double contact_distance = 0.01;
    double dt = 0.005;                 ///< s
    double rayleigh_stiffness = 0.05;  ///< EulerImplicitSolver rayleighStiffness (s)
    /// EulerImplicitSolver rayleighMass (1/s): a strong drag (terminal speed g/10 ≈ 1 m/s, a
    /// corner moves at most about C/2 per step) so that the frictionless cubes stop sliding within
    /// about two seconds and fast corners do not tunnel through the bowl (with 5/s, 185 of the 4096
    /// nodes of k = 8 ended beyond the bowl)
    double rayleigh_mass = 10.0;
    int cg_iterations = 1000;  ///< CGLinearSolver iterations (a limit, not expected to bind)
    double cg_tolerance = 1e-9;
    double cg_threshold = 1e-12;
    double max_tilt_deg = 10.0;  ///< each cube turns by up to ± this about x, y and z
    double bowl_cap_deg = 70.0;  ///< the bowl is the sphere's cap of polar angle ≤ this (from straight down)
    double bowl_edge = 0.1;      ///< about the bowl triangles' edge length (m)
};

/// contactStiffness k of every model: SOFA's law gives a spring ks = k·k/dist with dist = C (no
/// model contactDistance), so k = √(ks·C).
inline double contact_stiffness(const Setup& s) { return std::sqrt(s.spring_stiffness * s.contact_distance); }

/// Lattice pitch (m): cube edge plus gap.
inline double pitch(const Setup& s) { return s.cube_size + s.gap; }

/// Radius of a sphere about a cube's centre that holds the cube in any orientation (m).
inline double cube_bounding_radius(const Setup& s) { return 0.5 * std::sqrt(3.0) * s.cube_size; }

/// Horizontal distance from the bowl's axis to the centre of a corner column of the lattice (m).
inline double corner_column_offset(const Setup& s) { return 0.5 * (s.k - 1) * pitch(s) * std::numbers::sqrt2; }

/// Bowl radius R (m): bowl_ratio × (corner column offset + bounding radius) + cube edge.
inline double bowl_radius(const Setup& s) {
    return s.bowl_ratio * (corner_column_offset(s) + cube_bounding_radius(s)) + s.cube_size;
}

/// Height of the lowest layer's cube centres (m): the corner cubes' bounding spheres lie
/// `clearance` inside the bowl, |(h, y0 − R)| + r_b + clearance = R, h = corner_column_offset.
inline double lattice_bottom(const Setup& s) {
    const double R = bowl_radius(s);
    const double inner = R - cube_bounding_radius(s) - s.clearance;
    const double h = corner_column_offset(s);
    return R - std::sqrt(inner * inner - h * h);
}

/// Centre of the bowl's sphere (m): (0, R, 0); the bowl's bottom is the origin.
inline std::array<double, 3> bowl_centre(const Setup& s) { return {0.0, bowl_radius(s), 0.0}; }

/// Rings of the bowl mesh around its bottom point: arc length of the cap / bowl_edge, rounded up.
inline int bowl_rings(const Setup& s) {
    return std::max(1, int(std::ceil(bowl_radius(s) * s.bowl_cap_deg * std::numbers::pi / 180.0 / s.bowl_edge)));
}

/// Height of the bowl's rim (m): R·(1 − cos θ_max).
inline double bowl_rim_height(const Setup& s) {
    return bowl_radius(s) * (1.0 - std::cos(s.bowl_cap_deg * std::numbers::pi / 180.0));
}

/// Number of cubes, k³.
inline int cube_count(const Setup& s) { return s.k * s.k * s.k; }

/// Nodes of one cube, (cells + 1)³.
inline int nodes_per_cube(const Setup& s) { return (s.cells + 1) * (s.cells + 1) * (s.cells + 1); }

namespace detail {

using P3 = std::array<double, 3>;

inline P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline P3 cross(const P3& a, const P3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Orders triangle (a, b, c) so that its normal (b − a) × (c − a) points along `toward`.
inline std::array<int, 3> oriented(const std::vector<P3>& p, int a, int b, int c, const P3& toward) {
    const P3 n = cross(sub(p[std::size_t(b)], p[std::size_t(a)]), sub(p[std::size_t(c)], p[std::size_t(a)]));
    if (dot(n, toward) < 0) return {a, c, b};
    return {a, b, c};
}

/// Local mesh of one cube, centred at the origin.
struct CubeMesh {
    std::vector<P3> points;
    std::vector<std::array<int, 4>> tetrahedra;  ///< positive volume
    std::vector<std::array<int, 3>> triangles;   ///< boundary, normals outward
};

inline CubeMesh cube_mesh(const Setup& s) {
    const int n = s.cells + 1;
    const double h = s.cube_size / s.cells;
    const auto id = [n](int i, int j, int l) { return i + n * (j + n * l); };
    CubeMesh m;
    for (int l = 0; l < n; ++l)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                m.points.push_back(
                    {-0.5 * s.cube_size + i * h, -0.5 * s.cube_size + j * h, -0.5 * s.cube_size + l * h});
    // hexahedron corners in SOFA's order (0..7: x then y then z), split into 6 tetrahedra
    // (Hexa2TetraTopologicalMapping's pattern); each tetrahedron's order fixed to a positive volume
    constexpr int kTets[6][4] = {{0, 5, 1, 6}, {0, 1, 3, 6}, {1, 3, 6, 2}, {6, 3, 0, 7}, {6, 7, 0, 5}, {7, 5, 4, 0}};
    for (int l = 0; l < s.cells; ++l)
        for (int j = 0; j < s.cells; ++j)
            for (int i = 0; i < s.cells; ++i) {
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
    // boundary quads of the 6 faces, 2 triangles each, normal along the face's outward axis
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            P3 out{0, 0, 0};
            out[std::size_t(axis)] = side == 0 ? -1.0 : 1.0;
            const int fixed = side == 0 ? 0 : s.cells;
            for (int u = 0; u < s.cells; ++u)
                for (int v = 0; v < s.cells; ++v) {
                    const auto node = [&](int du, int dv) {
                        std::array<int, 3> ijk{};
                        ijk[std::size_t(axis)] = fixed;
                        ijk[std::size_t((axis + 1) % 3)] = u + du;
                        ijk[std::size_t((axis + 2) % 3)] = v + dv;
                        return id(ijk[0], ijk[1], ijk[2]);
                    };
                    const int q0 = node(0, 0), q1 = node(1, 0), q2 = node(1, 1), q3 = node(0, 1);
                    m.triangles.push_back(oriented(m.points, q0, q1, q2, out));
                    m.triangles.push_back(oriented(m.points, q0, q2, q3, out));
                }
        }
    return m;
}

/// Bowl points and triangles.
struct BowlMesh {
    std::vector<P3> points;
    std::vector<std::array<int, 3>> triangles;
};

/// The bowl's mesh (normals toward the sphere's centre): the cap of polar angle
/// θ ≤ bowl_cap_deg, as a triangulated disk mapped onto the sphere (ring r at θ = θ_max·r/rings
/// with 6r points, the pole ring 0 one point; neighbouring rings zipped by angle), so that every
/// triangle has edges of about bowl_edge.
inline BowlMesh bowl_mesh(const Setup& s) {
    const double R = bowl_radius(s);
    const double theta_max = s.bowl_cap_deg * std::numbers::pi / 180.0;
    const int rings = bowl_rings(s);
    const P3 centre = {0.0, R, 0.0};
    BowlMesh m;
    std::vector<int> first(std::size_t(rings) + 1);  // index of ring r's first point
    for (int r = 0; r <= rings; ++r) {
        first[std::size_t(r)] = int(m.points.size());
        const double theta = theta_max * r / rings;
        const int n = r == 0 ? 1 : 6 * r;
        for (int g = 0; g < n; ++g) {
            const double phi = 2.0 * std::numbers::pi * g / n;
            m.points.push_back(
                {R * std::sin(theta) * std::cos(phi), R - R * std::cos(theta), R * std::sin(theta) * std::sin(phi)});
        }
    }
    const auto add = [&](int a, int b, int c) {
        const auto& p = m.points;
        const P3 mid = {(p[std::size_t(a)][0] + p[std::size_t(b)][0] + p[std::size_t(c)][0]) / 3.0,
                        (p[std::size_t(a)][1] + p[std::size_t(b)][1] + p[std::size_t(c)][1]) / 3.0,
                        (p[std::size_t(a)][2] + p[std::size_t(b)][2] + p[std::size_t(c)][2]) / 3.0};
        m.triangles.push_back(oriented(p, a, b, c, sub(centre, mid)));
    };
    // zip ring r − 1 (n1 points) and ring r (n2 points): advance on the ring whose next point
    // comes first in angle (fractions i/n1, j/n2 of a turn; ties advance the inner ring)
    for (int r = 1; r <= rings; ++r) {
        const int n1 = r == 1 ? 1 : 6 * (r - 1), n2 = 6 * r;
        const auto inner = [&](int i) { return first[std::size_t(r - 1)] + i % n1; };
        const auto outer = [&](int j) { return first[std::size_t(r)] + j % n2; };
        int i = 0, j = 0;
        while (i < n1 || j < n2) {
            const bool advance_inner = j == n2 || (i < n1 && (i + 1) * n2 <= (j + 1) * n1);
            if (advance_inner && n1 > 1) {
                add(inner(i), outer(j), inner(i + 1));
                ++i;
            } else if (advance_inner) {
                ++i;  // the pole: a single point, nothing to advance
            } else {
                add(inner(i), outer(j), outer(j + 1));
                ++j;
            }
        }
    }
    return m;
}

/// Shortest text that reads back as the same double (std::to_chars).
inline std::string num(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

inline void write_points(std::ostream& o, const std::vector<P3>& points) {
    for (std::size_t i = 0; i < points.size(); ++i)
        o << (i == 0 ? "" : "  ") << num(points[i][0]) << ' ' << num(points[i][1]) << ' ' << num(points[i][2]);
}

template <std::size_t N>
void write_elements(std::ostream& o, const std::vector<std::array<int, N>>& elements) {
    for (std::size_t i = 0; i < elements.size(); ++i)
        for (std::size_t j = 0; j < N; ++j) o << (i == 0 && j == 0 ? "" : " ") << elements[i][j];
}

}  // namespace detail

/// Centre of cube (ix, iy, iz) of the lattice before the fall (m); ix, iz along x, z, iy upward.
inline std::array<double, 3> lattice_site(const Setup& s, int ix, int iy, int iz) {
    const double half = 0.5 * (s.k - 1);
    return {(ix - half) * pitch(s), lattice_bottom(s) + iy * pitch(s), (iz - half) * pitch(s)};
}

/// The scene as SOFA .scn text. Node names: `Bowl`; `Cubes/Cube_<i>` with i = ix + k·(iz + k·iy)
/// (layer by layer from the bottom), state `cube_<i>`, model `cube_<i>_triangles`.
inline std::string scene_xml(const Setup& s) {
    std::ostringstream o;
    o << "<?xml version=\"1.0\"?>\n"
      << "<!-- generated by tests/support/penalty_test/cubes_in_bowl.hpp: k = " << s.k << ", " << cube_count(s)
      << " cubes -->\n"
      << "<Node name=\"root\" dt=\"" << detail::num(s.dt) << "\" gravity=\"0 -9.81 0\">\n"
      << "  <DefaultAnimationLoop/>\n  <CollisionPipeline/>\n  <BruteForceBroadPhase/>\n  <BVHNarrowPhase/>\n"
      << "  <NewProximityIntersection alarmDistance=\"" << detail::num(s.alarm_distance) << "\" contactDistance=\""
      << detail::num(s.contact_distance) << "\"/>\n"
      << "  <CollisionResponse response=\"PenalityContactForceField\"/>\n";
    const detail::BowlMesh bowl = detail::bowl_mesh(s);
    o << "  <Node name=\"Bowl\">\n    <MeshTopology position=\"";
    detail::write_points(o, bowl.points);
    o << "\" triangles=\"";
    detail::write_elements(o, bowl.triangles);
    o << "\"/>\n    <MechanicalObject name=\"bowl\"/>\n"
      << "    <TriangleCollisionModel name=\"bowl_triangles\" simulated=\"0\" moving=\"0\" contactStiffness=\""
      << detail::num(contact_stiffness(s)) << "\"/>\n  </Node>\n";
    o << "  <Node name=\"Cubes\">\n"
      << "    <EulerImplicitSolver rayleighStiffness=\"" << detail::num(s.rayleigh_stiffness) << "\" rayleighMass=\""
      << detail::num(s.rayleigh_mass) << "\"/>\n"
      << "    <CGLinearSolver iterations=\"" << s.cg_iterations << "\" tolerance=\"" << detail::num(s.cg_tolerance)
      << "\" threshold=\"" << detail::num(s.cg_threshold) << "\"/>\n";
    const detail::CubeMesh cube = detail::cube_mesh(s);
    std::ostringstream mesh;
    mesh << "position=\"";
    detail::write_points(mesh, cube.points);
    mesh << "\" tetrahedra=\"";
    detail::write_elements(mesh, cube.tetrahedra);
    mesh << "\" triangles=\"";
    detail::write_elements(mesh, cube.triangles);
    mesh << "\"";
    const std::string mesh_attributes = mesh.str();
    // tilts: mt19937's output is fixed by the standard (seed 17), mapped to [−1, 1) by hand
    // (the standard distributions differ between libraries)
    std::mt19937 rng(17);
    const auto tilt = [&] { return s.max_tilt_deg * (2.0 * (double(rng()) / 4294967296.0) - 1.0); };
    for (int iy = 0; iy < s.k; ++iy)
        for (int iz = 0; iz < s.k; ++iz)
            for (int ix = 0; ix < s.k; ++ix) {
                const int i = ix + s.k * (iz + s.k * iy);
                const auto c = lattice_site(s, ix, iy, iz);
                const double rx = tilt(), ry = tilt(), rz = tilt();
                o << "    <Node name=\"Cube_" << i << "\">\n      <MeshTopology " << mesh_attributes << "/>\n"
                  << "      <MechanicalObject name=\"cube_" << i << "\" rotation=\"" << detail::num(rx) << ' '
                  << detail::num(ry) << ' ' << detail::num(rz) << "\" translation=\"" << detail::num(c[0]) << ' '
                  << detail::num(c[1]) << ' ' << detail::num(c[2]) << "\"/>\n"
                  << "      <UniformMass totalMass=\"" << detail::num(s.cube_mass) << "\"/>\n"
                  << "      <TetrahedronFEMForceField youngModulus=\"" << detail::num(s.young_modulus)
                  << "\" poissonRatio=\"" << detail::num(s.poisson_ratio) << "\" method=\"large\"/>\n"
                  << "      <TriangleCollisionModel name=\"cube_" << i << "_triangles\" contactStiffness=\""
                  << detail::num(contact_stiffness(s)) << "\"/>\n    </Node>\n";
            }
    o << "  </Node>\n</Node>\n";
    return o.str();
}

}  // namespace penalty::test::cubes_in_bowl
