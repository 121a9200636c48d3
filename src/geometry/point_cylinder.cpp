#include "penalty/geometry/point_cylinder.hpp"

#include <cmath>

namespace penalty {

Vec3 any_orthogonal(const Vec3& u) {
    // cross with the coordinate axis least aligned with u
    const Vec3 a = std::abs(u.x()) <= std::abs(u.y()) && std::abs(u.x()) <= std::abs(u.z())
                       ? Vec3::UnitX()
                       : (std::abs(u.y()) <= std::abs(u.z()) ? Vec3::UnitY() : Vec3::UnitZ());
    const Vec3 n = u.cross(a);
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : Vec3::UnitX();
}

PointCylinderResult point_cylinder_signed_distance(const Vec3& p, const CylinderShape& cyl) {
    const Vec3& u = cyl.axis;
    const double r = cyl.radius;
    const double h = cyl.half_height;
    const Vec3 cp = p - cyl.center;
    const double y = cp.dot(u);
    const Vec3 rho = cp - y * u;
    const double rho_n = rho.norm();
    const Vec3 rho_hat = rho_n > 1e-300 ? Vec3(rho / rho_n) : any_orthogonal(u);
    const double sy = y >= 0.0 ? 1.0 : -1.0;
    const bool top = y >= 0.0;
    const double ay = std::abs(y);

    PointCylinderResult res;
    if (ay <= h && rho_n <= r) {
        // inside or on the surface: nearest of the side and the caps
        const double depth_side = r - rho_n;
        const double depth_cap = h - ay;
        if (depth_side < depth_cap) {
            res.signed_distance = -depth_side;
            res.closest = cyl.center + y * u + r * rho_hat;
            res.normal = rho_hat;
            res.feature = CylinderFeature::Side;
        } else {
            res.signed_distance = -depth_cap;
            res.closest = cyl.center + sy * h * u + rho;
            res.normal = sy * u;
            res.feature = top ? CylinderFeature::CapTop : CylinderFeature::CapBottom;
        }
        return res;
    }
    if (ay <= h) {
        res.closest = cyl.center + y * u + r * rho_hat;
        res.feature = CylinderFeature::Side;
    } else if (rho_n <= r) {
        res.closest = cyl.center + sy * h * u + rho;
        res.feature = top ? CylinderFeature::CapTop : CylinderFeature::CapBottom;
    } else {
        res.closest = cyl.center + sy * h * u + r * rho_hat;
        res.feature = top ? CylinderFeature::RimTop : CylinderFeature::RimBottom;
    }
    const Vec3 d = p - res.closest;
    res.signed_distance = d.norm();
    res.normal = res.signed_distance > 0.0 ? Vec3(d / res.signed_distance) : rho_hat;
    return res;
}

}  // namespace penalty
