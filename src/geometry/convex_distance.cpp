#include "penalty/geometry/convex_distance.hpp"

#include "penalty/geometry/point_segment.hpp"
#include "penalty/geometry/point_triangle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace penalty {

ConvexShape ConvexShape::point(const Vec3& p) {
    ConvexShape s;
    s.kind = Kind::kPoint;
    s.v[0] = p;
    return s;
}
ConvexShape ConvexShape::segment(const Vec3& a, const Vec3& b) {
    ConvexShape s;
    s.kind = Kind::kSegment;
    s.v[0] = a;
    s.v[1] = b;
    return s;
}
ConvexShape ConvexShape::triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    ConvexShape s;
    s.kind = Kind::kTriangle;
    s.v[0] = a;
    s.v[1] = b;
    s.v[2] = c;
    return s;
}
ConvexShape ConvexShape::make_cylinder(const CylinderShape& c) {
    ConvexShape s;
    s.kind = Kind::kCylinder;
    s.cylinder = c;
    return s;
}

Vec3 ConvexShape::support(const Vec3& d) const {
    switch (kind) {
        case Kind::kPoint:
            return v[0];
        case Kind::kSegment:
            return d.dot(v[1]) > d.dot(v[0]) ? v[1] : v[0];
        case Kind::kTriangle: {
            int best = 0;
            double bd = d.dot(v[0]);
            for (int i = 1; i < 3; ++i) {
                const double di = d.dot(v[i]);
                if (di > bd) {
                    bd = di;
                    best = i;
                }
            }
            return v[best];
        }
        case Kind::kCylinder: {
            const Vec3& u = cylinder.axis;
            const double da = d.dot(u);
            Vec3 s = cylinder.center + (da >= 0.0 ? 1.0 : -1.0) * cylinder.half_height * u;
            const Vec3 perp = d - da * u;
            const double pn = perp.norm();
            if (pn > 1e-300 && pn > 1e-15 * d.norm()) s += cylinder.radius * (perp / pn);
            return s;
        }
    }
    return v[0];
}

Vec3 ConvexShape::inner_point() const {
    switch (kind) {
        case Kind::kPoint:
            return v[0];
        case Kind::kSegment:
            return 0.5 * (v[0] + v[1]);
        case Kind::kTriangle:
            return (v[0] + v[1] + v[2]) / 3.0;
        case Kind::kCylinder:
            return cylinder.center;
    }
    return v[0];
}

namespace {

double extent(const ConvexShape& s) {
    const Vec3 c = s.inner_point();
    switch (s.kind) {
        case ConvexShape::Kind::kPoint:
            return 0.0;
        case ConvexShape::Kind::kSegment:
            return std::max((s.v[0] - c).norm(), (s.v[1] - c).norm());
        case ConvexShape::Kind::kTriangle:
            return std::max({(s.v[0] - c).norm(), (s.v[1] - c).norm(), (s.v[2] - c).norm()});
        case ConvexShape::Kind::kCylinder:
            return s.cylinder.radius + s.cylinder.half_height;
    }
    return 0.0;
}

struct Simplex {
    std::array<Vec3, 4> w, a, b;
    std::array<double, 4> lambda{};
    int n = 0;
};

// closest point of conv(simplex) to the origin; reduces the simplex to the supporting feature
// and sets the barycentric weights. Returns true if the origin is inside a full tetrahedron.
bool reduce(Simplex& s, Vec3& v) {
    const Vec3 origin = Vec3::Zero();
    // s becomes its vertices idx (in that order) with weights lam, the weights past them 0
    auto keep = [&s](std::initializer_list<int> idx, std::initializer_list<double> lam) {
        const Simplex old = s;
        int k = 0;
        auto li = lam.begin();
        s.lambda = {};
        for (int i : idx) {
            s.w[k] = old.w[i];
            s.a[k] = old.a[i];
            s.b[k] = old.b[i];
            s.lambda[k] = *li++;
            ++k;
        }
        s.n = k;
    };
    if (s.n == 1) {
        s.lambda[0] = 1.0;
    } else if (s.n == 2) {
        const PointSegmentResult r = point_segment_closest_point(origin, s.w[0], s.w[1]);
        if (r.feature == SegmentFeature::A) keep({0}, {1.0});
        else if (r.feature == SegmentFeature::B) keep({1}, {1.0});
        else keep({0, 1}, {1.0 - r.t, r.t});
    } else if (s.n == 3) {
        const PointTriangleResult r = point_triangle_closest_point(origin, s.w[0], s.w[1], s.w[2]);
        const Vec3& l = r.barycentric;
        switch (r.feature) {
            case TriangleFeature::V0:
                keep({0}, {1.0});
                break;
            case TriangleFeature::V1:
                keep({1}, {1.0});
                break;
            case TriangleFeature::V2:
                keep({2}, {1.0});
                break;
            case TriangleFeature::E01:
                keep({0, 1}, {l[0], l[1]});
                break;
            case TriangleFeature::E12:
                keep({1, 2}, {l[1], l[2]});
                break;
            case TriangleFeature::E20:
                keep({2, 0}, {l[2], l[0]});
                break;
            case TriangleFeature::Face:
                keep({0, 1, 2}, {l[0], l[1], l[2]});
                break;
        }
    } else {
        // tetrahedron: inside test by face orientation, else the closest face
        constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
        const double vol = (s.w[1] - s.w[0]).dot((s.w[2] - s.w[0]).cross(s.w[3] - s.w[0]));
        bool inside = vol != 0.0;
        for (int k = 0; k < 4 && inside; ++k) {
            const Vec3& p0 = s.w[kFace[k][0]];
            const Vec3 n = (s.w[kFace[k][1]] - p0).cross(s.w[kFace[k][2]] - p0);
            const double side_vertex = n.dot(s.w[k] - p0);
            const double side_origin = n.dot(origin - p0);
            if (side_vertex * side_origin < 0.0) inside = false;
        }
        if (inside) {
            v.setZero();
            return true;
        }
        double best = std::numeric_limits<double>::infinity();
        int bk = 0;
        for (int k = 0; k < 4; ++k) {
            const double d2 = point_triangle_closest_point(origin, s.w[kFace[k][0]], s.w[kFace[k][1]], s.w[kFace[k][2]])
                                  .distance_squared;
            if (d2 < best) {
                best = d2;
                bk = k;
            }
        }
        keep({kFace[bk][0], kFace[bk][1], kFace[bk][2]}, {0.0, 0.0, 0.0});  // the face, weighed by reduce
        return reduce(s, v);
    }
    v.setZero();
    for (int i = 0; i < s.n; ++i) v += s.lambda[i] * s.w[i];
    return false;
}

}  // namespace

