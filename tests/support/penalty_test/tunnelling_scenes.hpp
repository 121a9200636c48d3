#pragma once
// The tunnelling guard's cases (docs/no-tunnelling.md), as SOFA scene text for scene::build_scene.
// Header-only, standard library only; used by tests/scene/test_tunnelling_guard.cpp and
// bench/bench_tunnelling.cpp. Units: m, kg, s, N.
//
//   ball_on_sheet    a ball (a 1 kg particle with a SphereCollisionModel of radius 0.1) thrown
//                    down at 10–50 m/s onto a single-layer 1 m × 1 m triangle sheet (static, or a
//                    spring cloth pinned at its corners), NewProximity;
//   draped_sheet     a thin FEM sheet (TriangularFEMForceField) dropped onto a static triangulated
//                    sphere, then pulled down on two opposite edges (ConstantForceField);
//   band_on_pegs     an elastic band (a closed loop of MeshSpringForceField springs, Point and Line
//                    models) stretched around two static triangulated pegs and pulled fast
//                    sideways at its middle;
//   the bowl         cubes_in_bowl.hpp (bench_scaling's scene).
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace penalty::test::tunnelling {

using P3 = std::array<double, 3>;

/// Shortest text that reads back as the same double.
inline std::string num(double x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

struct Mesh {
    std::vector<P3> points;
    std::vector<std::array<int, 3>> triangles;
    std::vector<std::array<int, 2>> edges;
};

inline std::string points_text(const std::vector<P3>& p) {
    std::ostringstream o;
    for (std::size_t i = 0; i < p.size(); ++i)
        o << (i ? "  " : "") << num(p[i][0]) << ' ' << num(p[i][1]) << ' ' << num(p[i][2]);
    return o.str();
}
template <std::size_t N>
std::string elements_text(const std::vector<std::array<int, N>>& e) {
    std::ostringstream o;
    for (std::size_t i = 0; i < e.size(); ++i)
        for (std::size_t j = 0; j < N; ++j) o << (i == 0 && j == 0 ? "" : " ") << e[i][j];
    return o.str();
}

/// An n × n-cell grid in the plane y = height, x and z in [−size/2, size/2], two triangles a cell
/// (normals +y), its edges.
inline Mesh grid(int n, double size, double height) {
    Mesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            m.points.push_back({-0.5 * size + size * i / n, height, -0.5 * size + size * j / n});
    const auto id = [n](int i, int j) { return i + (n + 1) * j; };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j)});
            m.triangles.push_back({id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)});
        }
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            if (i < n) m.edges.push_back({id(i, j), id(i + 1, j)});
            if (j < n) m.edges.push_back({id(i, j), id(i, j + 1)});
            if (i < n && j < n) m.edges.push_back({id(i + 1, j), id(i, j + 1)});
        }
    return m;
}

/// A UV sphere of `rings` × `segments` (poles included), centre c, radius r, normals outward.
inline Mesh uv_sphere(const P3& c, double r, int rings, int segments) {
    Mesh m;
    m.points.push_back({c[0], c[1] + r, c[2]});
    for (int k = 1; k < rings; ++k) {
        const double th = std::numbers::pi * k / rings;
        for (int s = 0; s < segments; ++s) {
            const double ph = 2.0 * std::numbers::pi * s / segments;
            m.points.push_back({c[0] + r * std::sin(th) * std::cos(ph), c[1] + r * std::cos(th),
                                c[2] + r * std::sin(th) * std::sin(ph)});
        }
    }
    m.points.push_back({c[0], c[1] - r, c[2]});
    const int south = int(m.points.size()) - 1;
    const auto ring = [&](int k, int s) { return 1 + (k - 1) * segments + (s % segments); };
    for (int s = 0; s < segments; ++s) m.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
    for (int k = 1; k + 1 < rings; ++k)
        for (int s = 0; s < segments; ++s) {
            m.triangles.push_back({ring(k, s), ring(k, s + 1), ring(k + 1, s)});
            m.triangles.push_back({ring(k, s + 1), ring(k + 1, s + 1), ring(k + 1, s)});
        }
    for (int s = 0; s < segments; ++s) m.triangles.push_back({south, ring(rings - 1, s), ring(rings - 1, s + 1)});
    return m;
}

