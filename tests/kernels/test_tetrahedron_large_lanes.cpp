// The corotational tetrahedra's lane kernels (kernels/mechanics/tetrahedron_large_lanes.cpp) against
// their scalar loops: force and product, the same bits, on random tetrahedra with degenerate ones;
// the other readers of the one lane layout (stiffness assembly, plasticity, a change of kernel
// path) on every path this CPU runs.
#include "kernel_cases.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"
#include "penalty/mechanics/spring_force_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
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

/// The kernel paths this CPU runs.
std::vector<KernelPath> runnable_paths() {
    std::vector<KernelPath> paths;
    for (const KernelPath path : {KernelPath::scalar, KernelPath::avx, KernelPath::avx512})
        if (kernel_path_supported(path)) paths.push_back(path);
    return paths;
}

/// A 3 × 1 × 1 grid's tetrahedra (SOFA's split, 18 elements: full blocks and a partial one of
/// either width) on a deformed and turned state.
struct GridCase {
    Vec3Object s;
    MeshTopology topo;
    explicit GridCase(std::mt19937& rng) {
        const RegularGridTopology grid({4, 2, 2}, Vec3(0, 0, 0), Vec3(1, 0.4, 0.3));
        s.position = grid.points();
        s.init();
        topo.set_tetrahedra(tetrahedra_from_hexahedra(grid.mesh().hexahedra(), 3, 1));
        std::uniform_real_distribution<double> u(-0.05, 0.05);
        const Mat3 turn = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
        for (auto& p : s.position) p = turn * p + Vec3(u(rng), u(rng), u(rng));
    }
};

TEST(VectorKernels, CorotationalTetrahedronStiffnessReadsEachPathsRotations) {
    // add_stiffness_triplets reads R from the lanes add_force wrote: the same bits on every path,
    // and −Rᵀ K^e R with the current frame (not the rest frame nor zero)
    std::mt19937 rng(5);
    GridCase c(rng);
    std::vector<TripletList> triplets;
    for (const KernelPath path : runnable_paths()) {
        TetrahedronFEMForceField fem(c.s, c.topo, 1e4, 0.3, FemMethod::Large);
        fem.set_kernel_path(path);
        fem.init();
        std::fill(c.s.force.begin(), c.s.force.end(), Vec3::Zero());
        fem.accumulate_force();
        TripletList t;
        fem.add_stiffness_triplets(t, 0, 1.0);
        ASSERT_EQ(t.size(), fem.tetrahedra().size() * 144);
        // element 12's first block: −R(current)ᵀ K^e₀₀ R(current), R from the edges of the moved state
        std::array<Vec3, 4> p;
        for (std::size_t k = 0; k < 4; ++k) p[k] = c.s.position[std::size_t(fem.tetrahedra()[12][k])];
        const Mat3 r = tetrahedron_rotation(p, FemMethod::Large);
        const Mat3 expected = -r.transpose() * fem.element_stiffness()[12].block<3, 3>(0, 0) * r;
        for (std::size_t i = 0; i < 9; ++i)
            EXPECT_NEAR(t[12 * 144 + i].value(), expected(Index(i / 3), Index(i % 3)), 1e-9 * expected.norm())
                << to_string(path);
        triplets.push_back(std::move(t));
    }
    for (std::size_t p = 1; p < triplets.size(); ++p)
        for (std::size_t i = 0; i < triplets[0].size(); ++i)
            EXPECT_EQ(0, std::memcmp(&triplets[0][i], &triplets[p][i], sizeof(Triplet))) << "path " << p << ", " << i;
}

TEST(VectorKernels, CorotationalTetrahedronPlasticityAndPathChangesAreBitwiseTheScalarLoops) {
    // plasticity's scalar force writes the R the vector products read; a change of kernel path
    // moves the lanes (R of the last force included) to the new width
    std::mt19937 rng(9);
    GridCase c(rng);
    const std::vector<KernelPath> paths = runnable_paths();
    std::vector<std::unique_ptr<TetrahedronFEMForceField>> fields;
    for (std::size_t i = 0; i < 2 * paths.size(); ++i) {
        auto& fem =
            *fields.emplace_back(std::make_unique<TetrahedronFEMForceField>(c.s, c.topo, 1e4, 0.3, FemMethod::Large));
        if (i >= paths.size()) fem.set_plasticity({.max_threshold = 0.1, .yield_threshold = 1e-4, .creep = 0.9});
        fem.set_kernel_path(paths[i % paths.size()]);
        fem.init();
    }
    int changed = 0;
    for (int round = 0; round < 4; ++round) {
        for (auto& p : c.s.position) p += Vec3(0.02, -0.01, 0.015) * double(round % 2 == 0 ? 1 : -1);
        fill_products(c.s, rng);
        const std::vector<Vec3> df_before(c.s.df.begin(), c.s.df.end());
        std::vector<Vec3> elastic_df;  // the plastic fields' product is elastic (SOFA's addDForce)
        for (std::size_t plastic = 0; plastic < 2; ++plastic) {
            std::vector<Vec3> expected_force, expected_df;
            for (std::size_t i = 0; i < paths.size(); ++i) {
                TetrahedronFEMForceField& fem = *fields[plastic * paths.size() + i];
                if (round == 2) fem.set_kernel_path(paths[(i + 1) % paths.size()]);  // another width
                std::fill(c.s.force.begin(), c.s.force.end(), Vec3::Zero());
                std::copy(df_before.begin(), df_before.end(), c.s.df.begin());
                fem.accumulate_force();
                fem.accumulate_dforce(-0.37, 0.0);
                const std::vector<Vec3> force(c.s.force.begin(), c.s.force.end()), df(c.s.df.begin(), c.s.df.end());
                if (i == 0) {
                    expected_force = force;
                    expected_df = df;
                    changed += changed_dofs(df_before, df);
                    if (plastic == 0) elastic_df = df;
                    else expect_same_bits(elastic_df, df, "plastic product, round " + std::to_string(round));
                    continue;
                }
                const std::string what = std::string(to_string(fem.kernel_path())) + (plastic ? ", plastic" : "") +
                                         ", round " + std::to_string(round);
                expect_same_bits(expected_force, force, "add_force, " + what);
                expect_same_bits(expected_df, df, "add_dforce, " + what);
            }
        }
    }
    EXPECT_GT(changed, 7 * int(c.s.position.size()));
    double plastic = 0.0;  // the plastic fields did creep
    for (const double v : fields[paths.size()]->plastic_strain(0)) plastic += v * v;
    EXPECT_GT(plastic, 1e-8);
}

}  // namespace
}  // namespace penalty
