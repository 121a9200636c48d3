#pragma once
/// @file
/// Loops over flat vectors shared by the CG and a subtree's system: each in SOFA's order of
/// operations (private to the simulation stage).

#include "penalty/mechanics/mechanical_object.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace penalty::detail {

/// Σ aᵢbᵢ, left to right (no vectorised partial sums).
inline double sequential_dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    double sum = 0.0;
    for (Eigen::Index i = 0; i < a.size(); ++i) sum += a[i] * b[i];
    return sum;
}

/// One state's part of SubtreeSystem::dot over the scalars [begin, end) of DOFs `width` wide:
/// d = Σ_c a_c·b_c left to right per DOF, sum = 0, sum += d per DOF in order.
inline double state_dot(const double* a, const double* b, Eigen::Index begin, Eigen::Index end, Eigen::Index width) {
    double sum = 0.0;
    if (width == 3) {  // Vec3 states, the common case: the same sums with a fixed inner count
        for (Eigen::Index i = begin; i < end; i += 3) sum += (a[i] * b[i] + a[i + 1] * b[i + 1]) + a[i + 2] * b[i + 2];
        return sum;
    }
    for (Eigen::Index i = begin; i < end; i += width) {
        double dof = a[i] * b[i];
        for (Eigen::Index c = 1; c < width; ++c) dof += a[i + c] * b[i + c];
        sum += dof;
    }
    return sum;
}

/// One state's part of SubtreeSystem::update_and_residual over the scalars [begin, end) of DOFs
/// `width` wide: x_j += α·p_j, r_j −= α·q_j (Eigen's x_j + (α·p_j), r_j − (α·q_j)), then the
/// state's r·r as state_dot sums it (a Vec3 DOF's sum right after its update).
inline double update_state(double alpha, const double* p, const double* q, double* x, double* r, Eigen::Index begin,
                           Eigen::Index end, Eigen::Index width) {
    if (width == 3) {
        double sum = 0.0;
        for (Eigen::Index j = begin; j < end; j += 3) {
            for (Eigen::Index c = j; c < j + 3; ++c) {
                x[c] += alpha * p[c];
                r[c] -= alpha * q[c];
            }
            sum += (r[j] * r[j] + r[j + 1] * r[j + 1]) + r[j + 2] * r[j + 2];
        }
        return sum;
    }
    for (Eigen::Index j = begin; j < end; ++j) {
        x[j] += alpha * p[j];
        r[j] -= alpha * q[j];
    }
    return state_dot(r, r, begin, end, width);
}

/// p_j = r_j (first) or r_j + β·p_j, into p and dx, for j < n: three vectors apart (segments
/// of distinct vectors), so the compiler may run the lanes together; each value gets the same
/// operations as in the loop over j alone.
inline void direction(bool first, double beta, const double* __restrict r, double* __restrict p, double* __restrict dx,
                      Eigen::Index n) {
    if (first) {
        for (Eigen::Index j = 0; j < n; ++j) dx[j] = p[j] = r[j];
        return;
    }
    for (Eigen::Index j = 0; j < n; ++j) dx[j] = p[j] = r[j] + beta * p[j];
}

/// Zeroes the DOFs `rows` of a flat vector of DOFs `width` scalars wide.
inline void zero_rows(FlatVector v, Eigen::Index width, const std::vector<std::uint32_t>& rows) {
    if (width == 3) {  // three stores a row (a segment of run-time size is a call to memset per row)
        for (const std::uint32_t row : rows) v.segment<3>(3 * static_cast<Eigen::Index>(row)).setZero();
        return;
    }
    for (const std::uint32_t row : rows) v.segment(width * static_cast<Eigen::Index>(row), width).setZero();
}

}  // namespace penalty::detail
