#pragma once
// A spring cube sliding over static points, as SOFA scene text (.scn) for scene::build_scene: the
// scene of the FixedReaders and fused-contact-product tests. Header-only, standard library only.
//
// Cube: 0.4 m, 8 points, MeshSpringForceField on its hexahedron, 2 m/s along x, in node "Body"
// with its own EulerImplicitSolver; its bottom face (y = 0.02) is a 5 × 5 vertex grid of 32
// triangles facing down (node "Body/Surface", a BarycentricMapping of the cube: a mapped state of
// selected rows). Floor: static points (PointCollisionModel) in rows along x at the given z,
// 0.13 m apart, under a few of the face's triangles at a time. MinProximity, A = 0.05 m,
// C = 0.02 m. With corner_spheres, a SphereCollisionModel (r = 0.03 m) on the cube's own state.
#include <sstream>
#include <string>
#include <vector>

namespace penalty::test {

struct SlidingCube {
    std::vector<double> floor_rows_z = {0.11, 0.29};  ///< z (m) of each row of 25 floor points
    bool corner_spheres = false;                      ///< spheres on the cube's own 8 points
};

inline std::string sliding_cube_xml(const SlidingCube& c = {}) {
    std::ostringstream s;
    s << R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <CollisionPipeline/>
  <BruteForceBroadPhase/>
  <BVHNarrowPhase/>
  <MinProximityIntersection alarmDistance="0.05" contactDistance="0.02"/>
  <CollisionResponse response="PenalityContactForceField"/>
  <Node name="Body">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <MechanicalObject position="0 0.02 0  0.4 0.02 0  0 0.42 0  0.4 0.42 0  0 0.02 0.4  0.4 0.02 0.4  0 0.42 0.4  0.4 0.42 0.4"
                      velocity="2 0 0  2 0 0  2 0 0  2 0 0  2 0 0  2 0 0  2 0 0  2 0 0"/>
    <MeshTopology hexas="0 1 3 2 4 5 7 6"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="500" damping="1"/>
)";
    if (c.corner_spheres) s << "    <SphereCollisionModel radius=\"0.03\" contactStiffness=\"100\"/>\n";
    s << R"(    <Node name="Surface">
      <MeshTopology position=")";
    for (int k = 0; k <= 4; ++k)
        for (int i = 0; i <= 4; ++i) s << 0.1 * i << " 0.02 " << 0.1 * k << "  ";
    s << R"(" triangles=")";
    const auto v = [](int i, int k) { return 5 * k + i; };
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 4; ++i)
            s << v(i, k) << ' ' << v(i + 1, k) << ' ' << v(i, k + 1) << "  " << v(i + 1, k) << ' ' << v(i + 1, k + 1)
              << ' ' << v(i, k + 1) << "  ";
    s << R"("/>
      <MechanicalObject/>
      <TriangleCollisionModel contactStiffness="200"/>
      <BarycentricMapping/>
    </Node>
  </Node>
  <Node name="Floor">
    <MechanicalObject position=")";
    for (const double z : c.floor_rows_z)
        for (int i = 0; i < 25; ++i) s << -0.2 + 0.13 * i << " 0 " << z << "  ";
    s << R"("/>
    <PointCollisionModel simulated="0" moving="0" contactStiffness="200"/>
  </Node>
</Node>
)";
    return s.str();
}

}  // namespace penalty::test