/// A closed vertical cylinder (axis along y from y0 to y1 at (x, z)), `segments` sides, capped.
inline Mesh cylinder(double x, double z, double radius, double y0, double y1, int segments) {
    Mesh m;
    for (int level = 0; level < 2; ++level)
        for (int s = 0; s < segments; ++s) {
            const double ph = 2.0 * std::numbers::pi * s / segments;
            m.points.push_back({x + radius * std::cos(ph), level ? y1 : y0, z + radius * std::sin(ph)});
        }
    m.points.push_back({x, y0, z});
    m.points.push_back({x, y1, z});
    const int bottom = 2 * segments, top = bottom + 1;
    for (int s = 0; s < segments; ++s) {
        const int a = s, b = (s + 1) % segments, c = segments + s, d = segments + (s + 1) % segments;
        m.triangles.push_back({a, c, b});
        m.triangles.push_back({b, c, d});
        m.triangles.push_back({bottom, a, b});
        m.triangles.push_back({top, d, c});
    }
    return m;
}

inline std::string header(double dt, double alarm, double contact, const std::string& guard) {
    std::ostringstream o;
    o << "<?xml version=\"1.0\"?>\n<Node name=\"root\" dt=\"" << num(dt) << "\" gravity=\"0 -9.81 0\">\n"
      << "  <DefaultAnimationLoop/>\n  <CollisionPipeline name=\"pipeline\"";
    if (!guard.empty()) o << " noTunnelling=\"" << guard << "\"";
    o << "/>\n  <BruteForceBroadPhase/>\n  <BVHNarrowPhase/>\n"
      << "  <NewProximityIntersection alarmDistance=\"" << num(alarm) << "\" contactDistance=\"" << num(contact)
      << "\"/>\n"
      << "  <CollisionResponse response=\"PenalityContactForceField\"/>\n";
    return o.str();
}

inline std::string static_mesh_node(const std::string& name, const Mesh& m, double stiffness, bool lines_and_points) {
    std::ostringstream o;
    const std::string fixed = "\" simulated=\"0\" moving=\"0\" contactStiffness=\"" + num(stiffness) + "\"/>\n";
    o << "  <Node name=\"" << name << "\">\n    <MeshTopology position=\"" << points_text(m.points) << "\" triangles=\""
      << elements_text(m.triangles) << "\"/>\n    <MechanicalObject name=\"" << name << "_dofs\"/>\n"
      << "    <TriangleCollisionModel name=\"" << name << "_triangles" << fixed;
    if (lines_and_points)
        o << "    <LineCollisionModel name=\"" << name << "_lines" << fixed << "    <PointCollisionModel name=\""
          << name << "_points" << fixed;
    o << "  </Node>\n";
    return o.str();
}

// ---- a ball onto a single-layer sheet ------------------------------------------------------------

struct BallOnSheet {
    double speed = 10.0;                  ///< downward speed at the start (m/s)
    double height = 0.3;                  ///< the ball's centre above the sheet at the start (m)
    double radius = 0.1;                  ///< m
    double mass = 1.0;                    ///< kg
    double dt = 0.005;                    ///< s
    double alarm = 0.05, contact = 0.02;  ///< NewProximity A, C (m)
    /// contactStiffness of both models: ks = k²/(C + r) = 3333 N/m, the ball's one spring (SOFA's
    /// law; NewProximity gives a sphere one contact): ½·ks·(C + r)² = 24 J, below ½·m·v² = 50 J
    /// (10 m/s) … 1250 J (50 m/s): the spring cannot stop the ball, and from about 30 m/s the
    /// ball moves farther than A + r = 0.15 m in a step
    double stiffness = 20.0;
    int cells = 10;                 ///< the sheet's grid (1 m × 1 m)
    bool deformable_sheet = false;  ///< a spring cloth pinned at its corners instead of a static sheet
    std::string guard;              ///< the pipeline's noTunnelling ("" : none)
};

