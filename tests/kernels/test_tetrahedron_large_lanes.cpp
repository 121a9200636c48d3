// The corotational tetrahedra's lane kernels (kernels/mechanics/tetrahedron_large_lanes.cpp) against
// their scalar loops: force and product, the same bits, on random tetrahedra with degenerate ones.
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

TEST(VectorKernels, CorotationalTetrahedronForceAndProductAreBitwiseTheScalarLoops) {
    if (!avx_available()) GTEST_SKIP() << "this CPU has no AVX: only the scalar path runs";
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> u(-1, 1);
    int compared = 0, changed = 0, changed_forces = 0;
    // avx512 (eight lanes, add_dforce only) where this CPU has AVX-512F; its blocks are filled at
    // init, or by set_kernel_path after init (count % 2 == 1), from the rotations of that moment
    const bool wide_available = kernel_path_supported(KernelPath::avx512);
    int compared_wide = 0;
    for (const std::size_t count : {std::size_t{1}, std::size_t{2}, std::size_t{3}, std::size_t{4}, std::size_t{5},
                                    std::size_t{6}, std::size_t{8}, std::size_t{9}, std::size_t{17}, std::size_t{57}}) {
        // a cloud of points, each element on four distinct points with a clear rest volume
        Vec3Object s;
        const std::size_t points = 12;
        for (std::size_t i = 0; i < points; ++i) s.position.emplace_back(u(rng), u(rng), u(rng));
        s.init();
        std::vector<Tetrahedron> tetrahedra;
        while (tetrahedra.size() < count) {
            Tetrahedron t{};
            for (auto& v : t) v = static_cast<PointId>(rng() % points);
            const auto& x = s.rest_position;
            const auto p = [&](int k) { return x[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])]; };
            if (std::abs((p(1) - p(0)).cross(p(2) - p(0)).dot(p(3) - p(0))) < 0.05) continue;
            tetrahedra.push_back(t);
        }
        MeshTopology topo;
        topo.set_tetrahedra(tetrahedra);
        TetrahedronFEMForceField scalar(s, topo, 1e4, 0.3, FemMethod::Large);
        TetrahedronFEMForceField vector(s, topo, 1e4, 0.3, FemMethod::Large);
        TetrahedronFEMForceField wide(s, topo, 1e4, 0.3, FemMethod::Large);
        scalar.set_kernel_path(KernelPath::scalar);
        vector.set_kernel_path(KernelPath::avx);
        wide.set_kernel_path(count % 2 == 1 ? KernelPath::avx
                                            : (wide_available ? KernelPath::avx512 : KernelPath::avx));
        scalar.init();
        vector.init();
        wide.init();
        for (int configuration = 0; configuration < 3; ++configuration) {
            // deformed and turned; the third time collapsed (coincident vertices: degenerate frames)
            for (std::size_t i = 0; i < points; ++i)
                s.position[i] = s.rest_position[i] + 0.3 * Vec3(u(rng), u(rng), u(rng));
            if (configuration == 2) {
                s.position[1] = s.position[0];
                s.position[3] = s.position[2];
                s.position[5] = Vec3::Zero();
            }
            // add_force: f and the energy bit for bit (the vector path forms R, δ and F in lanes)
            for (auto& f : s.force) f = Vec3(product_entry(rng), product_entry(rng), product_entry(rng));
            const std::vector<Vec3> force_before(s.force.begin(), s.force.end());
            scalar.accumulate_force();
            const std::vector<Vec3> expected_force(s.force.begin(), s.force.end());
            std::copy(force_before.begin(), force_before.end(), s.force.begin());
            vector.accumulate_force();
            expect_same_bits(expected_force, {s.force.begin(), s.force.end()},
                             "add_force, tetrahedra " + std::to_string(count));
            EXPECT_EQ(scalar.potential_energy(), vector.potential_energy());
            std::copy(force_before.begin(), force_before.end(), s.force.begin());
            wide.accumulate_force();
            expect_same_bits(expected_force, {s.force.begin(), s.force.end()},
                             "add_force (wide), tetrahedra " + std::to_string(count));
            if (configuration == 0 && count % 2 == 1 && wide_available) wide.set_kernel_path(KernelPath::avx512);
            changed_forces += changed_dofs(force_before, expected_force);
            for (const double k : {-0.0123, 1.0}) {
                fill_products(s, rng);
                const std::vector<Vec3> df(s.df.begin(), s.df.end());
                scalar.accumulate_dforce(k, 0.0);
                const std::vector<Vec3> expected(s.df.begin(), s.df.end());
                changed += changed_dofs(df, expected);
                std::copy(df.begin(), df.end(), s.df.begin());
                vector.accumulate_dforce(k, 0.0);
                expect_same_bits(expected, {s.df.begin(), s.df.end()}, "tetrahedra " + std::to_string(count));
                std::copy(df.begin(), df.end(), s.df.begin());
                wide.accumulate_dforce(k, 0.0);
                expect_same_bits(expected, {s.df.begin(), s.df.end()},
                                 std::string(to_string(wide.kernel_path())) + ", tetrahedra " + std::to_string(count));
                compared_wide += wide.kernel_path() == KernelPath::avx512 ? 1 : 0;
                ++compared;
            }
        }
    }
    EXPECT_EQ(compared, 10 * 3 * 2);
    EXPECT_EQ(compared_wide, wide_available ? 10 * 3 * 2 : 0);
    EXPECT_GT(changed, 200);
    EXPECT_GT(changed_forces, 100);
}

}  // namespace
}  // namespace penalty
