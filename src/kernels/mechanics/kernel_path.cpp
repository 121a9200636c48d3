#include "penalty/mechanics/kernel_path.hpp"

#include "kernels/lanes.hpp"
#include "penalty/core/error.hpp"

namespace penalty {

bool kernel_path_supported(KernelPath path) {
    switch (path) {
        case KernelPath::scalar:
            return true;
        case KernelPath::avx:
#ifdef PENALTY_HAS_AVX_LANES
            // libgcc's check includes the OS's support of the YMM state (XGETBV)
            return __builtin_cpu_supports("avx");
#else
            return false;
#endif
        case KernelPath::avx512:
#ifdef PENALTY_HAS_AVX_LANES
            // AVX-512F's ZMM state is checked by libgcc as well
            return __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx512f");
#else
            return false;
#endif
    }
    return false;
}

KernelPath best_kernel_path() {
    static const KernelPath best = kernel_path_supported(KernelPath::avx) ? KernelPath::avx : KernelPath::scalar;
    return best;
}

KernelPath best_fem_kernel_path() {
#ifdef PENALTY_HAS_AVX_LANES
    static const KernelPath best = kernel_path_supported(KernelPath::avx512) && __builtin_cpu_is("intel")
                                       ? KernelPath::avx512
                                       : best_kernel_path();
    return best;
#else
    return best_kernel_path();
#endif
}

KernelPath checked_kernel_path(KernelPath path, const char* component, bool has_avx512) {
    if (path == KernelPath::avx512 && !has_avx512)
        throw_invalid_argument(component, ": kernel path avx512 is the corotational tetrahedra's only; ", component,
                               " runs scalar or avx");
    if (!kernel_path_supported(path))
        throw_invalid_argument(component, ": kernel path ", to_string(path), " is not supported by this CPU");
    return path;
}

const char* to_string(KernelPath path) {
    switch (path) {
        case KernelPath::scalar:
            return "scalar";
        case KernelPath::avx:
            return "avx";
        case KernelPath::avx512:
            return "avx512";
    }
    return "unknown";
}

}  // namespace penalty
