// SOFA's helper::TriangleOctree (TriangleOctreeRoot::buildOctree / fillOctree,
// TriangleOctree::insert / trace / nearestTriangle), re-implemented: the cells, the order of the
// walk and the arithmetic are SOFA's, so the triangle a ray finds is SOFA's.
#include "mechanics/sofa_vector_ops.hpp"
#include "penalty/collision/ray_trace_narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty {

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kFar = 1e9;  // the walk's "infinite" cell parameter (SOFA's INF)

// SOFA's Vec dot and cross, left to right (no reassociation).
using sofa_vec::dot3;
Vec3 cross3(const Vec3& a, const Vec3& b) {
    return {a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(), a.x() * b.y() - a.y() * b.x()};
}

/// The octant after the current one: the axis of the smallest exit parameter (x → a, y → b,
/// z → c; ties go to the later axis, as SOFA's choose_next).
unsigned next_octant(double x, double y, double z, unsigned a, unsigned b, unsigned c) {
    if (x < y) return x < z ? a : c;
    return y < z ? b : c;
}

}  // namespace

bool ray_triangle_hit(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& origin, const Vec3& direction, double& t,
                      double& u, double& v) {
    t = u = v = 0.0;
    const Vec3 e0 = b - a;
    const Vec3 e1 = c - a;
    const Vec3 p = cross3(direction, e1);
    const double det = dot3(e0, p);
    if (std::abs(det) <= kEpsilon) return false;
    const double inverse = 1.0 / det;
    const Vec3 s = origin - a;
    u = dot3(s, p) * inverse;
    if (u < -kEpsilon || u > 1.0 + kEpsilon) return false;
    const Vec3 q = cross3(s, e0);
    v = dot3(direction, q) * inverse;
    if (v < -kEpsilon || u + v > 1.0 + kEpsilon) return false;
    t = dot3(e1, q) * inverse;
    return !(t < kEpsilon || std::isnan(t) || std::isnan(u) || std::isnan(v));
}

/// The walk's fixed data: the ray mirrored into the positive octant (for the cell parameters),
/// the ray as given (for the triangle tests), the mirrored axes (a) and the axes the ray is
/// parallel to (b).
struct TriangleOctree::Ray {
    Vec3 origin;
    Vec3 given_origin;
    Vec3 given_direction;
    unsigned a = 0;
    unsigned b = 0;
};

void TriangleOctree::build(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
    positions_ = positions;
    triangles_ = triangles;
    used_ = 0;
    (void)new_node(-kHalfSize, -kHalfSize, -kHalfSize, 2.0 * kHalfSize);
    for (std::size_t i = 0; i < triangles.size(); ++i) fill(int(i));
}

int TriangleOctree::new_node(double x, double y, double z, double size) {
    // the nodes of the last build are reused, with their triangle lists' capacity (a surface's
    // tree is built again at every step)
    if (used_ == nodes_.size()) nodes_.emplace_back();
    Node& n = nodes_[used_];
    n.x = x;
    n.y = y;
    n.z = z;
    n.size = size;
    n.children.fill(-1);
    n.leaf = true;
    n.triangles.clear();
    return int(used_++);
}

void TriangleOctree::fill(int triangle) {
    const Triangle& tri = triangles_[std::size_t(triangle)];
    const Vec3& p1 = positions_[std::size_t(tri[0])];
    const Vec3& p2 = positions_[std::size_t(tri[1])];
    const Vec3& p3 = positions_[std::size_t(tri[2])];
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::min({p1[k], p2[k], p3[k]});
        hi[k] = std::max({p1[k], p2[k], p3[k]});
    }
    const double extent = std::max({std::abs(hi[0] - lo[0]), std::abs(hi[1] - lo[1]), std::abs(hi[2] - lo[2])});
    // the depth whose cells are the smallest that hold the box's extent
    const double levels = std::log10(2.0 * kHalfSize / extent) / std::log10(2.0);
    if (!(levels >= 0.0 && levels < 31.0)) return;  // a point-like or a huge triangle: SOFA's shift is undefined there
    const int depth = int(levels);
    const double cell = 2.0 * kHalfSize / double(1 << depth);
    if (lo[0] < -kHalfSize || lo[1] < -kHalfSize || lo[2] < -kHalfSize || hi[0] > kHalfSize || hi[1] > kHalfSize ||
        hi[2] > kHalfSize)
        return;
    const auto first = [&](double l) { return double(int((l + kHalfSize) / cell)) * cell - kHalfSize; };
    for (double x = first(lo[0]); x <= hi[0]; x += cell)
        for (double y = first(lo[1]); y <= hi[1]; y += cell)
            for (double z = first(lo[2]); z <= hi[2]; z += cell) insert(0, x, y, z, cell, triangle);
}

