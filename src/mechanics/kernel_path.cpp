#include "penalty/mechanics/kernel_path.hpp"

#include "penalty/core/avx_lanes.hpp"

namespace penalty {

bool kernel_path_supported(KernelPath path) {
    switch (path) {
    case KernelPath::scalar: return true;
    case KernelPath::avx:
#ifdef PENALTY_HAS_AVX_LANES
        // libgcc's check includes the OS's support of the YMM state (XGETBV)
        return __builtin_cpu_supports("avx");
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

const char* to_string(KernelPath path) { return path == KernelPath::avx ? "avx" : "scalar"; }

}  // namespace penalty
