#include "scene/attributes.hpp"

#include <algorithm>
#include <map>
#include <string_view>

namespace penalty::scene {

namespace {

// SOFA Data that never change the numbers (logging, display, bookkeeping).
constexpr std::string_view kHarmless[] = {"printLog", "tags", "listening", "draw", "verbose", "bbox",
                                          "componentState", "showObject", "showObjectScale", "drawMode",
                                          "color", "showIndices", "showIndicesScale", "showColor",
                                          "showVectors", "showVectorsScale", "drawArrows", "drawSize",
                                          "showImpostors", "displayFreePosition", "showEdges", "showTriangles",
                                          "drawEdges", "drawTriangles", "drawHeterogeneousTetra", "showStressColorMap",
                                          "showStressAlpha", "showVonMisesStressPerNode", "computeVonMisesStress",
                                          "showWireFrame", "showAxisSizeFactor", "showGravity", "showLines",
                                          "drawElements", "activated", "depth", "handleSeams"};

const std::vector<std::string> kCollisionCommon = {"active",        "moving",           "simulated",
                                                   "selfCollision", "proximity",        "contactDistance",
                                                   "contactStiffness", "contactFriction", "contactRestitution",
                                                   "contactResponse", "group",           "bothSide",
                                                   "topology"};

const std::map<std::string, std::vector<std::string>, std::less<>>& table() {
    static const std::map<std::string, std::vector<std::string>, std::less<>> t = [] {
        std::map<std::string, std::vector<std::string>, std::less<>> m;
        m["Node"] = {"dt", "gravity"};
        m["DefaultAnimationLoop"] = {};
        m["CollisionPipeline"] = {};
        m["CompositeCollisionPipeline"] = {"subCollisionPipelines"};
        m["SubCollisionPipeline"] = {"collisionModels", "broadPhaseDetection", "narrowPhaseDetection",
                                     "intersectionMethod", "contactManager"};
        m["BruteForceBroadPhase"] = {};
        m["BVHNarrowPhase"] = {};
        m["CollisionResponse"] = {"response", "responseParams"};
        // beyondSofaPairs, fixSofaQuirks, zeroDistanceNormal: beyond SOFA (docs/sofa-compatibility.md).
        m["NewProximityIntersection"] = {"alarmDistance", "contactDistance", "useLineLine", "beyondSofaPairs",
                                         "fixSofaQuirks", "zeroDistanceNormal"};
        m["MinProximityIntersection"] = {"alarmDistance",  "contactDistance",  "useLineLine",     "useSphereTriangle",
                                         "usePointPoint",  "useLinePoint",     "useSurfaceNormals", "beyondSofaPairs",
                                         "fixSofaQuirks",  "zeroDistanceNormal"};
        m["LocalMinDistance"] = {"alarmDistance", "contactDistance", "filterIntersection", "angleCone", "coneFactor",
                                 "useLMDFilters", "beyondSofaPairs", "fixSofaQuirks", "zeroDistanceNormal"};
        m["DiscreteIntersection"] = {"beyondSofaPairs", "fixSofaQuirks", "zeroDistanceNormal"};
        m["EulerImplicitSolver"] = {"rayleighStiffness", "rayleighMass", "vdamping", "firstOrder",
                                    "trapezoidalScheme", "newton", "newtonIterations", "newtonTolerance"};
        m["EulerExplicitSolver"] = {"symplectic"};
        m["CGLinearSolver"] = {"iterations", "tolerance", "threshold"};
        m["MechanicalObject"] = {"position", "velocity", "rest_position", "src", "size", "translation", "rotation",
                                 "scale3d", "dx", "dy", "dz", "rx", "ry", "rz", "scale"};
        m["MeshTopology"] = {"src", "filename", "position", "edges", "triangles", "quads", "tetrahedra", "tetras",
                             "hexahedra", "hexas"};
        m["RegularGridTopology"] = {"n", "nx", "ny", "nz", "min", "max", "xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
        m["UniformMass"] = {"vertexMass", "totalMass", "inertiaMatrix"};
        m["Gravity"] = {"gravity"};
        const std::vector<std::string> springs = {"stiffness",       "damping",         "linesStiffness",
                                                  "linesDamping",    "trianglesStiffness", "trianglesDamping",
                                                  "quadsStiffness",  "quadsDamping",    "tetrasStiffness",
                                                  "tetrasDamping",   "cubesStiffness",  "cubesDamping"};
        m["MeshSpringForceField"] = springs;
        m["RegularGridSpringForceField"] = springs;
        // computeGlobalMatrix / updateStiffnessMatrix only choose how SOFA stores the same
        // matrices; penalty always recomputes the corotational stiffness each step (method large).
        m["TetrahedronFEMForceField"] = {"youngModulus", "poissonRatio", "method", "computeGlobalMatrix",
                                         "updateStiffnessMatrix"};
        m["HexahedronFEMForceField"] = {"youngModulus", "poissonRatio", "method"};
        m["FixedProjectiveConstraint"] = {"indices", "fixAll"};
        m["FixedConstraint"] = {"indices", "fixAll"};
        for (const char* type : {"PointCollisionModel", "LineCollisionModel", "TetrahedronCollisionModel"})
            m[type] = kCollisionCommon;
        m["TriangleCollisionModel"] = kCollisionCommon;
        m["TriangleCollisionModel"].push_back("computeNormals");
        std::vector<std::string> no_topology = kCollisionCommon;
        no_topology.erase(std::find(no_topology.begin(), no_topology.end(), "topology"));
        m["SphereCollisionModel"] = no_topology;
        m["SphereCollisionModel"].insert(m["SphereCollisionModel"].end(), {"radius", "listRadius"});
        m["CylinderCollisionModel"] = no_topology;
        m["CylinderCollisionModel"].insert(m["CylinderCollisionModel"].end(),
                                           {"radii", "heights", "defaultRadius", "defaultHeight", "defaultLocalAxis",
                                            "localAxes"});
        m["IdentityMapping"] = {"input", "output"};
        m["BarycentricMapping"] = {"input", "output"};
        m["SubsetMapping"] = {"input", "output", "indices"};
        m["RigidMapping"] = {"input", "output", "points", "index", "rigidIndexPerPoint", "globalToLocalCoords"};
        return m;
    }();
    return t;
}

}  // namespace

std::vector<std::string> read_attributes(const std::string& type) {
    const auto it = table().find(type);
    return it == table().end() ? std::vector<std::string>{} : it->second;
}

std::vector<std::string> unread_attributes(const io::SceneElement& element) {
    std::vector<std::string> out;
    const auto it = table().find(element.type);
    if (it == table().end()) return out;
    for (const io::SceneAttribute& a : element.attributes) {
        if (std::find(std::begin(kHarmless), std::end(kHarmless), a.name) != std::end(kHarmless)) continue;
        if (std::find(it->second.begin(), it->second.end(), a.name) != it->second.end()) continue;
        out.push_back(a.name);
    }
    return out;
}

}  // namespace penalty::scene
