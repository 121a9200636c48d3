// The cut itself (SOFA's TriangleSetGeometryAlgorithms::SplitAlongPath and InciseAlongEdgeList):
// the path's points created, the triangles it crosses replaced by triangles along it, then the
// path's edges duplicated. Every change is a call to the container's modifier, in SOFA's order
// (addPoints, addEdges, addRemoveTriangles, movePointsProcess, notifyEndingEvent).
#include "penalty/mechanics/triangle_incision.hpp"

#include "incision_math.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace penalty {

using namespace incision_math;

namespace {

/// isQuadDeulaunayOriented(p1, p2, p3, p4): the quad p1 p2 p3 p4 is cut along p2-p4 when the
/// angles at p1 and p3 sum to at most π.
bool quad_delaunay_oriented(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
    Vec3 ab = p2 - p1, ad = p4 - p1, cb = p2 - p3, cd = p4 - p3;
    normalize(ab);
    normalize(ad);
    const double alpha = std::acos(dot(ab, ad));
    normalize(cb);
    normalize(cd);
    const double beta = std::acos(dot(cb, cd));
    return alpha + beta <= std::numbers::pi;
}

int vertex_in_triangle(const Triangle& t, PointId p) {
    for (int j = 0; j < 3; ++j)
        if (t[std::size_t(j)] == p) return j;
    return -1;
}
int edge_in_triangle(const std::array<std::int32_t, 3>& edges, ElementId e) {
    for (int j = 0; j < 3; ++j)
        if (edges[std::size_t(j)] == e) return j;
    return -1;
}

/// What SplitAlongPath collects before it changes anything.
struct SplitPlan {
    std::vector<PointAncestorElement> points;  ///< new points, in path order
    std::vector<PointId> path_points;          ///< SOFA's new_edge_points: the path's vertices
    std::vector<Triangle> triangles;           ///< new triangles
    std::vector<std::vector<ElementId>> ancestors;
    std::vector<ElementId> removed;
    void add(const Triangle& t, ElementId ancestor) {
        triangles.push_back(t);
        ancestors.push_back({ancestor});
    }
};

/// The positions and lists SplitAlongPath reads.
struct SplitContext {
    const MeshTopology& m;
    const std::vector<Vec3>& x;
    const std::vector<IncisionPathElement>& path;
    SplitPlan& plan;
    [[nodiscard]] Vec3 edge_point(ElementId e, double c) const {
        const Edge& edge = m.edges()[std::size_t(e)];
        return x[std::size_t(edge[0])] * (1 - c) + x[std::size_t(edge[1])] * c;
    }
    /// The triangle around edge `e` with vertex `p` (the last one tried when none: SOFA's).
    std::pair<ElementId, Triangle> triangle_with(ElementId e, PointId p) const {
        ElementId id = -1;
        Triangle t{};
        for (const ElementId s : m.triangles_around_edge()[std::size_t(e)]) {
            id = s;
            t = m.triangles()[std::size_t(s)];
            if (vertex_in_triangle(t, p) >= 0) break;
        }
        return {id, t};
    }
};

// POINT then EDGE (or EDGE then POINT, `point_first` false): the triangle with the point and
// the edge split in two at the edge's new point.
bool split_point_edge(const SplitContext& c, std::size_t i, bool point_first) {
    const PointId point = c.path[point_first ? i : i + 1].index;
    const ElementId edge = c.path[point_first ? i + 1 : i].index;
    const PointId on_edge = c.plan.path_points[point_first ? i + 1 : i];
    const auto [id, tri] = c.triangle_with(edge, point);
    const int v = vertex_in_triangle(tri, point);
    if (v < 0) return false;
    const auto at = [&v, &corners = tri](int k) { return corners[std::size_t((v + k) % 3)]; };
    if (point_first) {
        c.plan.add({at(0), on_edge, at(2)}, id);
        c.plan.add({at(0), at(1), on_edge}, id);
    } else {
        c.plan.add({point, on_edge, at(2)}, id);
        c.plan.add({point, at(1), on_edge}, id);
    }
    c.plan.removed.push_back(id);
    return true;
}

// EDGE then EDGE: the corner triangle between the two new points, the remaining quad cut by
// the Delaunay criterion.
bool split_edge_edge(const SplitContext& c, std::size_t i) {
    const ElementId first = c.path[i].index, second = c.path[i + 1].index;
    const PointId p1 = c.plan.path_points[i], p2 = c.plan.path_points[i + 1];
    const Edge e1 = c.m.edges()[std::size_t(first)], e2 = c.m.edges()[std::size_t(second)];
    const Vec3 pos1 = c.edge_point(first, c.path[i].coefs[0]);
    const Vec3 pos2 = c.edge_point(second, c.path[i + 1].coefs[0]);
    ElementId id = -1;
    Triangle tri{};
    for (const ElementId s : c.m.triangles_around_edge()[std::size_t(first)]) {
        id = s;
        tri = c.m.triangles()[std::size_t(s)];
        if (edge_in_triangle(c.m.edges_in_triangle()[std::size_t(s)], second) >= 0) break;
    }
    const int corner_in_edge1 = (e1[0] == e2[0] || e1[0] == e2[1]) ? 0 : 1;
    const int v = vertex_in_triangle(tri, e1[std::size_t(corner_in_edge1)]);
    if (v < 0) return false;
    std::array<PointId, 5> order{};  // corner, p1, tri+1, tri+2, p2
    std::array<Vec3, 4> pos;
    order[0] = e1[std::size_t(corner_in_edge1)];
    if (tri[std::size_t((v + 1) % 3)] == e1[std::size_t((corner_in_edge1 + 1) % 2)]) {
        pos[0] = pos1;
        order[1] = p1;
        pos[3] = pos2;
        order[4] = p2;
    } else {
        pos[0] = pos2;
        order[1] = p2;
        pos[3] = pos1;
        order[4] = p1;
    }
    order[2] = tri[std::size_t((v + 1) % 3)];
    order[3] = tri[std::size_t((v + 2) % 3)];
    pos[1] = c.x[std::size_t(order[2])];
    pos[2] = c.x[std::size_t(order[3])];
    c.plan.add({order[0], order[1], order[4]}, id);
    if (quad_delaunay_oriented(pos[0], pos[1], pos[2], pos[3])) {
        c.plan.add({order[1], order[2], order[4]}, id);
        c.plan.add({order[2], order[3], order[4]}, id);
    } else {
        c.plan.add({order[1], order[2], order[3]}, id);
        c.plan.add({order[4], order[1], order[3]}, id);
    }
    c.plan.removed.push_back(id);
    return true;
}

// EDGE and TRIANGLE (either order): the triangle's point p joined to its corners and to the
// split edge's point (4 triangles).
bool split_edge_triangle(const SplitContext& c, std::size_t i, bool edge_first) {
    const ElementId edge = c.path[edge_first ? i : i + 1].index;
    const ElementId id = c.path[edge_first ? i + 1 : i].index;
    const PointId p = c.plan.path_points[edge_first ? i + 1 : i];
    const PointId q = c.plan.path_points[edge_first ? i : i + 1];
    const Triangle t = c.m.triangles()[std::size_t(id)];
    const int k = edge_in_triangle(c.m.edges_in_triangle()[std::size_t(id)], edge);
    if (k < 0) return false;
    const auto at = [&](int j) { return t[std::size_t((k + j) % 3)]; };
    c.plan.add({p, at(0), at(1)}, id);
    c.plan.add({p, at(2), at(0)}, id);
    c.plan.add({p, at(1), q}, id);
    c.plan.add({p, q, at(2)}, id);
    c.plan.removed.push_back(id);
    return true;
}

// TRIANGLE then TRIANGLE (both in one triangle): one triangle and two quads around the two new
// points, chosen by the corners each is closest to; each quad cut by the Delaunay criterion.
bool split_triangle_triangle(const SplitContext& c, std::size_t i) {
    const ElementId id = c.path[i].index;
    if (c.path[i + 1].index != id) return false;  // SOFA: "incision not in the mesh plan"
    const Triangle t = c.m.triangles()[std::size_t(id)];
    const PointId p1 = c.plan.path_points[i], p2 = c.plan.path_points[i + 1];
    const auto& b1 = c.path[i].coefs;
    const auto& b2 = c.path[i + 1].coefs;
    double tmp1 = 0, tmp2 = 0;
    std::size_t c1 = 0, c2 = 0;
    for (std::size_t j = 0; j < 3; ++j) {
        if (b1[j] > tmp1) {
            tmp1 = b1[j];
            c1 = j;
        }
        if (b2[j] > tmp2) {
            tmp2 = b2[j];
            c2 = j;
        }
    }
    const auto T = [&](std::size_t j) { return t[j % 3]; };
    std::array<std::array<PointId, 4>, 2> quad{};
    Triangle tri1{};
    if (c1 != c2) {
        if ((c1 + 1) % 3 == c2) {
            quad[0] = {p1, T(c1), T(c2), p2};
            if (b1[(c1 + 2) % 3] > b2[(c1 + 2) % 3]) {
                quad[1] = {p2, T(c1 + 1), T(c1 + 2), p1};
                tri1 = {p1, T(c1 + 2), T(c1)};
            } else {
                quad[1] = {p2, T(c1 + 2), T(c1), p1};
                tri1 = {p2, T(c1 + 1), T(c1 + 2)};
            }
        } else {
            quad[0] = {p2, T(c2), T(c1), p1};
            if (b1[(c2 + 2) % 3] > b2[(c2 + 2) % 3]) {
                quad[1] = {p1, T(c1 + 1), T(c1 + 2), p2};
                tri1 = {p1, T(c1), T(c1 + 1)};
            } else {
                quad[1] = {p1, T(c1), T(c1 + 1), p2};
                tri1 = {p2, T(c1 + 1), T(c1 + 2)};
            }
        }
    } else {
        const bool first_closest = tmp1 > tmp2;
        const PointId closest = first_closest ? p1 : p2, second = first_closest ? p2 : p1;
        const std::size_t corner = first_closest ? c1 : c2;
        quad[0] = {closest, T(corner), T(corner + 1), second};
        quad[1] = {second, T(corner + 2), T(corner), closest};
        tri1 = {second, T(corner + 1), T(corner + 2)};
    }
    c.plan.add(tri1, id);
    for (const auto& q : quad) {
        std::array<Vec3, 4> pos;
        for (std::size_t k = 0; k < 4; ++k) {
            const auto* b = q[k] == p1 ? &b1 : q[k] == p2 ? &b2 : nullptr;
            if (!b) {
                pos[k] = c.x[std::size_t(q[k])];
                continue;
            }
            pos[k] = Vec3::Zero();
            for (std::size_t u = 0; u < 3; ++u)
                for (int v = 0; v < 3; ++v) pos[k][v] = pos[k][v] + c.x[std::size_t(t[u])][v] * (*b)[u];
        }
        if (quad_delaunay_oriented(pos[0], pos[1], pos[2], pos[3])) {
            c.plan.add({q[1], q[2], q[0]}, id);
            c.plan.add({q[3], q[0], q[2]}, id);
        } else {
            c.plan.add({q[2], q[3], q[1]}, id);
            c.plan.add({q[0], q[1], q[3]}, id);
        }
    }
    c.plan.removed.push_back(id);
    return true;
}

// POINT then TRIANGLE, TRIANGLE then POINT: the triangle's new point joined to its 3 corners.
bool split_point_triangle(const SplitContext& c, std::size_t i, bool point_first) {
    const ElementId id = c.path[point_first ? i + 1 : i].index;
    const PointId p = c.plan.path_points[point_first ? i + 1 : i];
    const Triangle t = c.m.triangles()[std::size_t(id)];
    if (point_first) {
        c.plan.add({t[0], t[1], p}, id);
        c.plan.add({t[1], t[2], p}, id);
        c.plan.add({t[2], t[0], p}, id);
    } else {
        c.plan.add({p, t[0], t[1]}, id);
        c.plan.add({p, t[1], t[2]}, id);
        c.plan.add({p, t[2], t[0]}, id);
    }
    c.plan.removed.push_back(id);
    return true;
}

}  // namespace

