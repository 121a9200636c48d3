#include "triangle_fem_sofa_order.hpp"

#include "sofa_vector_ops.hpp"

#include <cmath>
#include <limits>

namespace penalty::triangle_fem_sofa {

using sofa_vec::minus;

Mat3 rotation(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ex = sofa_vec::normalized(minus(b, a));
    const Vec3 ez = sofa_vec::normalized(sofa_vec::cross(ex, minus(c, a)));
    const Vec3 ey = sofa_vec::cross(ez, ex);
    Mat3 r;
    r << ex[0], ex[1], ex[2], ey[0], ey[1], ey[2], ez[0], ez[1], ez[2];
    return r;
}

std::array<Vec3, 2> rest_local_large(const Mat3& rest_rotation, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ra = sofa_vec::times(rest_rotation, a);
    return {minus(sofa_vec::times(rest_rotation, b), ra), minus(sofa_vec::times(rest_rotation, c), ra)};
}

bool strain_displacement_local(StrainDisplacement& j, const Vec3& b, const Vec3& c) {
    const double det = b[0] * c[1];
    if (std::abs(det) < std::numeric_limits<double>::epsilon()) return false;
    const double inv = 1 / det;
    j.setZero();
    j(0, 0) = j(1, 2) = -c[1] * inv;
    j(0, 2) = j(1, 1) = (c[0] - b[0]) * inv;
    j(2, 0) = j(3, 2) = c[1] * inv;
    j(2, 2) = j(3, 1) = -c[0] * inv;
    j(4, 2) = j(5, 1) = b[0] * inv;
    return true;
}

double area(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = sofa_vec::cross(minus(b, a), minus(c, a));
    return 0.5 * std::sqrt(sofa_vec::dot3(n, n));
}

bool element_forces(bool large, const std::array<Vec3, 2>& rest, const Vec3& db, const Vec3& dc, const Mat3& material,
                    StrainDisplacement& j, Vec3& strain, Vec3& stress, Displacement& forces) {
    Displacement d;
    // computeDisplacementLarge (the local y of b is 0 by construction) / computeDisplacementSmall
    if (large) d << 0, 0, rest[0][0] - db[0], 0, rest[1][0] - dc[0], rest[1][1] - dc[1];
    else d << 0, 0, rest[0][0] - db[0], rest[0][1] - db[1], rest[1][0] - dc[0], rest[1][1] - dc[1];
    if (!strain_displacement_local(j, db, dc)) return false;
    strain = detail::strain_of(!large, j, d);
    stress = detail::stress_of(!large, material, strain);
    forces = detail::forces_of(large, j, stress);
    return true;
}

}  // namespace penalty::triangle_fem_sofa
