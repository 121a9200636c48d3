#pragma once
/// @file
/// Spring lists of SOFA's bending-spring components that use the SpringForceField law
/// (penalty::SpringForceField evaluates them):
///  - QuadularBendingSprings: two springs across each edge shared by exactly two quads;
///  - TriangleBendingSprings: one spring between the opposite vertices of two faces sharing an
///    edge (quads split into (0,1,2), (0,2,3));
///  - QuadBendingSprings: two springs across each edge shared by two quads, each vertex pair once.
/// Each builder gives SOFA's springs in SOFA's order, ends (a, b) as SOFA's (m1, m2) and rest
/// lengths |x_a − x_b| from the given positions; ks in N/m, kd in N·s/m.

#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <span>
#include <vector>

namespace penalty {

/// SOFA's QuadularBendingSprings (QuadularBendingSprings::applyQuadCreation, init): for each edge
/// in edge order whose quads-around-edge are exactly two, with q2 the lower-index quad (the first
/// quad visited), q1 the other, and i1, i2 the edge's index in edges_in_quad of q1 and q2
/// (edge j of quad q = (q[j+1], q[j+2])): spring 0 = (q1[i1], q2[i2+3]), spring 1 =
/// (q1[i1+3], q2[i2]) (indices mod 4); rest lengths from `rest_positions`. These join the vertices
/// next to each end of the shared edge, across it. The force is SpringForceField's with the null
/// length kBendingSpringNullLength and SpringArithmetic::quadular_bending_springs.
std::vector<Spring> quadular_bending_springs(const MeshTopology& topology, std::span<const Vec3> rest_positions,
                                             double ks, double kd);

/// SOFA's TriangleBendingSprings (TriangleBendingSprings::init, registerTriangle): faces in order
/// (triangles, then each quad (a,b,c,d) as (a,b,c) and (a,c,d)); for each face (a,b,c) its edges
/// {a,b}, {b,c}, {c,a} with opposite vertices c, a, b: the first face to hold an edge records its
/// opposite vertex o1; each later face holding it adds the spring (its opposite vertex, o1). Rest
/// lengths from `positions` (SOFA reads the positions at init).
std::vector<Spring> triangle_bending_springs(const MeshTopology& topology, std::span<const Vec3> positions, double ks,
                                             double kd);

/// SOFA's QuadBendingSprings::localRange: springs whose two ends are both below `first` (when
/// first >= 0) or both above `last` (when last >= 0) are skipped.
struct LocalRange {
    int first = -1;
    int last = -1;
};

/// SOFA's QuadBendingSprings (QuadBendingSprings::init, registerEdge, addSpring): for each quad
/// (q0,q1,q2,q3) in order, its edges with the facing edge: ((q0,q1),(q3,q2)), ((q1,q2),(q0,q3)),
/// ((q2,q3),(q1,q0)), ((q3,q0),(q2,q1)); an edge (a,b) with a > b is swapped together with its
/// facing pair. The first quad to hold an edge records its facing pair (e, f); a later quad with
/// facing pair (c, d) adds the springs (c, e) then (d, f), each unordered vertex pair at most once,
/// within `range`. Rest lengths from `positions`.
std::vector<Spring> quad_bending_springs(const MeshTopology& topology, std::span<const Vec3> positions, double ks,
                                         double kd, LocalRange range = {});

}  // namespace penalty