// SplitAlongPath: snapping (SnapAlongPath, SnapBorderPath), a new point per EDGE and TRIANGLE
// element of the path (addPoints with their elements), the triangles between consecutive
// elements split, the new edges added, addRemoveTriangles, the snapped vertices moved to their
// mean crossing (movePointsProcess), notifyEndingEvent; `new_edges`: the edges joining the
// path's vertices.
int TriangleIncision::split_along_path(PointId a_point, Vec3& a, PointId b_point, Vec3& b,
                                       std::vector<IncisionPathElement>& path, std::vector<ElementId>& new_edges,
                                       double epsilon_path, double epsilon_border) {
    if (path.empty()) return 0;
    std::vector<std::vector<double>> snaps;
    if (epsilon_path != 0.0) snap_along_path(path, snaps, epsilon_path);
    if (epsilon_border != 0.0) snap_border_path(a_point, a, b_point, b, path, snaps, epsilon_border);
    const MeshTopology& m = mesh();
    const std::size_t n = path.size();
    SplitPlan plan;
    auto next_point = PointId(container_->num_points());
    for (std::size_t i = 0; i < n; ++i) {
        const IncisionPathElement& e = path[i];
        if (e.type == ElementType::point) {
            plan.path_points.push_back(e.index);
            for (auto& s : snaps) {
                if (s[0] != double(e.index)) continue;
                if (i == 0 || i == n - 1) {  // a path end (SOFA: "should not happen")
                    int count = 0;
                    for (const ElementId edge : m.edges_around_vertex()[std::size_t(e.index)]) {
                        const Edge& ed = m.edges()[std::size_t(edge)];
                        s.push_back(double(ed[0] == e.index ? ed[1] : ed[0]));
                        if (++count == 3) break;
                    }
                    if (count < 2)
                        throw_invalid_argument("incision: vertex ", e.index,
                                               " snapped at the end of the path has fewer than 2 neighbours");
                    break;
                }
                s.push_back(double(next_point - 1));
                s.push_back(double(next_point));
                if (path[i - 1].type == ElementType::point) s[4] = double(path[i - 1].index);
                if (path[i + 1].type == ElementType::point) s[5] = double(path[i + 1].index);
                break;
            }
        } else if (e.type == ElementType::edge) {
            const Edge& edge = m.edges()[std::size_t(e.index)];
            plan.points.push_back({ElementType::edge, {edge[0], edge[1], 0}, {e.coefs[0], 0, 0}});
            plan.path_points.push_back(next_point++);
        } else if (e.type == ElementType::triangle) {
            const Triangle& t = m.triangles()[std::size_t(e.index)];
            plan.points.push_back({ElementType::triangle, t, {e.coefs[1], e.coefs[2], 0}});
            plan.path_points.push_back(next_point++);
        }
    }
    const SplitContext context{m, *positions_, path, plan};
    for (std::size_t i = 0; i + 1 < n; ++i) {
        const ElementType first = path[i].type, second = path[i + 1].type;
        bool ok = true;
        if (first == ElementType::point) {
            if (second == ElementType::point) {
                ok = m.edge_index(path[i].index, path[i + 1].index) >= 0;
            } else if (second == ElementType::edge) {
                ok = split_point_edge(context, i, true);
            } else {
                ok = split_point_triangle(context, i, true);
            }
        } else if (first == ElementType::edge) {
            if (second == ElementType::point) {
                ok = split_point_edge(context, i, false);
            } else if (second == ElementType::edge) {
                ok = split_edge_edge(context, i);
            } else {
                ok = split_edge_triangle(context, i, true);
            }
        } else {
            if (second == ElementType::point) {
                ok = split_point_triangle(context, i, false);
            } else if (second == ElementType::edge) {
                ok = split_edge_triangle(context, i, false);
            } else {
                ok = split_triangle_triangle(context, i);
            }
        }
        if (!ok) return -1;  // SOFA: "ERROR: in the incision path", before any change
    }
    apply_split(plan.points, plan.triangles, plan.ancestors, plan.removed);
    if (!snaps.empty()) move_snapped(snaps);
    container_->notify_ending_event();
    for (std::size_t i = 0; i + 1 < plan.path_points.size(); ++i) {
        ElementId e = m.edge_index(plan.path_points[i], plan.path_points[i + 1]);
        if (e < 0) e = m.edge_index(plan.path_points[i + 1], plan.path_points[i]);
        if (e >= 0) new_edges.push_back(e);  // SOFA: "NOT FOUND", skipped
    }
    return int(plan.points.size());
}