void TriangleOctree::insert(int node, double x, double y, double z, double cell, int triangle) {
    while (cell < nodes_[std::size_t(node)].size) {
        const Node& n = nodes_[std::size_t(node)];
        const double half = n.size / 2;
        const int dx = x >= n.x + half ? 1 : 0;
        const int dy = y >= n.y + half ? 1 : 0;
        const int dz = z >= n.z + half ? 1 : 0;
        const int i = dx * 4 + dy * 2 + dz;
        if (n.children[std::size_t(i)] < 0) {
            const int index =
                new_node(n.x + dx * half, n.y + dy * half, n.z + dz * half, half);  // (n is not used after this)
            nodes_[std::size_t(node)].children[std::size_t(i)] = index;
            nodes_[std::size_t(node)].leaf = false;
        }
        node = nodes_[std::size_t(node)].children[std::size_t(i)];
    }
    nodes_[std::size_t(node)].triangles.push_back(triangle);
}

int TriangleOctree::nearest_in(int node, int first, const Ray& ray, RayHit& hit) const {
    // TriangleOctree::nearestTriangle: `first` (the hit found below, or the node's first
    // triangle), then the node's triangles in order, the strictly nearer replacing it
    double best = 10e8;
    int best_triangle = -1;
    double t = 0, u = 0, v = 0;
    const auto test = [&](int k) {
        const Triangle& tri = triangles_[std::size_t(k)];
        return ray_triangle_hit(positions_[std::size_t(tri[0])], positions_[std::size_t(tri[1])],
                                positions_[std::size_t(tri[2])], ray.given_origin, ray.given_direction, t, u, v);
    };
    if (test(first)) {
        hit = {first, t, u, v};
        best = t;
        best_triangle = first;
    }
    for (const int k : nodes_[std::size_t(node)].triangles) {
        if (!test(k) || !(t < best)) continue;
        hit = {k, t, u, v};
        best = t;
        best_triangle = k;
    }
    if (best_triangle >= 0) hit.triangle = best_triangle;
    return best_triangle;
}

