// place_loaded_points: SOFA's loader transform (MeshLoader::reinit, SphereLoader::applyTransform).
#include "penalty/mechanics/loader_placement.hpp"

#include "sofa_quaternion.hpp"
#include "sofa_vector_ops.hpp"

#include <array>
#include <numbers>

namespace penalty {

namespace {
using Matrix4 = std::array<std::array<double, 4>, 4>;

Matrix4 identity4() {
    Matrix4 m{};
    for (std::size_t i = 0; i < 4; ++i) m[i][i] = 1.0;
    return m;
}

/// type::Mat operator*: r(i, j) = 0 + Σ_k a(i, k)·b(k, j), k in order.
Matrix4 product(const Matrix4& a, const Matrix4& b) {
    Matrix4 r{};
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t k = 0; k < 4; ++k)
            for (std::size_t j = 0; j < 4; ++j) r[i][j] += a[i][k] * b[k][j];
    return r;
}

/// Mat::transform: r_i = m_i0·v0 + m_i1·v1 + m_i2·v2 + m_i3, left to right.
Vec3 transform(const Matrix4& m, const Vec3& v) {
    Vec3 r;
    for (std::size_t i = 0; i < 3; ++i) {
        double s = m[i][0] * v[0];
        s += m[i][1] * v[1];
        s += m[i][2] * v[2];
        s += m[i][3];
        r[Eigen::Index(i)] = s;
    }
    return r;
}

/// transformInvertMatrix: R⁻¹ by invertMatrix, t' = (−1·R⁻¹)·t; false when R is singular.
bool transform_inverse(const Matrix4& m, Matrix4& out) {
    Mat3 r;
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j) r(Eigen::Index(i), Eigen::Index(j)) = m[i][j];
    if (sofa_vec::determinant(r) == 0.0) return false;
    const Mat3 r_inv = sofa_vec::inverse(r);
    out = identity4();
    for (std::size_t i = 0; i < 3; ++i) {
        double t = 0.0;
        for (std::size_t k = 0; k < 3; ++k) t += (r_inv(Eigen::Index(i), Eigen::Index(k)) * -1.0) * m[k][3];
        for (std::size_t j = 0; j < 3; ++j) out[i][j] = r_inv(Eigen::Index(i), Eigen::Index(j));
        out[i][3] = t;
    }
    return true;
}
}  // namespace

void place_loaded_points(std::span<Vec3> points, const Vec3& translation, const Vec3& rotation_degrees,
                         const Vec3& scale3d, LoaderKind kind) {
    if (translation.isZero(0.0) && rotation_degrees.isZero(0.0) && scale3d == Vec3::Ones()) return;
    Matrix4 shift = identity4(), rotation = identity4(), scale = identity4();
    for (std::size_t i = 0; i < 3; ++i) {
        shift[i][3] = translation[Eigen::Index(i)];
        scale[i][i] = scale3d[Eigen::Index(i)];
    }
    // createQuaterFromEuler(rotation · M_PI / 180.0): (r·π)/180 per component
    const Vec3 radians(rotation_degrees[0] * std::numbers::pi / 180.0, rotation_degrees[1] * std::numbers::pi / 180.0,
                       rotation_degrees[2] * std::numbers::pi / 180.0);
    const Mat3 r = sofa_quat::to_matrix(sofa_quat::from_euler_zyx(radians));
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j) rotation[i][j] = r(Eigen::Index(i), Eigen::Index(j));
    const Matrix4 t = product(product(shift, rotation), scale);
    Matrix4 inverse;
    const bool round_trip = kind == LoaderKind::mesh_loader && transform_inverse(t, inverse);
    for (Vec3& p : points) {
        p = transform(t, p);
        if (round_trip) p = transform(t, transform(inverse, p));
    }
}

}  // namespace penalty