// SplitAlongPath's FINAL STEP: addPoints, addEdges (each edge of a new triangle that is not an
// edge between old points already, once, in the triangles' order, its vertices sorted),
// addRemoveTriangles (addTriangles, then removeTriangles with isolated edges and points).
void TriangleIncision::apply_split(const std::vector<PointAncestorElement>& points,
                                   const std::vector<Triangle>& triangles,
                                   const std::vector<std::vector<ElementId>>& ancestors,
                                   std::vector<ElementId> removed) {
    const auto first_new = PointId(container_->num_points());
    container_->add_points(points);
    const MeshTopology& m = mesh();
    std::set<Edge> seen;
    std::vector<Edge> edges;
    for (const Triangle& t : triangles)
        for (std::size_t k = 0; k < 3; ++k) {
            Edge e{t[k], t[(k + 1) % 3]};
            if (e[0] > e[1]) std::swap(e[0], e[1]);
            if (e[0] < first_new && e[1] < first_new && m.edge_index(e[0], e[1]) >= 0) continue;
            if (!seen.insert(e).second) continue;
            edges.push_back(e);
        }
    if (!edges.empty()) container_->add_edges(edges);
    const std::vector<std::vector<double>> coefficients(triangles.size(), std::vector<double>{1.0});
    container_->add_triangles(triangles, ancestors, coefficients);
    container_->remove_triangles(std::move(removed), true, true);
}

