// The path of a cut over a triangle surface (SOFA's TriangleSetGeometryAlgorithms:
// isPointInsideTriangle, compute3PointsBarycoefs, computeSegmentTriangleIntersection,
// computeIntersectedPointsList, computeIntersectedObjectsList; TopologicalChangeProcessor::
// findElementIndex): which triangles, edges and points the segment from a to b crosses.
#include "penalty/mechanics/triangle_incision.hpp"

#include "incision_math.hpp"

#include <algorithm>
#include <numeric>

namespace penalty {

using namespace incision_math;

namespace {

/// SOFA's `indices` vector of computeSegmentTriangleIntersection: clear() keeps the values, so a
/// read after a failed test sees the last edge found (what SOFA's std::vector reads there).
struct EdgeCrossing {
    std::array<PointId, 2> v{};
    bool found = false;
};

}  // namespace

TriangleIncision::TriangleIncision(TopologyContainer& container, const std::vector<Vec3>& positions)
    : container_(&container), positions_(&positions) {}

// isPointInsideTriangle(t, is_tested = false, p): p on the inner side of the three edges (within
// 1e-12), in the triangle's plane frame n = (p2 - p0) x (p1 - p0).
bool TriangleIncision::point_inside(ElementId t, const Vec3& p) const {
    const Triangle& tri = mesh().triangles()[std::size_t(t)];
    const Vec3 &p0 = x(tri[0]), &p1 = x(tri[1]), &p2 = x(tri[2]);
    const Vec3 n = cross(p2 - p0, p1 - p0);
    if (norm2(n) == 0.0) return false;
    const double v01 = dot(p - p0, cross(p1 - p0, n));
    const double v12 = dot(p - p1, cross(p2 - p1, n));
    const double v20 = dot(p - p2, cross(p0 - p2, n));
    constexpr double kZero = -1e-12;
    return v01 > kZero && v12 > kZero && v20 > kZero;
}

// compute3PointsBarycoefs(p, t[0], t[1], t[2]): areas of the sub-triangles over the triangle's
// (M = (b - a) x (c - a), N = M / |M|²); 1/3 each for a flat triangle (|M|² < 1e-12).
std::array<double, 3> TriangleIncision::barycentric(ElementId t, const Vec3& p) const {
    const Triangle& tri = mesh().triangles()[std::size_t(t)];
    return barycentric_of(p, x(tri[0]), x(tri[1]), x(tri[2]));
}

std::array<double, 3> TriangleIncision::barycentric_of(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 m = cross(b - a, c - a);
    const double n2 = norm2(m);
    if (n2 < 1e-12) {
        const double third = 1.0 / 3.0;
        return {third, third, 1.0 - (third + third)};
    }
    const Vec3 n = divided(m, n2);
    const double ca = dot(n, cross(b - p, c - p));
    const double cb = dot(n, cross(c - p, a - p));
    return {ca, cb, 1.0 - (ca + cb)};
}

// TopologicalChangeProcessor::findElementIndex: the triangles whose bounding box holds p and
// that hold it; one: it. Else (none or several) the triangles holding p projected on their plane
// (the scan stops at a flat triangle): the first, or `previous` when it is one of them.
ElementId TriangleIncision::find_triangle(const Vec3& p, ElementId previous) const {
    const auto& triangles = mesh().triangles();
    std::vector<ElementId> found;
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& t = triangles[i];
        bool in_box = true;
        for (int j = 0; j < 3 && in_box; ++j) {
            const double lo = std::min(x(t[0])[j], std::min(x(t[1])[j], x(t[2])[j]));
            const double hi = std::max(x(t[0])[j], std::max(x(t[1])[j], x(t[2])[j]));
            in_box = !(p[j] < lo || p[j] > hi);
        }
        if (!in_box || !point_inside(ElementId(i), p)) continue;
        if (ElementId(i) == previous) return previous;
        found.push_back(ElementId(i));
    }
    if (found.size() == 1) return found[0];
    found.clear();
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        const Triangle& t = triangles[i];
        Vec3 n = cross(x(t[1]) - x(t[0]), x(t[2]) - x(t[0]));  // computeTriangleNormal
        if (norm(n) == 0.0) break;
        n = divided(n, norm(n));
        const double a = n[0], b = n[1], c = n[2];
        const Vec3& q = x(t[0]);
        const double d = -(q[0] * a + q[1] * b + q[2] * c);
        const Vec3 projected((b * b + c * c) * p[0] - a * b * p[1] - a * c * p[2] - d * a,
                             -a * b * p[0] + (a * a + c * c) * p[1] - b * c * p[2] - d * b,
                             -a * c * p[0] - b * c * p[1] + (a * a + b * b) * p[2] - d * c);
        if (!point_inside(ElementId(i), projected)) continue;
        if (ElementId(i) == previous) return previous;
        found.push_back(ElementId(i));
    }
    return found.empty() ? -1 : found[0];
}

