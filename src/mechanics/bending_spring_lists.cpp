#include "penalty/mechanics/bending_spring_lists.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

namespace penalty {

namespace {

/// A spring (a, b) with its rest length |x_a − x_b| (the order of SOFA's difference; the norm is
/// the same either way up to rounding, so follow SOFA: restPosition[m1] − restPosition[m2]).
Spring spring_between(PointId a, PointId b, std::span<const Vec3> x, double ks, double kd, const char* who) {
    for (const PointId m : {a, b})
        if (m < 0 || static_cast<std::size_t>(m) >= x.size())
            throw_invalid_argument(who, ": point ", m, " out of range for a state of ", x.size(), " points");
    const Vec3 u = x[static_cast<std::size_t>(a)] - x[static_cast<std::size_t>(b)];
    return {.a = a, .b = b, .ks = ks, .kd = kd, .rest_length = u.norm()};
}

using VertexPair = std::pair<PointId, PointId>;

VertexPair sorted_pair(PointId a, PointId b) { return a < b ? VertexPair{a, b} : VertexPair{b, a}; }

}  // namespace

std::vector<Spring> quadular_bending_springs(const MeshTopology& topology, std::span<const Vec3> rest_positions,
                                             double ks, double kd) {
    const auto& quads = topology.quads();
    const auto& around_edge = topology.quads_around_edge();
    const auto& edges_in_quad = topology.edges_in_quad();
    // the position of edge e in quad q's edge list (SOFA's getEdgeIndexInQuad)
    const auto index_in_quad = [&](std::int32_t q, std::int32_t e) -> std::size_t {
        const auto& list = edges_in_quad[static_cast<std::size_t>(q)];
        for (std::size_t j = 0; j < 4; ++j)
            if (list[j] == e) return j;
        throw_invalid_argument("QuadularBendingSprings: edge ", e, " is not in quad ", q);
    };
    std::vector<Spring> springs;
    for (std::size_t e = 0; e < around_edge.size(); ++e) {
        const auto& shell = around_edge[e];
        if (shell.size() != 2) continue;  // boundary or non-manifold edge: no spring
        const auto edge = static_cast<std::int32_t>(e);
        // quads are visited in index order: the first one holding the edge is q2
        const std::int32_t q2 = std::min(shell[0], shell[1]);
        const std::int32_t q1 = std::max(shell[0], shell[1]);
        const std::size_t i1 = index_in_quad(q1, edge);
        const std::size_t i2 = index_in_quad(q2, edge);
        const Quad& t1 = quads[static_cast<std::size_t>(q1)];
        const Quad& t2 = quads[static_cast<std::size_t>(q2)];
        springs.push_back(spring_between(t1[i1], t2[(i2 + 3) % 4], rest_positions, ks, kd, "QuadularBendingSprings"));
        springs.push_back(spring_between(t1[(i1 + 3) % 4], t2[i2], rest_positions, ks, kd, "QuadularBendingSprings"));
    }
    return springs;
}

std::vector<Spring> triangle_bending_springs(const MeshTopology& topology, std::span<const Vec3> positions, double ks,
                                             double kd) {
    std::vector<Spring> springs;
    std::map<VertexPair, PointId> first_opposite;  // edge → opposite vertex in the first face holding it
    const auto register_face = [&](PointId a, PointId b, PointId c) {
        // TriangleBendingSprings::registerTriangle: edges {a,b}, {b,c}, {c,a}, opposite c, a, b
        for (const auto& [edge, opposite] :
             {std::pair{sorted_pair(a, b), c}, std::pair{sorted_pair(b, c), a}, std::pair{sorted_pair(c, a), b}}) {
            const auto [it, first] = first_opposite.try_emplace(edge, opposite);
            if (!first)
                springs.push_back(spring_between(opposite, it->second, positions, ks, kd, "TriangleBendingSprings"));
        }
    };
    for (const Triangle& t : topology.triangles()) register_face(t[0], t[1], t[2]);
    for (const Quad& q : topology.quads()) {
        register_face(q[0], q[1], q[2]);
        register_face(q[0], q[2], q[3]);
    }
    return springs;
}

std::vector<Spring> quad_bending_springs(const MeshTopology& topology, std::span<const Vec3> positions, double ks,
                                         double kd, LocalRange range) {
    std::vector<Spring> springs;
    std::map<VertexPair, VertexPair> first_facing;  // edge → facing pair in the first quad holding it
    std::set<VertexPair> made;                      // unordered pairs that have a spring
    const auto add_spring = [&](PointId a, PointId b) {
        // QuadBendingSprings::addSpring: outside the local range, or a pair seen before: nothing
        if (range.first >= 0 && a < range.first && b < range.first) return;
        if (range.last >= 0 && a > range.last && b > range.last) return;
        if (!made.insert(sorted_pair(a, b)).second) return;
        springs.push_back(spring_between(a, b, positions, ks, kd, "QuadBendingSprings"));
    };
    const auto register_edge = [&](VertexPair ab, VertexPair cd) {
        if (ab.first > ab.second) {
            std::swap(ab.first, ab.second);
            std::swap(cd.first, cd.second);
        }
        const auto [it, first] = first_facing.try_emplace(ab, cd);
        if (first) return;
        const VertexPair ef = it->second;
        add_spring(cd.first, ef.first);
        add_spring(cd.second, ef.second);
    };
    for (const Quad& q : topology.quads()) {
        register_edge({q[0], q[1]}, {q[3], q[2]});
        register_edge({q[1], q[2]}, {q[0], q[3]});
        register_edge({q[2], q[3]}, {q[1], q[0]});
        register_edge({q[3], q[0]}, {q[2], q[1]});
    }
    return springs;
}

}  // namespace penalty
