#pragma once
/// @file
/// Which instructions the per-element loops with a vector path run: the force fields' kernels
/// (SpringForceField add_force and add_dforce, TetrahedronFEMForceField method large), the
/// triangle normals and the traversal's leaf-level box tests. Every path gives the same bits: a
/// vector lane does exactly the scalar operations of one spring, row, element or triangle, in
/// the same order, with no fused multiply-add, and the results are added in the scalar loop's
/// order (docs/mechanics.md, "Vector kernels").

namespace penalty {

enum class KernelPath {
    scalar,  ///< the per-element loops as compiled for the baseline (x86-64: SSE2)
    avx,     ///< 256-bit AVX lanes (x86-64 CPUs with AVX, chosen at run time)
    /// 512-bit AVX-512F lanes, eight elements a vector: TetrahedronFEMForceField's product of
    /// method large only (its other loops run the avx path); see best_fem_kernel_path().
    avx512,
};

/// KernelPath::avx when the build targets x86-64 and this CPU and OS support AVX, else scalar.
[[nodiscard]] KernelPath best_kernel_path();

/// TetrahedronFEMForceField's default: avx512 on Intel CPUs with AVX-512F, else
/// best_kernel_path(). On a Xeon (2026-11-28) its eight-lane product took 0.80–0.84 of the
/// four-lane one's time; on an AMD EPYC of family 26, which splits 512-bit operations, eight lanes
/// took 1.05 of it (2026-11-27): docs/performance.md, "The corotational product in eight lanes".
[[nodiscard]] KernelPath best_fem_kernel_path();

/// Whether `path` can run on this machine (scalar always can).
[[nodiscard]] bool kernel_path_supported(KernelPath path);

/// `path`, for a field's set_kernel_path: std::invalid_argument naming `component` when this
/// machine cannot run it, or when it is avx512 and the component's loops have no eight-lane path
/// (`has_avx512` false).
[[nodiscard]] KernelPath checked_kernel_path(KernelPath path, const char* component, bool has_avx512);

/// "scalar", "avx" or "avx512".
[[nodiscard]] const char* to_string(KernelPath path);

}  // namespace penalty