// The snapped vertices moved (movePointsProcess) to their mean crossing, as weights of their
// neighbours on the path: two (computeEdgeBarycentricCoordinates) or, at a path end, three
// (compute3PointsBarycoefs).
void TriangleIncision::move_snapped(const std::vector<std::vector<double>>& snaps) {
    std::vector<PointId> ids;
    std::vector<std::vector<ElementId>> ancestors;
    std::vector<std::vector<double>> coefficients;
    for (const auto& s : snaps) {
        if (s.size() < 6) continue;  // a snap no path point took (SOFA reads past its end)
        const Vec3 target(s[1], s[2], s[3]);
        const auto first = PointId(s[4]), second = PointId(s[5]);
        ids.push_back(PointId(s[0]));
        if (s.size() == 7) {
            const auto third = PointId(s[6]);
            const auto c = barycentric_of(target, x(first), x(second), x(third));
            ancestors.push_back({first, second, third});
            coefficients.push_back({c[0], c[1], c[2]});
        } else {
            const double length = norm(x(second) - x(first));
            ancestors.push_back({first, second});
            if (length < kEqualityThreshold) {
                coefficients.push_back({0.5, 0.5});
            } else {
                coefficients.push_back({norm(target - x(second)) / length, norm(target - x(first)) / length});
            }
        }
    }
    container_->move_points(ids, ancestors, coefficients);
}