inline std::string ball_on_sheet_xml(const BallOnSheet& s) {
    std::ostringstream o;
    o << header(s.dt, s.alarm, s.contact, s.guard);
    const Mesh sheet = grid(s.cells, 1.0, 0.0);
    // the ball alone: no Rayleigh damping (its speed is the case); the cloth: some
    const std::string solver =
        s.deformable_sheet ? "<EulerImplicitSolver rayleighStiffness=\"0.05\" rayleighMass=\"0.2\"/>\n"
                             "  <CGLinearSolver iterations=\"1000\" tolerance=\"1e-8\" threshold=\"1e-20\"/>\n"
                           : "<EulerImplicitSolver rayleighStiffness=\"0\" rayleighMass=\"0\"/>\n"
                             "    <CGLinearSolver iterations=\"200\" tolerance=\"1e-12\" threshold=\"1e-20\"/>\n";
    const std::string indent = "  ";
    if (!s.deformable_sheet) {
        o << static_mesh_node("Sheet", sheet, s.stiffness, false);
    } else {
        // one solver, at the root, for the cloth and the ball: their contact, stored in the
        // pipeline's node (spec §2.1), is then implicit
        const int n = s.cells;
        o << "  " << solver;
        o << "  <Node name=\"Sheet\">\n"
          << "    <MeshTopology position=\"" << points_text(sheet.points) << "\" triangles=\""
          << elements_text(sheet.triangles) << "\" edges=\"" << elements_text(sheet.edges)
          << "\"/>\n    <MechanicalObject name=\"sheet\"/>\n"
          << "    <UniformMass totalMass=\"0.5\"/>\n    <MeshSpringForceField stiffness=\"2000\" damping=\"1\"/>\n"
          << "    <FixedConstraint indices=\"0 " << n << " " << (n + 1) * n << " " << (n + 1) * (n + 1) - 1 << "\"/>\n"
          << "    <TriangleCollisionModel name=\"sheet_triangles\" contactStiffness=\"" << num(s.stiffness) << "\"/>\n"
          << "    <PointCollisionModel name=\"sheet_points\" contactStiffness=\"" << num(s.stiffness)
          << "\"/>\n  </Node>\n";
    }
    o << indent << "<Node name=\"Ball\">\n";
    if (!s.deformable_sheet) o << indent << "  " << solver;
    o << indent << "  <MechanicalObject name=\"ball\" position=\"0.03 " << num(s.height) << " 0.04\" velocity=\"0 "
      << num(-s.speed) << " 0\"/>\n"
      << indent << "  <UniformMass totalMass=\"" << num(s.mass) << "\"/>\n"
      << indent << "  <SphereCollisionModel name=\"ball_sphere\" radius=\"" << num(s.radius) << "\" contactStiffness=\""
      << num(s.stiffness) << "\"/>\n"
      << indent << "</Node>\n";
    o << "</Node>\n";
    return o.str();
}

// ---- a thin FEM sheet draped on a sphere and pulled -----------------------------------------------

struct DrapedSheet {
    double dt = 0.01;
    double alarm = 0.02, contact = 0.01;
    double stiffness = 3.0;      ///< contactStiffness of every model: ks = k²/C = 900 N/m
    int cells = 16;              ///< the sheet: 1.2 m × 1.2 m, starting 0.05 m above the sphere's top
    double mass = 0.3;           ///< kg
    double young_modulus = 5e4;  ///< Pa (a membrane of unit thickness: N/m)
    double pull = 1.0;           ///< N down on each node of two opposite edges, from the start
    std::string guard;
};

inline std::string draped_sheet_xml(const DrapedSheet& s) {
    std::ostringstream o;
    o << header(s.dt, s.alarm, s.contact, s.guard);
    o << static_mesh_node("Sphere", uv_sphere({0, 0, 0}, 0.4, 12, 24), s.stiffness, true);
    const int n = s.cells;
    const Mesh sheet = grid(n, 1.2, 0.45);
    std::ostringstream pulled;
    for (int i = 0; i <= n; ++i) pulled << (i ? " " : "") << i << ' ' << i + (n + 1) * n;
    o << "  <Node name=\"Sheet\">\n    <EulerImplicitSolver rayleighStiffness=\"0.02\" rayleighMass=\"0.5\"/>\n"
      << "    <CGLinearSolver iterations=\"1000\" tolerance=\"1e-10\" threshold=\"1e-20\"/>\n"
      << "    <MeshTopology position=\"" << points_text(sheet.points) << "\" triangles=\""
      << elements_text(sheet.triangles) << "\"/>\n    <MechanicalObject name=\"sheet\"/>\n    <UniformMass totalMass=\""
      << num(s.mass) << "\"/>\n"
      << "    <TriangularFEMForceField name=\"fem\" youngModulus=\"" << num(s.young_modulus)
      << "\" poissonRatio=\"0.3\" method=\"large\"/>\n"
      << "    <ConstantForceField name=\"pull\" indices=\"" << pulled.str() << "\" forces=\"0 " << num(-s.pull)
      << " 0\"/>\n"
      << "    <TriangleCollisionModel name=\"sheet_triangles\" contactStiffness=\"" << num(s.stiffness) << "\"/>\n"
      << "    <LineCollisionModel name=\"sheet_lines\" contactStiffness=\"" << num(s.stiffness) << "\"/>\n"
      << "    <PointCollisionModel name=\"sheet_points\" contactStiffness=\"" << num(s.stiffness)
      << "\"/>\n  </Node>\n</Node>\n";
    return o.str();
}