// computeSegmentTriangleIntersection: where the ray from a towards b (projected on triangle t's
// plane) leaves t: `indices` the edge's vertices, `bary` the coordinate along it from
// indices[0], `kmin` the ray parameter (1 at b). `entered`: the edge in `indices` is where the
// ray came in, not tested. False when t is flat or a and b project onto one point.
bool TriangleIncision::segment_triangle_intersection(bool entered, const Vec3& pa, const Vec3& pb, ElementId t,
                                                     std::vector<PointId>& indices, double& bary, double& kmin) const {
    PointId first = 0, second = 0;
    if (indices.size() > 1) {
        first = indices[0];
        second = indices[1];
    }
    indices.clear();
    const Triangle& tri = mesh().triangles()[std::size_t(t)];
    const auto is_full = [&](PointId u, PointId v) {
        return entered && ((u == first && v == second) || (v == first && u == second));
    };
    const Vec3 &p0 = x(tri[0]), &p1 = x(tri[1]), &p2 = x(tri[2]);
    Vec3 normal = cross(p2 - p0, p1 - p0);
    const double normal_norm = norm(normal);
    if (normal_norm == 0.0) return false;  // flat triangle
    normal = divided(normal, normal_norm);
    const Vec3 ab = pb - pa;
    const Vec3 ab_proj = ab - normal * dot(ab, normal);
    const Vec3 pb_proj = ab_proj + pa;
    const Vec3 n_proj = cross(ab_proj, normal);
    const double norm2_ab_proj = dot(ab_proj, ab_proj);
    if (norm2_ab_proj == 0.0) return false;  // a and b project onto one point
    bool validated = false, initialized = false;
    kmin = 0.0;
    // the edges (p0,p1), (p1,p2), (p2,p0) in turn: the last crossing along the ray wins
    const std::array<std::array<int, 2>, 3> kEdges{{{0, 1}, {1, 2}, {2, 0}}};
    for (const auto& [u, v] : kEdges) {
        if (is_full(tri[std::size_t(u)], tri[std::size_t(v)])) continue;
        const Vec3 &pu = x(tri[std::size_t(u)]), &pv = x(tri[std::size_t(v)]);
        const Vec3 n_uv = cross(pv - pu, normal);
        const double s_t = dot(pu - pv, n_proj);
        const double s_k = dot(pa - pb_proj, n_uv);
        double coord_t = 0.0, coord_k = 0.0;
        bool intersected = false;
        if (s_t == 0.0) {
            if (dot(pu - pa, n_proj) == 0.0) {  // on the ray's line
                const double test1 = dot(pa - pu, pa - pb_proj) / norm2_ab_proj;
                const double test2 = dot(pa - pv, pa - pb_proj) / norm2_ab_proj;
                if (test1 >= 0) {
                    coord_k = test1;
                    coord_t = 0.0;
                } else {
                    coord_k = test2;
                    coord_t = 1.0;
                }
                intersected = coord_k > 0.0 && coord_t >= 0.0 && coord_t <= 1.0;
            }
        } else {
            coord_k = dot(pa - pu, n_uv) * 1.0 / s_k;
            coord_t = dot(pu - pa, n_proj) * 1.0 / s_t;
            intersected = coord_k > 0.0 && coord_t >= 0.0 && coord_t <= 1.0;
        }
        if (intersected) {
            if (!initialized || coord_k > kmin) {
                indices = {tri[std::size_t(u)], tri[std::size_t(v)]};
                bary = coord_t;
                kmin = coord_k;
            }
            initialized = true;
        }
        validated = validated || initialized;
    }
    return validated;
}

