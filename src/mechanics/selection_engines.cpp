#include "penalty/mechanics/selection_engines.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty {

MeshRegion::MeshRegion(std::vector<Vec3> points, std::vector<Triangle> triangles, bool use_mesh)
    : points_(std::move(points)), triangles_(std::move(triangles)), use_mesh_(use_mesh) {
    check_triangles();
    // MeshROI::computeBoundingBox: b[0..2] collect the largest coordinates and b[3..5] the least,
    // then each pair is swapped into (min, max)
    std::array<double, 6>& b = box_;
    if (!points_.empty()) {
        const Vec3& p = points_[0];
        b = {p[0], p[1], p[2], p[0], p[1], p[2]};
        for (std::size_t i = 1; i < points_.size(); ++i) {
            const Vec3& q = points_[i];
            for (int k = 0; k < 3; ++k) {
                if (b[std::size_t(k)] < q[k]) b[std::size_t(k)] = q[k];
                if (b[std::size_t(k) + 3] > q[k]) b[std::size_t(k) + 3] = q[k];
            }
        }
    }
    for (std::size_t k = 0; k < 3; ++k)
        if (b[k] > b[k + 3]) std::swap(b[k], b[k + 3]);
}

void MeshRegion::check_triangles() const {
    for (std::size_t t = 0; t < triangles_.size(); ++t)
        for (const PointId i : triangles_[t])
            if (i < 0 || std::size_t(i) >= points_.size())
                throw_invalid_argument("MeshROI: ROI triangle ", t, " uses point ", i, " but the ROI mesh has ",
                                       points_.size(), " points");
}

MeshRegion MeshRegion::moved(std::vector<Vec3> points) const {
    MeshRegion region = *this;
    region.points_ = std::move(points);
    region.check_triangles();
    return region;
}

bool MeshRegion::in_box(const Vec3& p) const {
    const auto& b = box_;
    return p[0] >= b[0] && p[0] <= b[3] && p[1] >= b[1] && p[1] <= b[4] && p[2] >= b[2] && p[2] <= b[5];
}

namespace {

/// MeshROI::checkSameOrder: ((B − A) × (pt − A))·N ≥ 0, SOFA's operation order.
bool same_order(const Vec3& a, const Vec3& b, const Vec3& pt, const Vec3& n) {
    const double v0 = ((b[1] - a[1]) * (pt[2] - a[2])) - ((pt[1] - a[1]) * (b[2] - a[2]));
    const double v1 = ((b[2] - a[2]) * (pt[0] - a[0])) - ((pt[2] - a[2]) * (b[0] - a[0]));
    const double v2 = ((b[0] - a[0]) * (pt[1] - a[1])) - ((pt[0] - a[0]) * (b[1] - a[1]));
    return !(v0 * n[0] + v1 * n[1] + v2 * n[2] < 0);
}

}  // namespace

bool MeshRegion::contains(const Vec3& p) const {
    if (!use_mesh_) return true;
    if (!in_box(p)) return false;
    const auto& b = box_;
    // the ray's end: 100 beyond the box corner nearest to p
    Vec3 ray;
    const double to_min = (b[0] - p[0]) * (b[0] - p[0]) + (b[1] - p[1]) * (b[1] - p[1]) + (b[2] - p[2]) * (b[2] - p[2]);
    const double to_max = (b[3] - p[0]) * (b[3] - p[0]) + (b[4] - p[1]) * (b[4] - p[1]) + (b[5] - p[2]) * (b[5] - p[2]);
    if (to_min < to_max) ray = Vec3((b[0] - 100.0) - p[0], (b[1] - 100.0) - p[1], (b[2] - 100.0) - p[2]);
    else ray = Vec3((b[3] + 100.0) - p[0], (b[4] + 100.0) - p[1], (b[5] + 100.0) - p[2]);
    int through = 0;
    for (const Triangle& t : triangles_) {
        const Vec3& p0 = points_[std::size_t(t[0])];
        const Vec3& p1 = points_[std::size_t(t[1])];
        const Vec3& p2 = points_[std::size_t(t[2])];
        const Vec3 n((p1[1] - p0[1]) * (p2[2] - p1[2]) - (p1[2] - p0[2]) * (p2[1] - p1[1]),
                     (p1[2] - p0[2]) * (p2[0] - p1[0]) - (p1[0] - p0[0]) * (p2[2] - p1[2]),
                     (p1[0] - p0[0]) * (p2[1] - p1[1]) - (p1[1] - p0[1]) * (p2[0] - p1[0]));
        const double dot = n[0] * ray[0] + n[1] * ray[1] + n[2] * ray[2];
        if (dot == 0) continue;
        const double d = (n[0] * (p0[0] - p[0]) + n[1] * (p0[1] - p[1]) + n[2] * (p0[2] - p[2])) / dot;
        if (!(d >= 0)) continue;
        const Vec3 hit(p[0] + d * ray[0], p[1] + d * ray[1], p[2] + d * ray[2]);
        if (same_order(p0, p1, hit, n) && same_order(p1, p2, hit, n) && same_order(p2, p0, hit, n)) ++through;
    }
    return through % 2 != 0;
}