// InciseAlongEdgeList: the chain of edges' vertices (init_points); each one that is not a chain
// end inside the surface gets a copy (a point weighted 1 on it); the triangles on one side of the
// chain (from the first edge's first triangle, turning around each vertex to the next edge, and
// to the border at a border end) are replaced by triangles on the copies (addRemoveTriangles).
bool TriangleIncision::incise_along_edge_list(const std::vector<ElementId>& edges, std::vector<PointId>& new_points,
                                              std::vector<PointId>& end_points, bool& reach_border) {
    const MeshTopology& m = mesh();
    const std::size_t n = edges.size();
    if (n == 0) return true;
    std::vector<PointId> chain{m.edges()[std::size_t(edges[0])][0], m.edges()[std::size_t(edges[0])][1]};
    if (n > 1) {
        const Edge& e = m.edges()[std::size_t(edges[1])];
        if (chain[0] == e[0] || chain[0] == e[1]) std::swap(chain[0], chain[1]);
        for (std::size_t i = 1; i < n; ++i) {
            const Edge& ei = m.edges()[std::size_t(edges[i])];
            if (ei[0] == chain.back()) {
                chain.push_back(ei[1]);
            } else if (ei[1] == chain.back()) {
                chain.push_back(ei[0]);
            } else {
                return false;  // SOFA: "Edges are not connected"
            }
        }
    }
    for (const ElementId e : edges)
        if (m.triangles_around_edge()[std::size_t(e)].size() != 2) return false;  // "Cannot split an edge"
    const auto on_border = [&](PointId p) {
        return m.triangles_around_vertex()[std::size_t(p)].size() < m.edges_around_vertex()[std::size_t(p)].size();
    };
    const bool begin_on_border = on_border(chain.front());
    const bool end_on_border = on_border(chain.back());
    if (!begin_on_border) end_points.push_back(chain.front());
    if (!end_on_border) {
        end_points.push_back(chain.back());
    } else {
        reach_border = true;
    }
    // STEP 1: the copies
    const std::size_t first = begin_on_border ? 0 : 1;
    const std::size_t last = end_on_border ? chain.size() - 1 : chain.size() - 2;
    std::map<PointId, PointId> split;
    std::vector<std::vector<ElementId>> point_ancestors;
    auto next_point = PointId(container_->num_points());
    for (std::size_t i = first; i <= last && last + 1 > 0; ++i) {
        point_ancestors.push_back({chain[i]});
        new_points.push_back(next_point);
        split[chain[i]] = next_point++;
    }
    // STEP 2: the triangles on one side
    std::set<ElementId> updated;
    const std::size_t guard = 2 * m.triangles().size() + 8;
    const auto other = [](const Triangle& t, PointId a, PointId b) {
        return t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
    };
    // turns around p0 from triangle tid (across edge p0-p1) until the border (or `stop` is met)
    const auto turn = [&](ElementId tid, PointId p0, PointId p1, PointId stop, bool to_border) {
        for (std::size_t k = 0;; ++k) {
            if (k > guard) throw_invalid_argument("incision: the triangles around vertex ", p0, " do not close");
            updated.insert(tid);
            const Triangle& t = m.triangles()[std::size_t(tid)];
            const PointId p2 = other(t, p0, p1);
            if (!to_border && p2 == stop) return tid;
            const ElementId e = m.edge_index(p0, p2);
            if (e < 0) return tid;
            const auto& around = m.triangles_around_edge()[std::size_t(e)];
            if (to_border ? around.size() != 2 : around.size() < 2) return tid;
            tid = around[0] == tid ? around[1] : around[0];
            p1 = p2;
        }
    };
    ElementId t0 = m.triangles_around_edge()[std::size_t(edges[0])][0];
    if (begin_on_border) turn(t0, chain[0], chain[1], -1, true);
    for (std::size_t i = 0; i + 1 < n; ++i) t0 = turn(t0, chain[i + 1], chain[i], chain[i + 2], false);
    if (end_on_border) turn(t0, chain[n], chain[n - 1], -1, true);
    // STEP 3: the updated triangles on the copies
    std::vector<Triangle> triangles;
    std::vector<std::vector<ElementId>> ancestors;
    std::vector<ElementId> removed;
    for (const ElementId tid : updated) {
        Triangle t = m.triangles()[std::size_t(tid)];
        bool changed = false;
        for (auto& v : t)
            if (const auto it = split.find(v); it != split.end()) {
                v = it->second;
                changed = true;
            }
        if (!changed) continue;  // SOFA: "flagged as updated but no change was found"
        triangles.push_back(t);
        ancestors.push_back({tid});
        removed.push_back(tid);
    }
    if (!point_ancestors.empty())
        container_->add_points(point_ancestors.size(), point_ancestors,
                               std::vector<std::vector<double>>(point_ancestors.size(), std::vector<double>{1.0}));
    const std::vector<std::vector<double>> coefficients(triangles.size(), std::vector<double>{1.0});
    container_->add_triangles(triangles, ancestors, coefficients);
    container_->remove_triangles(std::move(removed), true, true);
    return true;
}

}  // namespace penalty