int TriangleOctree::walk(int node, const Ray& ray, double tx0, double ty0, double tz0, double tx1, double ty1,
                         double tz1, RayHit& hit) const {
    if (tx1 < 0.0 || ty1 < 0.0 || tz1 < 0.0) return -1;  // the cell lies behind the origin
    const Node& n = nodes_[std::size_t(node)];
    if (n.leaf) return n.triangles.empty() ? -1 : nearest_in(node, n.triangles.front(), ray, hit);
    // the parameters where the ray crosses the cell's middle planes (a ray parallel to an axis
    // never crosses it: ±"infinity" by the side its origin lies)
    const double centre[3] = {0.5 * (n.x + (n.x + n.size)), 0.5 * (n.y + (n.y + n.size)), 0.5 * (n.z + (n.z + n.size))};
    const auto middle = [&](unsigned axis_bit, double t0, double t1, int axis) {
        if ((ray.b & axis_bit) == 0) return 0.5 * (t0 + t1);
        return ray.origin[axis] < centre[axis] ? kFar : -kFar;
    };
    const double txm = middle(4, tx0, tx1, 0);
    const double tym = middle(2, ty0, ty1, 1);
    const double tzm = middle(1, tz0, tz1, 2);
    // the first octant: by the entry plane (the largest entry parameter)
    unsigned octant = 0;
    if (tx0 > ty0) {
        if (tx0 > tz0) {
            if (tym < tx0) octant |= 2;
            if (tzm < tx0) octant |= 1;
        } else {
            if (txm < tz0) octant |= 4;
            if (tym < tz0) octant |= 2;
        }
    } else if (ty0 > tz0) {
        if (txm < ty0) octant |= 4;
        if (tzm < ty0) octant |= 1;
    } else {
        if (txm < tz0) octant |= 4;
        if (tym < tz0) octant |= 2;
    }
    constexpr unsigned kEnd = 8;
    const auto visit = [&](unsigned child_octant, double ax0, double ay0, double az0, double ax1, double ay1,
                           double az1) {
        const int child = n.children[child_octant ^ ray.a];
        if (child < 0) return -1;
        const int found = walk(child, ray, ax0, ay0, az0, ax1, ay1, az1, hit);
        return found < 0 ? -1 : nearest_in(node, found, ray, hit);
    };
    int found = -1;
    while (octant != kEnd) {
        switch (octant) {
            case 0:
                found = visit(0, tx0, ty0, tz0, txm, tym, tzm);
                octant = next_octant(txm, tym, tzm, 4, 2, 1);
                break;
            case 1:
                found = visit(1, tx0, ty0, tzm, txm, tym, tz1);
                octant = next_octant(txm, tym, tz1, 5, 3, kEnd);
                break;
            case 2:
                found = visit(2, tx0, tym, tz0, txm, ty1, tzm);
                octant = next_octant(txm, ty1, tzm, 6, kEnd, 3);
                break;
            case 3:
                found = visit(3, tx0, tym, tzm, txm, ty1, tz1);
                octant = next_octant(txm, ty1, tz1, 7, kEnd, kEnd);
                break;
            case 4:
                found = visit(4, txm, ty0, tz0, tx1, tym, tzm);
                octant = next_octant(tx1, tym, tzm, kEnd, 6, 5);
                break;
            case 5:
                found = visit(5, txm, ty0, tzm, tx1, tym, tz1);
                octant = next_octant(tx1, tym, tz1, kEnd, 7, kEnd);
                break;
            case 6:
                found = visit(6, txm, tym, tz0, tx1, ty1, tzm);
                octant = next_octant(tx1, ty1, tzm, kEnd, kEnd, 7);
                break;
            default:  // 7: the last octant
                found = visit(7, txm, tym, tzm, tx1, ty1, tz1);
                octant = kEnd;
                break;
        }
        if (found >= 0) return found;
    }
    // no child hit: the node's own triangles
    return n.triangles.empty() ? -1 : nearest_in(node, n.triangles.front(), ray, hit);
}

RayHit TriangleOctree::trace(const Vec3& origin, const Vec3& direction) const {
    RayHit hit;
    if (used_ == 0) return hit;
    Ray ray;
    ray.origin = origin;
    ray.given_origin = origin;
    ray.given_direction = direction;
    Vec3 d = direction;
    const unsigned bits[3] = {4, 2, 1};
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            d[k] = 0.0;  // SOFA sets it to its EPSILON, +0 (a −0 would turn the cell parameters' infinities)
            ray.b |= bits[k];
        } else if (d[k] < 0.0) {
            ray.origin[k] = -ray.origin[k];
            d[k] = -d[k];
            ray.a |= bits[k];
        }
    }
    const double tx0 = (-kHalfSize - ray.origin[0]) / d[0];
    const double tx1 = (kHalfSize - ray.origin[0]) / d[0];
    const double ty0 = (-kHalfSize - ray.origin[1]) / d[1];
    const double ty1 = (kHalfSize - ray.origin[1]) / d[1];
    const double tz0 = (-kHalfSize - ray.origin[2]) / d[2];
    const double tz1 = (kHalfSize - ray.origin[2]) / d[2];
    if (!(std::max({tx0, ty0, tz0}) < std::min({tx1, ty1, tz1}))) return hit;
    const int found = walk(0, ray, tx0, ty0, tz0, tx1, ty1, tz1, hit);
    if (found < 0) return RayHit{};
    hit.triangle = found;
    return hit;
}

RayHit TriangleOctree::nearest_hit(const Vec3& origin, const Vec3& direction) const {
    RayHit best;
    for (std::size_t i = 0; i < triangles_.size(); ++i) {
        const Triangle& tri = triangles_[i];
        double t = 0, u = 0, v = 0;
        if (!ray_triangle_hit(positions_[std::size_t(tri[0])], positions_[std::size_t(tri[1])],
                              positions_[std::size_t(tri[2])], origin, direction, t, u, v))
            continue;
        if (best.triangle < 0 || t < best.t) best = {int(i), t, u, v};
    }
    return best;
}

}  // namespace penalty
