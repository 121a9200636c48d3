#pragma once
/// @file
/// A hexahedron's element stiffness times a vector, f = K·d (K 24×24, stored by columns as
/// Eigen's default), each row summed left to right as SOFA's Mat<24,24>::operator*(Vec<24>):
///   f_i = (…((k_i,0·d_0 + k_i,1·d_1) + k_i,2·d_2) + …) + k_i,23·d_23
/// HexahedronFEMForceField's and HexahedralFEMForceField's force and product (accumulateForce*,
/// addDForce) do one per element. Scalar (the reference) and in AVX lanes of four rows
/// (KernelPath::avx; avx512 runs avx): a column's four rows are one load, and each lane does its
/// row's operations in their order, IEEE lane-wise, nothing fused, so every path gives the same
/// bits (tests/kernels/test_hexahedron_stiffness.cpp). Internal (namespace detail).
#include "penalty/mechanics/kernel_path.hpp"

#include <Eigen/Core>

namespace penalty::detail {

using HexahedronStiffness = Eigen::Matrix<double, 24, 24>;
using HexahedronVector = Eigen::Matrix<double, 24, 1>;

/// f = K·d, rows summed left to right (see the file comment), on `path`'s instructions.
[[nodiscard]] HexahedronVector hexahedron_stiffness_times(KernelPath path, const HexahedronStiffness& k,
                                                          const HexahedronVector& d);

}  // namespace penalty::detail
