#include "penalty/geometry/point_tetrahedron.hpp"

#include "penalty/geometry/point_triangle.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace penalty {

PointTetrahedronResult point_tetrahedron_signed_distance(const Vec3& p, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                                                         const Vec3& p3) {
    const std::array<Vec3, 4> v = {p0, p1, p2, p3};
    // face k is opposite vertex k
    constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    double lmax = 0.0;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) lmax = std::max(lmax, (v[i] - v[j]).norm());
    const double vol6 = (p1 - p0).dot((p2 - p0).cross(p3 - p0));
    const bool flat = !(std::abs(vol6) > 1e-14 * lmax * lmax * lmax);

    PointTetrahedronResult res;
    if (!flat) {
        // signed distances to the four face planes, outward normals
        double best = -std::numeric_limits<double>::infinity();
        bool inside = true;
        Vec3 best_n = Vec3::UnitX();
        int best_k = 0;
        for (int k = 0; k < 4; ++k) {
            const Vec3& a = v[kFace[k][0]];
            Vec3 n = (v[kFace[k][1]] - a).cross(v[kFace[k][2]] - a).normalized();
            if (n.dot(v[k] - a) > 0.0) n = -n;  // outward: away from the opposite vertex
            const double sd = n.dot(p - a);
            if (sd > 0.0) inside = false;
            if (sd > best) {
                best = sd;
                best_n = n;
                best_k = k;
            }
        }
        if (inside) {
            res.inside = true;
            res.signed_distance = best;  // <= 0
            res.normal = best_n;
            res.closest = p - best * best_n;
            res.face = best_k;
            return res;
        }
    }
    // outside (or flat): nearest face
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) {
        const PointTriangleResult t = point_triangle_closest_point(p, v[kFace[k][0]], v[kFace[k][1]], v[kFace[k][2]]);
        if (t.distance_squared < best_d2) {
            best_d2 = t.distance_squared;
            res.closest = t.closest;
            res.face = k;
        }
    }
    res.signed_distance = std::sqrt(best_d2);
    const Vec3 d = p - res.closest;
    res.normal = res.signed_distance > 0.0 ? Vec3(d / res.signed_distance) : Vec3::UnitX();
    return res;
}

}  // namespace penalty