// ---- an elastic band around two pegs, pulled fast ------------------------------------------------

struct BandOnPegs {
    double dt = 0.005;
    double alarm = 0.01, contact = 0.005;
    double stiffness = 5.0;                        ///< contactStiffness: ks = k²/C = 5000 N/m
    int points = 80;                               ///< band points (a closed loop)
    double peg_radius = 0.03, peg_distance = 0.5;  ///< pegs at x = ±peg_distance/2 (m)
    double band_stiffness = 2000;                  ///< N/m per spring, rest length 70 % of the loop's: stretched
    double pull = 30.0;                            ///< N on each of the 5 middle points of one side, along −z
    std::string guard;
};

inline std::string band_on_pegs_xml(const BandOnPegs& s) {
    std::ostringstream o;
    o << header(s.dt, s.alarm, s.contact, s.guard);
    const double half = 0.5 * s.peg_distance;
    o << static_mesh_node("PegLeft", cylinder(-half, 0.0, s.peg_radius, -0.1, 0.1, 16), s.stiffness, true);
    o << static_mesh_node("PegRight", cylinder(half, 0.0, s.peg_radius, -0.1, 0.1, 16), s.stiffness, true);
    // the loop: a stadium around the pegs at y = 0, 5 mm outside them
    const double r = s.peg_radius + 0.005;
    const double perimeter = 2.0 * s.peg_distance + 2.0 * std::numbers::pi * r;
    std::vector<P3> p;
    for (int i = 0; i < s.points; ++i) {
        double a = perimeter * i / s.points;
        if (a < s.peg_distance) {
            p.push_back({-half + a, 0.0, r});
            continue;
        }
        a -= s.peg_distance;
        if (a < std::numbers::pi * r) {
            const double th = a / r;
            p.push_back({half + r * std::sin(th), 0.0, r * std::cos(th)});
            continue;
        }
        a -= std::numbers::pi * r;
        if (a < s.peg_distance) {
            p.push_back({half - a, 0.0, -r});
            continue;
        }
        a -= s.peg_distance;
        const double th = a / r;
        p.push_back({-half - r * std::sin(th), 0.0, -r * std::cos(th)});
    }
    std::vector<std::array<int, 2>> edges;
    for (int i = 0; i < s.points; ++i) edges.push_back({i, (i + 1) % s.points});
    const double rest = 0.7 * perimeter / s.points;
    std::ostringstream springs;
    for (std::size_t i = 0; i < edges.size(); ++i)
        springs << (i ? "  " : "") << edges[i][0] << ' ' << edges[i][1] << ' ' << num(s.band_stiffness) << " 0.5 "
                << num(rest);
    // the middle of the first straight side (z = +r), pulled along +z: away from the pegs' line,
    // which drags the band across the pegs' round side
    std::ostringstream pulled;
    const int mid = int(std::lround(0.5 * s.peg_distance / perimeter * s.points));
    for (int i = mid - 2; i <= mid + 2; ++i) pulled << (i > mid - 2 ? " " : "") << i;
    o << "  <Node name=\"Band\">\n    <EulerImplicitSolver rayleighStiffness=\"0.01\" rayleighMass=\"0.5\"/>\n"
      << "    <CGLinearSolver iterations=\"1000\" tolerance=\"1e-10\" threshold=\"1e-20\"/>\n"
      << "    <MeshTopology position=\"" << points_text(p) << "\" edges=\"" << elements_text(edges) << "\"/>\n"
      << "    <MechanicalObject name=\"band\"/>\n    <UniformMass totalMass=\"0.05\"/>\n"
      << "    <SpringForceField spring=\"" << springs.str() << "\"/>\n"
      << "    <ConstantForceField indices=\"" << pulled.str() << "\" forces=\"0 0 " << num(s.pull) << "\"/>\n"
      << "    <LineCollisionModel name=\"band_lines\" contactStiffness=\"" << num(s.stiffness) << "\"/>\n"
      << "    <PointCollisionModel name=\"band_points\" contactStiffness=\"" << num(s.stiffness)
      << "\"/>\n  </Node>\n</Node>\n";
    return o.str();
}

}  // namespace penalty::test::tunnelling
