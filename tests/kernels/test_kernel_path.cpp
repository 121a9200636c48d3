// The kernel paths (kernels/mechanics/kernel_path.cpp): reported, and an unsupported one refused.
#include "kernel_cases.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace penalty {
namespace {

using namespace test_kernel_cases;

TEST(VectorKernels, PathsAreReportedAndUnsupportedOnesRefused) {
    EXPECT_TRUE(kernel_path_supported(KernelPath::scalar));
    EXPECT_EQ(best_kernel_path(), avx_available() ? KernelPath::avx : KernelPath::scalar);
    EXPECT_STREQ(to_string(KernelPath::avx), "avx");
    EXPECT_STREQ(to_string(KernelPath::avx512), "avx512");
    // the FEM's default: eight lanes on Intel CPUs with AVX-512F only
#if defined(__x86_64__) && defined(__GNUC__)
    const bool intel_wide = kernel_path_supported(KernelPath::avx512) && __builtin_cpu_is("intel");
#else
    const bool intel_wide = false;
#endif
    EXPECT_EQ(best_fem_kernel_path(), intel_wide ? KernelPath::avx512 : best_kernel_path());
    Vec3Object s;
    s.position = {Vec3::Zero(), Vec3::UnitX()};
    s.init();
    SpringForceField springs(s);
    EXPECT_EQ(springs.kernel_path(), best_kernel_path());
    springs.set_kernel_path(KernelPath::scalar);
    EXPECT_EQ(springs.kernel_path(), KernelPath::scalar);
    if (!avx_available()) {
        EXPECT_THROW(springs.set_kernel_path(KernelPath::avx), std::invalid_argument);
    }
    EXPECT_THROW(springs.set_kernel_path(KernelPath::avx512), std::invalid_argument);  // the FEM's only
    EXPECT_EQ(springs.kernel_path(), KernelPath::scalar);
    Vec3Object body;
    body.position = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    body.init();
    MeshTopology topo;
    topo.set_tetrahedra({Tetrahedron{0, 1, 2, 3}});
    TetrahedronFEMForceField fem(body, topo, 1e4, 0.3, FemMethod::Large);
    EXPECT_EQ(fem.kernel_path(), best_fem_kernel_path());
    if (!kernel_path_supported(KernelPath::avx512)) {
        EXPECT_THROW(fem.set_kernel_path(KernelPath::avx512), std::invalid_argument);
    }
}

}  // namespace
}  // namespace penalty
