// The built-in scene of `penalty run` without a scene file.
#include "penalty/scene/scene.hpp"

namespace penalty::scene {

std::string_view default_scene_xml() {
    // A soft FEM cube (5x5x5 grid, large-displacement tetrahedral FEM, 1 kg) falls on a static
    // floor and a rigid ball (0.5 kg) falls on the cube. One implicit solver at the root holds
    // both bodies, so every contact is integrated implicitly (spec §2.1): floor triangles vs cube
    // points, rigid ball vs cube points, rigid ball vs floor.
    // NewProximity intersection: a sphere-point contact per point (SOFA's id is the index in the
    // larger model) at the sphere's centre, so the ball rests on the four points of a cell of the
    // cube's top. (MinProximity keeps one contact per sphere, SOFA's id = the sphere's index, and
    // SOFA HEAD puts its point on the surface while `dist` counts the radius again: the ball hung
    // on one point at a time, pushed out beyond the alarm distance, and the contact flickered
    // on and off with 67 mm of penetration.)
    // Contact springs ks = k1·k2/dist (SOFA's law): floor-cube 10·10/0.02 = 5000 N/m; ball-cube
    // 85·10/(0.02 + 0.15) = 5000 N/m too (the ball's dist holds its radius).
    return R"(<?xml version="1.0"?>
<Node name="root" dt="0.005" gravity="0 -9.81 0">
    <DefaultAnimationLoop/>
    <CollisionPipeline/>
    <BruteForceBroadPhase/>
    <BVHNarrowPhase/>
    <NewProximityIntersection name="proximity" alarmDistance="0.1" contactDistance="0.02"/>
    <CollisionResponse name="response" response="PenalityContactForceField"/>
    <EulerImplicitSolver name="solver" rayleighStiffness="0.05" rayleighMass="0.1"/>
    <CGLinearSolver name="cg" iterations="200" tolerance="1e-9" threshold="1e-15"/>
    <Node name="Floor">
        <MeshTopology name="floor_topology" position="-2 0 -2  2 0 -2  2 0 2  -2 0 2" triangles="0 2 1  0 3 2"/>
        <MechanicalObject name="floor"/>
        <UniformMass totalMass="1"/>
        <FixedProjectiveConstraint fixAll="1"/>
        <TriangleCollisionModel name="floor_triangles" simulated="0" moving="0"/>
    </Node>
    <Node name="SoftCube">
        <RegularGridTopology nx="5" ny="5" nz="5" xmin="-0.3" xmax="0.3" ymin="0.05" ymax="0.65" zmin="-0.3" zmax="0.3"/>
        <MechanicalObject name="cube"/>
        <UniformMass totalMass="1"/>
        <TetrahedronFEMForceField youngModulus="3000" poissonRatio="0.3" method="large"/>
        <PointCollisionModel name="cube_points"/>
    </Node>
    <Node name="Ball">
        <MechanicalObject name="ball" template="Rigid3d" position="0.1 1.2 0.05  0 0 0 1"/>
        <UniformMass totalMass="0.5"/>
        <SphereCollisionModel name="ball_sphere" template="Rigid3d" radius="0.15" contactStiffness="85"/>
    </Node>
</Node>
)";
}

}  // namespace penalty::scene
