// TetrahedronFEMForceField's method-large force and product on TBB's threads
// (src/mechanics/tetrahedron_fem_concurrent.cpp): f, df, the energy and the frames the product
// reads are the bits of one thread, on every kernel path this CPU runs, for elements numbered in
// space or shuffled, and after the elements change.
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/grid_meshes.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace penalty {
namespace {

/// 13 × 12 × 9 cells, 8 424 tetrahedra: above detail::OrderedScatter::kMinElements.
const RegularGridTopology& grid() {
    static const RegularGridTopology g({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    return g;
}

struct Outcome {
    std::vector<Vec3> force, product;
    double energy = 0.0;
    std::size_t chunks = 0, deferred = 0;
};

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

/// addForce at a perturbed x, then addDForce of a random dx onto a random df, in an arena of
/// `threads` threads.
Outcome run(TetrahedronFEMForceField& fem, Vec3Object& state, int threads) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vec3> x = state.rest_position;
    for (Vec3& p : x) p += 0.02 * Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> dx(x.size()), v(x.size(), Vec3::Zero());
    for (Vec3& d : dx) d = Vec3(u(rng), u(rng), u(rng));
    Outcome out;
    out.force.assign(x.size(), Vec3::Zero());
    out.product.resize(x.size());
    for (Vec3& d : out.product) d = Vec3(u(rng), u(rng), u(rng));
    tbb::task_arena arena(threads);
    arena.execute([&] {
        fem.add_force(out.force, x, v);
        fem.add_dforce(out.product, dx, -0.37, 0.0);
    });
    out.energy = fem.potential_energy();
    out.chunks = fem.product_scatter().chunk_count();
    out.deferred = fem.product_scatter().deferred_terms();
    return out;
}

std::vector<KernelPath> paths_here() {
    std::vector<KernelPath> paths;
    for (const KernelPath p : {KernelPath::scalar, KernelPath::avx, KernelPath::avx512})
        if (kernel_path_supported(p)) paths.push_back(p);
    return paths;
}

TEST(TetrahedronFemConcurrent, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    const MeshTopology spatial = test::kuhn_tetrahedra(grid());
    std::vector<Tetrahedron> shuffled = spatial.tetrahedra();
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
    MeshTopology random_order;
    random_order.set_tetrahedra(shuffled);
    ASSERT_GE(spatial.tetrahedra().size(), detail::OrderedScatter::kMinElements);
    for (const MeshTopology* mesh : {&spatial, static_cast<const MeshTopology*>(&random_order)})
        for (const KernelPath path : paths_here()) {
            Vec3Object state;
            state.position = grid().points();
            state.init();
            TetrahedronFEMForceField fem(state, *mesh, 3e4, 0.35, FemMethod::Large);
            fem.set_kernel_path(path);
            fem.init();
            const Outcome one = run(fem, state, 1);
            EXPECT_EQ(one.chunks, 0U);  // one thread: the loop itself
            EXPECT_GT(one.energy, 0.0);
            for (const int threads : {2, 3, 8}) {
                const Outcome many = run(fem, state, threads);
                const std::string where = std::string(to_string(path)) + ", " + std::to_string(threads) + " threads" +
                                          (mesh == &spatial ? "" : ", shuffled");
                const std::size_t chunks =
                    std::min(detail::OrderedScatter::kChunksPerThread * std::size_t(threads),
                             mesh->tetrahedra().size() / detail::OrderedScatter::kMinElementsPerChunk);
                EXPECT_GT(chunks, 1U);
                EXPECT_EQ(many.chunks, chunks) << where;
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_TRUE(same_bits(many.force, one.force)) << where;
                EXPECT_TRUE(same_bits(many.product, one.product)) << where;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
            }
        }
}

TEST(TetrahedronFemConcurrent, NewElementsMakeTheSplitAgain) {
    // the same count of elements in another order: a split kept from before would mark the
    // wrong terms
    const MeshTopology spatial = test::kuhn_tetrahedra(grid());
    Vec3Object state;
    state.position = grid().points();
    state.init();
    TetrahedronFEMForceField fem(state, spatial, 3e4, 0.35, FemMethod::Large);
    fem.init();
    const Outcome before = run(fem, state, 2);
    ASSERT_EQ(before.chunks, 4U);
    std::vector<Tetrahedron> reversed = spatial.tetrahedra();
    std::reverse(reversed.begin(), reversed.end());
    fem.set_elements(reversed);
    fem.init();
    const Outcome many = run(fem, state, 2);
    const Outcome one = run(fem, state, 1);
    EXPECT_TRUE(same_bits(many.force, one.force));
    EXPECT_TRUE(same_bits(many.product, one.product));
    EXPECT_FALSE(same_bits(one.product, before.product));  // the order of the sums changed
}

TEST(TetrahedronFemConcurrent, FewElementsOrOtherMethodsRunOnOneThread) {
    const RegularGridTopology small({4, 4, 4}, Vec3::Zero(), Vec3::Ones());
    const MeshTopology mesh = test::kuhn_tetrahedra(small);
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small}) {
        Vec3Object state;
        state.position = small.points();
        state.init();
        TetrahedronFEMForceField fem(state, mesh, 3e4, 0.35, method);
        fem.init();
        EXPECT_EQ(run(fem, state, 4).chunks, 0U);
    }
    const MeshTopology large = test::kuhn_tetrahedra(grid());
    Vec3Object state;
    state.position = grid().points();
    state.init();
    TetrahedronFEMForceField small_method(state, large, 3e4, 0.35, FemMethod::Small);
    small_method.init();
    EXPECT_EQ(run(small_method, state, 4).chunks, 0U);
}

}  // namespace
}  // namespace penalty
