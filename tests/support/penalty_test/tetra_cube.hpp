#pragma once
// A cube of n³ unit cells, 5 positively oriented tetrahedra each (neighbouring cells mirrored so
// that their faces match), and a square sheet of triangles: the project's small meshes for the
// topological-change tests, as lists and as scene attribute text.
#include "penalty/mechanics/topology.hpp"

#include <sstream>
#include <string>
#include <vector>

namespace penalty::test {

struct TetraCube {
    std::vector<Vec3> points;
    std::vector<Tetrahedron> tetrahedra;
};

inline TetraCube tetra_cube(int n, double size = 1.0) {
    TetraCube c;
    const auto id = [n](int x, int y, int z) { return PointId(x + (n + 1) * (y + (n + 1) * z)); };
    for (int z = 0; z <= n; ++z)
        for (int y = 0; y <= n; ++y)
            for (int x = 0; x <= n; ++x) c.points.push_back(Vec3(x, y, z) * (size / n));
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const PointId v[8] = {
                    id(x, y, z),     id(x + 1, y, z),     id(x + 1, y + 1, z),     id(x, y + 1, z),
                    id(x, y, z + 1), id(x + 1, y, z + 1), id(x + 1, y + 1, z + 1), id(x, y + 1, z + 1)};
                static constexpr int kEven[5][4] = {
                    {0, 1, 3, 4}, {1, 2, 3, 6}, {1, 4, 5, 6}, {3, 4, 6, 7}, {1, 3, 4, 6}};
                static constexpr int kOdd[5][4] = {
                    {0, 1, 2, 5}, {0, 2, 3, 7}, {0, 4, 5, 7}, {2, 5, 6, 7}, {0, 2, 5, 7}};
                for (const auto& t : (x + y + z) % 2 == 0 ? kEven : kOdd) {
                    Tetrahedron tet{v[t[0]], v[t[1]], v[t[2]], v[t[3]]};
                    const Vec3& a = c.points[std::size_t(tet[0])];
                    if ((c.points[std::size_t(tet[1])] - a)
                            .cross(c.points[std::size_t(tet[2])] - a)
                            .dot(c.points[std::size_t(tet[3])] - a) < 0)
                        std::swap(tet[2], tet[3]);
                    c.tetrahedra.push_back(tet);
                }
            }
    return c;
}

/// An n×n sheet of unit squares in the plane y = height, two triangles each, x and z in [0, n·size].
struct TriangleSheet {
    std::vector<Vec3> points;
    std::vector<Triangle> triangles;
};

inline TriangleSheet triangle_sheet(int n, double size, double height = 0.0) {
    TriangleSheet s;
    for (int z = 0; z <= n; ++z)
        for (int x = 0; x <= n; ++x) s.points.push_back(Vec3(x * size, height, z * size));
    const auto id = [n](int x, int z) { return PointId(x + (n + 1) * z); };
    for (int z = 0; z < n; ++z)
        for (int x = 0; x < n; ++x) {
            s.triangles.push_back({id(x, z), id(x, z + 1), id(x + 1, z)});
            s.triangles.push_back({id(x + 1, z), id(x, z + 1), id(x + 1, z + 1)});
        }
    return s;
}

/// "x y z  x y z ..." (17 significant digits).
inline std::string points_text(const std::vector<Vec3>& p) {
    std::ostringstream out;
    out.precision(17);
    for (const Vec3& v : p) out << v.x() << ' ' << v.y() << ' ' << v.z() << "  ";
    return out.str();
}

template <std::size_t N>
std::string elements_text(const std::vector<std::array<PointId, N>>& e) {
    std::ostringstream out;
    for (const auto& x : e) {
        for (const PointId p : x) out << p << ' ';
        out << ' ';
    }
    return out.str();
}

/// The scene text's first lines shared by the topological-change tests: a root of `gravity` (and
/// dt 0.01) holding a node "body" with the 2×2×2-cell tetrahedral cube of side 0.2 m (a
/// TetrahedronSetTopologyContainer "volume" and its modifier, "dofs", DiagonalMass 1000 kg/m³,
/// TetrahedronFEMForceField large E = 2000 Pa, ν = 0.3) fixed at its x = 0 face, over eight lines
/// (the caller writes the rest and closes both nodes).
inline std::string fixed_tetra_cube_head(const std::string& gravity) {
    const TetraCube cube = tetra_cube(2, 0.2);
    return R"(<Node name="root" gravity=")" + gravity + R"(" dt="0.01"><DefaultAnimationLoop/><Node name="body">
  <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
  <CGLinearSolver iterations="200" tolerance="1e-20" threshold="1e-20"/>
  <TetrahedronSetTopologyContainer name="volume" position=")" +
           points_text(cube.points) + R"(" tetrahedra=")" + elements_text(cube.tetrahedra) + R"("/>
  <TetrahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <DiagonalMass massDensity="1000"/>
  <TetrahedronFEMForceField youngModulus="2000" poissonRatio="0.3" method="large"/>
  <FixedProjectiveConstraint indices="3 6 9 12 15 18 21 24"/>
)";
}

}  // namespace penalty::test