namespace {

/// ProximityROI's SortingPair: ordered by distance (a max-heap keeps the farthest on top).
struct SortingPair {
    double distance;
    unsigned index;
    bool operator<(const SortingPair& other) const { return distance < other.distance; }
};

}  // namespace

ProximitySelection proximity_roi(std::span<const Vec3> points, std::span<const Vec3> centers, std::vector<double> radii,
                                 std::size_t max_count) {
    ProximitySelection out;
    if (centers.empty() || radii.empty() || max_count == 0) {
        out.indices = {0};  // SOFA's initial value of `indices`, left as it was
        return out;
    }
    if (centers.size() > radii.size()) radii.resize(centers.size(), radii.back());
    std::vector<SortingPair> heap;
    for (std::size_t i = 0; i < points.size(); ++i) {
        double least = std::numeric_limits<double>::max();
        for (std::size_t j = 0; j < centers.size(); ++j) {
            const Vec3 d(centers[j][0] - points[i][0], centers[j][1] - points[i][1], centers[j][2] - points[i][2]);
            const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (dist < radii[j] && least > dist) least = dist;
        }
        const auto index = static_cast<unsigned>(i);
        if (least == std::numeric_limits<double>::max()) {
            out.indices_out.push_back(PointId(i));
            continue;
        }
        if (heap.empty()) {
            heap.push_back({least, index});
            std::push_heap(heap.begin(), heap.end());
        } else if (heap.front().distance >= least) {
            if (heap.size() >= max_count) {
                std::pop_heap(heap.begin(), heap.end());
                heap.pop_back();
                out.indices_out.push_back(PointId(heap.front().index));  // SOFA's reference to the front
            }
            heap.push_back({least, index});
            std::push_heap(heap.begin(), heap.end());
        } else if (heap.size() < max_count) {
            heap.push_back({least, index});
            std::push_heap(heap.begin(), heap.end());
        } else {
            out.indices_out.push_back(PointId(i));
        }
    }
    for (const SortingPair& p : heap) {
        out.indices.push_back(PointId(p.index));
        out.distances.push_back(p.distance);
        out.points.push_back(points[p.index]);
    }
    return out;
}

namespace {

/// ValuesFromPositions::valueFromPosition.
double value_at(const Vec3& p, const Vec3& dir, std::span<const double> values, double bmin, double bmax) {
    const auto n = static_cast<int>(values.size());
    if (n == 0) return 0;
    if (n == 1) return values[0];
    double coef = p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2];
    coef = (coef - bmin) / (bmax - bmin);
    coef *= (n - 1);
    const int v = static_cast<int>(std::floor(coef));
    if (v < 0) return values[0];
    if (v >= n - 1) return values[std::size_t(n - 1)];
    coef -= v;
    return values[std::size_t(v)] * (1 - coef) + values[std::size_t(v) + 1] * coef;
}

Vec3 sum(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }

}  // namespace

ValuesFromPositionsResult values_from_positions(std::span<const Vec3> points, const std::vector<Edge>& edges,
                                                const std::vector<Triangle>& triangles,
                                                const std::vector<Tetrahedron>& tetrahedra, const Vec3& direction,
                                                std::span<const double> input_values, double bmin, double bmax,
                                                bool vector_field) {
    const auto at = [&](PointId i) -> const Vec3& {
        if (i < 0 || std::size_t(i) >= points.size())
            throw_invalid_argument("ValuesFromPositions: an element uses point ", i, " but there are ", points.size(),
                                   " points");
        return points[std::size_t(i)];
    };
    // the centres, as SOFA sums them: (p1 + p0)·0.5, (p2 + p1 + p0)/3, (p3 + p2 + p1 + p0)/4
    std::vector<Vec3> edge_centers, triangle_centers, tetrahedron_centers;
    for (const Edge& e : edges) {
        const Vec3 s = sum(at(e[1]), at(e[0]));
        edge_centers.emplace_back(s[0] * 0.5, s[1] * 0.5, s[2] * 0.5);
    }
    for (const Triangle& t : triangles) {
        const Vec3 s = sum(sum(at(t[2]), at(t[1])), at(t[0]));
        triangle_centers.emplace_back(s[0] / 3.0, s[1] / 3.0, s[2] / 3.0);
    }
    for (const Tetrahedron& t : tetrahedra) {
        const Vec3 s = sum(sum(sum(at(t[3]), at(t[2])), at(t[1])), at(t[0]));
        tetrahedron_centers.emplace_back(s[0] / 4.0, s[1] / 4.0, s[2] / 4.0);
    }
    ValuesFromPositionsResult r;
    if (vector_field) {
        r.point_vectors.assign(points.size(), direction);
        r.edge_vectors.assign(edges.size(), direction);
        r.triangle_vectors.assign(triangles.size(), direction);
        r.tetrahedron_vectors.assign(tetrahedra.size(), direction);
        return r;
    }
    const auto values = [&](std::span<const Vec3> where, std::vector<double>& out) {
        for (const Vec3& p : where) out.push_back(value_at(p, direction, input_values, bmin, bmax));
    };
    values(points, r.point_values);
    values(edge_centers, r.edge_values);
    values(triangle_centers, r.triangle_values);
    values(tetrahedron_centers, r.tetrahedron_values);
    return r;
}

}  // namespace penalty
