#pragma once
/// @file
/// SpringForceField's kernels: the forces with their Jacobians (SpringForceField::addForce /
/// computeSpringForce) and the product df (addDForce / computeSpringDForce), scalar and in AVX
/// lanes (KernelPath::avx). Each vector lane does the scalar reference's operations in their
/// order, and the sums into f and df run spring by spring in spring order, so every path gives
/// the same bits (tests/kernels/test_springs.cpp). Internal (namespace detail).
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include <array>
#include <cstddef>
#include <span>

namespace penalty::detail {

/// The springs a kernel call covers, [first, end) (a chunk of a loop on threads): where
/// `deferred` marks a spring's end (bit 0: a, bit 1: b; OrderedScatter over the ends), its term is
/// stored (slot 2i: the term t of a, 2i + 1: −t of b, added after) instead of applied; with
/// `energies`, each spring's energy is stored at energies[i] (0 for one no longer than the null
/// length) instead of added to `energy`.
struct SpringRange {
    std::size_t first = 0, end = 0;
    DeferredTerms deferred = {};
    double* energies = nullptr;
};

/// f1[a] += F·U, f2[b] −= F·U and dfdx[i] = m of each spring of `range` in order
/// (SpringForceField's class comment gives the law); `energy` += ½·ks·e² spring by spring.
/// Springs no longer than `null_length` give no force and a zero m.
void spring_forces(KernelPath path, SpringArithmetic arithmetic, std::span<const Spring> springs, SpringRange range,
                   double null_length, Vec3* f1, Vec3* f2, const Vec3* x1, const Vec3* x2, const Vec3* v1,
                   const Vec3* v2, SpringStiffnessColumns* dfdx, double& energy);

/// df1[a] += d, df2[b] −= d for each spring of `range` in order, d = m·(dx_b − dx_a)·k_factor in
/// `arithmetic`'s rounding; `ends` are the springs' ends as byte offsets (a·sizeof(Vec3),
/// b·sizeof(Vec3)), read by the avx path.
void spring_dforces(KernelPath path, SpringArithmetic arithmetic, std::span<const Spring> springs, SpringRange range,
                    const std::array<std::ptrdiff_t, 2>* ends, const SpringStiffnessColumns* dfdx, Vec3* df1, Vec3* df2,
                    const Vec3* dx1, const Vec3* dx2, double k_factor);

}  // namespace penalty::detail
