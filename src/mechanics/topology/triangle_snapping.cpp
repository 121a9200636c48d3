// Snapping of a cut's path (SOFA's TriangleSetGeometryAlgorithms::SnapAlongPath, SnapBorderPath,
// EdgeSetGeometryAlgorithms::computePointProjectionOnEdge): crossings close to a vertex are merged
// into that vertex (which then moves to their mean), a path end close to a border edge is moved
// onto that edge.
#include "penalty/mechanics/triangle_incision.hpp"

#include "incision_math.hpp"

#include <algorithm>
#include <map>

namespace penalty {

using namespace incision_math;

Vec3 TriangleIncision::edge_point(ElementId e, double coord) const {
    const Edge& edge = mesh().edges()[std::size_t(e)];
    return x(edge[0]) * (1 - coord) + x(edge[1]) * coord;  // computeBaryEdgePoint
}

// SnapAlongPath: the vertices some crossing lies within `epsilon` of (an edge crossing's
// coordinate, a triangle point's barycentric coordinate), not on the border, and met by more than
// one path element; each becomes one POINT element of the path (the first, the others dropped)
// and `snaps` gets [vertex, mean position of its crossings].
void TriangleIncision::snap_along_path(std::vector<IncisionPathElement>& path, std::vector<std::vector<double>>& snaps,
                                       double epsilon) const {
    const MeshTopology& m = mesh();
    std::map<PointId, std::vector<std::size_t>> crossings;  // vertex -> path elements
    std::map<PointId, Vec3> sum;
    for (const IncisionPathElement& e : path) {
        if (e.type == ElementType::edge) {
            const Edge& edge = m.edges()[std::size_t(e.index)];
            if (e.coefs[0] < epsilon) {
                crossings.try_emplace(edge[0]);
            } else if (e.coefs[0] > 1.0 - epsilon) {
                crossings.try_emplace(edge[1]);
            }
        } else if (e.type == ElementType::triangle) {
            for (int j = 0; j < 3; ++j)
                if (e.coefs[std::size_t(j)] > 1.0 - epsilon) {
                    crossings.try_emplace(m.triangles()[std::size_t(e.index)][std::size_t(j)]);
                    break;
                }
        }
    }
    if (crossings.empty()) return;
    for (auto& [v, list] : crossings) sum[v] = Vec3::Zero();
    for (std::size_t i = 0; i < path.size(); ++i) {
        const IncisionPathElement& e = path[i];
        if (e.type == ElementType::point) {
            if (!crossings.contains(e.index)) continue;
            crossings[e.index].push_back(i);
            for (int j = 0; j < 3; ++j) sum[e.index][j] += x(e.index)[j];
        } else if (e.type == ElementType::edge) {
            const Edge& edge = m.edges()[std::size_t(e.index)];
            for (const PointId v : edge)
                if (crossings.contains(v)) {
                    crossings[v].push_back(i);
                    const Vec3 c = edge_point(e.index, e.coefs[0]);
                    for (int j = 0; j < 3; ++j) sum[v][j] += c[j];
                    break;
                }
        } else if (e.type == ElementType::triangle) {
            const Triangle& t = m.triangles()[std::size_t(e.index)];
            for (std::size_t k = 0; k < 3; ++k)
                if (crossings.contains(t[k]) && e.coefs[k] > 1 - epsilon) {
                    crossings[t[k]].push_back(i);
                    const Vec3 c = x(t[0]) * e.coefs[0] + x(t[1]) * e.coefs[1] + x(t[2]) * e.coefs[2];
                    for (int j = 0; j < 3; ++j) sum[t[k]][j] += c[j];
                    break;
                }
        }
    }
    // no snapping on the border: a vertex with an edge of one triangle
    for (auto it = crossings.begin(); it != crossings.end();) {
        bool border = false;
        for (const ElementId edge : m.edges_around_vertex()[std::size_t(it->first)])
            if (m.triangles_around_edge()[std::size_t(edge)].size() == 1) {
                border = true;
                break;
            }
        it = border ? crossings.erase(it) : std::next(it);
    }
    std::vector<std::size_t> dropped;
    for (const auto& [v, list] : crossings) {
        const std::size_t size = list.size();
        if (size == 1) continue;  // a border case or a re-incision
        snaps.push_back({double(v), sum[v][0] / double(size), sum[v][1] / double(size), sum[v][2] / double(size)});
        IncisionPathElement& first = path[list[0]];
        first.type = ElementType::point;
        first.index = v;
        first.coefs[0] = -1.0;
        for (std::size_t i = 1; i < size; ++i) dropped.push_back(list[i]);
    }
    std::sort(dropped.begin(), dropped.end());
    for (auto it = dropped.rbegin(); it != dropped.rend(); ++it) path.erase(path.begin() + std::ptrdiff_t(*it));
}

// computePointProjectionOnEdge: c's orthogonal projection on edge e (the intersection of the
// edge with the line from c along ((AB x AC) x AB) 10⁶, taken in single precision as SOFA does),
// as the edge's barycentric coordinates; empty when they do not meet.
std::vector<double> TriangleIncision::project_on_edge(ElementId e, const Vec3& c, bool& intersected) const {
    const Edge& edge = mesh().edges()[std::size_t(e)];
    const Vec3 a = x(edge[0]), b = x(edge[1]);
    const Vec3 ab = b - a, ac = c - a;
    const Vec3 ortho = cross(ab, ac) * 1000;
    const Vec3 ch = cross(ortho, ab) * 1000;
    Vec3 d;
    for (int i = 0; i < 3; ++i) d[i] = c[i] + double(float(ch[i]));
    // Edge::intersectionWithEdge in 3D (closestPointWithEdge), then interpolate
    const Vec3 cd = d - c, ca = a - c;
    const double dcacd = dot(ca, cd), dabcd = dot(ab, cd), dcdcd = dot(cd, cd), dcaab = dot(ca, ab),
                 dabab = dot(ab, ab);
    const double alpha_nom = dcacd * dabcd - dcaab * dcdcd;
    const double alpha_denom = dabab * dcdcd - dabcd * dabcd;
    double alpha = 0, beta = 0;
    if (!(alpha_denom < 2.220446049250313e-16)) {
        alpha = alpha_nom / alpha_denom;
        beta = (dcacd + alpha * dabcd) / dcdcd;
        if (std::fabs(alpha) < kEqualityThreshold) {
            alpha = 0;
        } else if (std::fabs(1 - alpha) < kEqualityThreshold) {
            alpha = 1;
        }
        if (std::fabs(beta) < kEqualityThreshold) {
            beta = 0;
        } else if (std::fabs(1 - beta) < kEqualityThreshold) {
            beta = 1;
        }
    }
    const Vec3 px = a + alpha * ab, py = c + beta * cd;
    intersected = !(alpha < 0 || beta < 0 || alpha > 1 || beta > 1 || norm2(py - px) > kEqualityThreshold);
    if (!intersected) return {};
    Vec3 h = Vec3::Zero();
    h += a * (1 - alpha);
    h += b * alpha;
    // computeEdgeBarycentricCoordinates(h, edge): distances to the other end over the length
    const double length = norm(b - a);
    if (length < kEqualityThreshold) return {0.5, 0.5};
    return {norm(h - b) / length, norm(h - a) / length};
}

// SnapBorderPath: each end of the path in a triangle (not already snapped onto a vertex) with a
// barycentric coordinate under `epsilon`: near an inner edge, snapped onto the triangle's vertex
// over 1 - epsilon (the path elements on that vertex dropped); near a border edge, moved onto
// the edge (its orthogonal projection).
void TriangleIncision::snap_border_path(PointId pa, Vec3& a, PointId pb, Vec3& b,
                                        std::vector<IncisionPathElement>& path,
                                        const std::vector<std::vector<double>>& snaps, double epsilon) const {
    bool snap_a = false, snap_b = false;
    for (const auto& s : snaps) {
        if (pa >= 0 && s[0] == double(pa)) {
            snap_a = true;
        } else if (pb >= 0 && s[0] == double(pb)) {
            snap_b = true;
        }
        if (snap_a && snap_b) break;
    }
    if (!snap_a && path.front().type == ElementType::triangle) snap_border_end(false, a, a, path, epsilon);
    // SOFA writes the last end's projection into a as well
    if (!snap_b && path.back().type == ElementType::triangle) snap_border_end(true, a, b, path, epsilon);
}

void TriangleIncision::snap_border_end(bool last, Vec3& a_written, const Vec3& end,
                                       std::vector<IncisionPathElement>& path, double epsilon) const {
    const MeshTopology& m = mesh();
    const auto end_index = [&] { return last ? path.size() - 1 : std::size_t(0); };
    const auto next_index = [&] { return last ? path.size() - 2 : std::size_t(1); };
    for (std::size_t i = 0; i < 3; ++i) {
        IncisionPathElement& tip = path[end_index()];
        if (!(tip.coefs[i] < epsilon)) continue;
        const ElementId edge = m.edges_in_triangle()[std::size_t(tip.index)][i];
        if (m.triangles_around_edge()[std::size_t(edge)].size() > 1) {  // an inner edge: snap onto a vertex
            bool find = false;
            PointId point = 0;
            for (std::size_t j = 0; j < 3; ++j)
                if (tip.coefs[j] > 1 - epsilon) {
                    point = m.triangles()[std::size_t(tip.index)][j];
                    tip.type = ElementType::point;
                    tip.index = point;
                    find = true;
                    break;
                }
            if (path.size() <= 2) break;
            while (find && path.size() >= 2) {
                bool point_done = true, all_done = true;
                const std::size_t k = next_index();
                if (path[k].type == ElementType::edge) {
                    const auto& shell = m.edges_around_vertex()[std::size_t(point)];
                    if (std::find(shell.begin(), shell.end(), path[k].index) != shell.end()) {
                        path.erase(path.begin() + std::ptrdiff_t(k));
                        all_done = false;
                    }
                } else if (path[k].type == ElementType::point) {
                    if (path[k].index == point) {
                        path.erase(path.begin() + std::ptrdiff_t(k));
                        point_done = false;
                    }
                } else {
                    find = false;
                }
                if (point_done && all_done) find = false;
            }
            break;
        }
        if (path.size() >= 2 && path[next_index()].index == edge && path[next_index()].type == ElementType::edge) {
            path.erase(path.begin() + std::ptrdiff_t(end_index()));  // SOFA: "Unexpected case reached"
            break;
        }
        bool intersected = true;
        const std::vector<double> coord = project_on_edge(edge, end, intersected);
        if (!intersected) continue;
        IncisionPathElement& moved = path[end_index()];
        moved.type = ElementType::edge;
        moved.index = edge;
        moved.coefs = {coord[1], coord[0], 0.0};
        a_written = edge_point(edge, coord[1]);
        break;
    }
}

}  // namespace penalty