// computeIntersectedPointsList: from a in triangle ta (or from the point last_point a previous cut
// ended on: the triangle around it the ray leaves by an edge not on it), triangle after triangle
// through the edge the ray leaves by (a crossing on a vertex: the triangle around it whose exit
// is nearest b) until b's triangle tb. `edges`, `coords`: the edges crossed and the coordinate of
// each crossing from the edge's vertex 0. Kept as SOFA's, including the reads of the last test's
// edge after a fan of tests.
bool TriangleIncision::intersected_points(PointId last_point, const Vec3& a, const Vec3& b, ElementId& ta,
                                          ElementId& tb, std::vector<ElementId>& edges,
                                          std::vector<double>& coords) const {
    const MeshTopology& m = mesh();
    bool validated = true, on_boundary = false;
    std::vector<PointId> indices;
    EdgeCrossing last_edge;  // what SOFA's cleared vector still holds
    const auto remember = [&] {
        if (indices.size() > 1) last_edge = {{indices[0], indices[1]}, true};
    };
    double coord_t = 0.0, coord_k = 0.0;
    Vec3 p_current = a;
    ElementId current = ta, triangle = ta;
    bool intersected = segment_triangle_intersection(false, p_current, b, current, indices, coord_t, coord_k);
    remember();
    if (last_point >= 0 && (!intersected || indices[0] == last_point || indices[1] == last_point)) {
        const std::vector<ElementId> shell = m.triangles_around_vertex()[std::size_t(last_point)];
        for (const ElementId s : shell) {
            if (s != current) {
                intersected = segment_triangle_intersection(false, p_current, b, s, indices, coord_t, coord_k);
                remember();
            }
            if (intersected && last_edge.v[0] != last_point && last_edge.v[1] != last_point) {
                current = s;
                ta = current;
                break;
            }
        }
    }
    if (ta == tb) return false;  // SOFA: "inputs elements are the same element"
    double coord_k_test = coord_k;
    double dist_min = dot(b - a, b - a);
    std::size_t guard = 0;
    while (coord_k_test < 1.0 && validated && intersected) {
        if (++guard > 4 * m.triangles().size() + 8) return false;  // a loop SOFA would not leave
        const PointId e0 = last_edge.v[0], e1 = last_edge.v[1];
        const ElementId edge = m.edge_index(e0, e1);
        if (edge < 0) return false;
        edges.push_back(edge);
        coords.push_back(m.edges()[std::size_t(edge)][0] == e0 ? coord_t : 1.0 - coord_t);
        const auto at_t = [&](PointId u, PointId v, double t) {
            return Vec3((1.0 - t) * x(u)[0] + t * x(v)[0], (1.0 - t) * x(u)[1] + t * x(v)[1],
                        (1.0 - t) * x(u)[2] + t * x(v)[2]);
        };
        p_current = at_t(e0, e1, coord_t);
        std::vector<ElementId> shell;
        const ElementId from = current;
        const bool on_vertex = coord_t == 0.0 || coord_t == 1.0;
        if (on_vertex) {
            shell = m.triangles_around_vertex()[std::size_t(coord_t == 0.0 ? e0 : e1)];
            if (shell.empty()) return false;  // (a vertex of the current triangle has it in its shell)
            triangle = shell[0];
            if (shell.size() <= 1) {
                on_boundary = true;
                validated = false;
                continue;
            }
        } else {
            shell = m.triangles_around_edge()[std::size_t(edge)];
        }
        triangle = shell[0];
        bool test_init = false;
        for (const ElementId s : shell) {
            if (s == from) continue;
            triangle = s;
            intersected = segment_triangle_intersection(true, p_current, b, s, indices, coord_t, coord_k);
            remember();
            if (!intersected) continue;
            const Vec3 c = at_t(last_edge.v[0], last_edge.v[1], coord_t);
            const double dist = dot(b - c, b - c);
            if (!test_init || (dist < dist_min && coord_k <= 1)) {
                coord_k_test = coord_k;
                dist_min = dist;
                current = s;
            }
            test_init = true;
        }
        intersected = test_init;
    }
    (void)on_boundary;
    if (tb < 0) tb = triangle;
    const bool reached = tb == triangle && coord_k_test >= 1.0;
    return reached && validated && intersected;
}

// computeIntersectedObjectsList: the path as SplitAlongPath reads it: a (triangle ta with its
// barycentric coordinates, or the point last_point), the edges crossed, b (triangle tb, or its
// vertex when one of b's coordinates exceeds 0.9999).
bool TriangleIncision::intersected_objects(PointId last_point, const Vec3& a, const Vec3& b, ElementId& ta,
                                           ElementId& tb, std::vector<IncisionPathElement>& path) const {
    std::vector<ElementId> edges;
    std::vector<double> coords;
    if (!intersected_points(last_point, a, b, ta, tb, edges, coords)) return false;
    if (last_point >= 0) {
        const Vec3& p = x(last_point);
        path.push_back({ElementType::point, last_point, {p[0], p[1], p[2]}});
    } else {
        path.push_back({ElementType::triangle, ta, barycentric(ta, a)});
    }
    for (std::size_t i = 0; i < edges.size(); ++i) path.push_back({ElementType::edge, edges[i], {coords[i], 0.0, 0.0}});
    const auto cb = barycentric(tb, b);
    IncisionPathElement last{ElementType::triangle, tb, cb};
    for (int i = 0; i < 3; ++i)
        if (cb[std::size_t(i)] > 0.9999) {
            last.type = ElementType::point;
            last.index = mesh().triangles()[std::size_t(tb)][std::size_t(i)];
            break;
        }
    path.push_back(last);
    return true;
}

std::size_t count_connected_components(const std::vector<Triangle>& triangles, std::size_t num_points) {
    std::vector<std::size_t> parent(num_points);
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    const auto root = [&](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::vector<char> used(num_points, 0);
    for (const Triangle& t : triangles)
        for (int j = 0; j < 3; ++j) {
            used[std::size_t(t[std::size_t(j)])] = 1;
            parent[root(std::size_t(t[std::size_t(j)]))] = root(std::size_t(t[0]));
        }
    std::size_t count = 0;
    for (std::size_t i = 0; i < num_points; ++i) count += used[i] && root(i) == i;
    return count;
}

}  // namespace penalty
