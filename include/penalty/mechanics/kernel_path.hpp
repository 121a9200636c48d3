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
};

/// KernelPath::avx when the build targets x86-64 and this CPU and OS support AVX, else scalar.
[[nodiscard]] KernelPath best_kernel_path();

/// Whether `path` can run on this machine (scalar always can).
[[nodiscard]] bool kernel_path_supported(KernelPath path);

/// "scalar" or "avx".
[[nodiscard]] const char* to_string(KernelPath path);

}  // namespace penalty