ConvexDistanceResult convex_distance(const ConvexShape& A, const ConvexShape& B, double relative_tolerance,
                                     int max_iterations) {
    ConvexDistanceResult res;
    const double scale = 1.0 + extent(A) + extent(B) + (A.inner_point() - B.inner_point()).norm();
    const double tiny2 = 1e-24 * scale * scale;

    Simplex s;
    Vec3 v = A.inner_point() - B.inner_point();
    if (v.squaredNorm() <= tiny2) v = Vec3::UnitX();
    Simplex best_s;
    Vec3 best_v = v;
    bool have_best = false;
    bool overlap = false;
    int it = 0;
    for (; it < max_iterations; ++it) {
        const Vec3 d = -v;
        const Vec3 pa = A.support(d);
        const Vec3 pb = B.support(-d);
        const Vec3 w = pa - pb;
        const double vv = v.squaredNorm();
        if (have_best) {
            // converged: the lower bound v·w/|v| is within tolerance of the upper bound |v|
            if (vv - v.dot(w) <= relative_tolerance * vv) break;
            bool dup = false;
            for (int i = 0; i < s.n; ++i) dup = dup || (s.w[i] - w).squaredNorm() <= tiny2;
            if (dup) break;
        }
        s.w[s.n] = w;
        s.a[s.n] = pa;
        s.b[s.n] = pb;
        ++s.n;
        Vec3 nv;
        if (reduce(s, nv) || nv.squaredNorm() <= tiny2) {
            overlap = true;
            best_s = s;
            best_v = nv;
            break;
        }
        if (have_best && nv.squaredNorm() >= best_v.squaredNorm()) break;  // no progress
        v = nv;
        best_v = nv;
        best_s = s;
        have_best = true;
    }
    res.iterations = it;
    res.overlapping = overlap;
    res.point_a.setZero();
    res.point_b.setZero();
    double lsum = 0.0;
    for (int i = 0; i < best_s.n; ++i) {
        res.point_a += best_s.lambda[i] * best_s.a[i];
        res.point_b += best_s.lambda[i] * best_s.b[i];
        lsum += best_s.lambda[i];
    }
    if (best_s.n == 0 || !(lsum > 0.0)) {
        res.point_a = A.inner_point();
        res.point_b = B.inner_point();
    }
    res.distance = overlap ? 0.0 : (res.point_b - res.point_a).norm();
    return res;
}

ConvexPenetrationResult convex_penetration(const ConvexShape& a, const ConvexShape& b,
                                           std::span<const Vec3> candidates) {
    ConvexPenetrationResult best;
    best.depth = std::numeric_limits<double>::infinity();
    bool any = false;
    for (const Vec3& c : candidates) {
        const double len = c.norm();
        if (!(len > 1e-12) || !std::isfinite(len)) continue;
        for (double sign : {1.0, -1.0}) {
            const Vec3 n = sign * c / len;
            const Vec3 sa = a.support(n);
            const Vec3 sb = b.support(-n);
            const double depth = n.dot(sa) - n.dot(sb);
            if (depth < best.depth) {
                best.depth = depth;
                best.normal = n;
                best.point_a = sa;
                best.point_b = sb;
                any = true;
            }
        }
    }
    if (!any) {
        best = ConvexPenetrationResult{};
        best.point_a = a.inner_point();
        best.point_b = b.inner_point();
        best.depth = 0.0;
    }
    return best;
}

}  // namespace penalty
