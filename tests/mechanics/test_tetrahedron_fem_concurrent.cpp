// TetrahedronFEMForceField's force and product on TBB's threads (src/mechanics/fem.cpp, through
// LinearElementForceField::scatter_in_order): f, df, the energy and the frames the product reads
// are the bits of one thread, for every method, on every kernel path this CPU runs, for elements
// numbered in space or shuffled, and after the elements change.
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/grid_meshes.hpp"

#include "penalty_test/element_products_on_threads.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace penalty {
namespace {

/// 13 × 12 × 9 cells, 8 424 tetrahedra: above detail::OrderedScatter::kMinElements.
const RegularGridTopology& tetrahedron_grid() {
    static const RegularGridTopology g({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    return g;
}

using test::ElementProducts;
using test::same_vectors_bits;

ElementProducts run_tetrahedra(TetrahedronFEMForceField& fem, const Vec3Object& state, int threads) {
    return test::element_products_on_threads(fem, state, threads, 0.02, -0.37);
}

std::vector<KernelPath> paths_here() {
    std::vector<KernelPath> paths;
    for (const KernelPath p : {KernelPath::scalar, KernelPath::avx, KernelPath::avx512})
        if (kernel_path_supported(p)) paths.push_back(p);
    return paths;
}

TEST(TetrahedronFemConcurrent, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    const MeshTopology spatial = test::kuhn_tetrahedra(tetrahedron_grid());
    std::vector<Tetrahedron> shuffled = spatial.tetrahedra();
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(5));
    MeshTopology random_order;
    random_order.set_tetrahedra(shuffled);
    ASSERT_GE(spatial.tetrahedra().size(), detail::OrderedScatter::kMinElements);
    for (const MeshTopology* mesh : {&spatial, static_cast<const MeshTopology*>(&random_order)})
        for (const KernelPath path : paths_here()) {
            Vec3Object state;
            state.position = tetrahedron_grid().points();
            state.init();
            TetrahedronFEMForceField fem(state, *mesh, 3e4, 0.35, FemMethod::Large);
            fem.set_kernel_path(path);
            fem.init();
            const ElementProducts one = run_tetrahedra(fem, state, 1);
            EXPECT_EQ(one.chunks, 0U);  // one thread: the loop itself
            EXPECT_GT(one.energy, 0.0);
            for (const int threads : {2, 3, 8}) {
                const ElementProducts many = run_tetrahedra(fem, state, threads);
                const std::string where = std::string(to_string(path)) + ", " + std::to_string(threads) + " threads" +
                                          (mesh == &spatial ? "" : ", shuffled");
                const std::size_t chunks =
                    std::min(detail::OrderedScatter::kChunksPerThread * std::size_t(threads),
                             mesh->tetrahedra().size() / detail::OrderedScatter::kMinElementsPerChunk);
                EXPECT_GT(chunks, 1U);
                EXPECT_EQ(many.chunks, chunks) << where;
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_TRUE(same_vectors_bits(many.force, one.force)) << where;
                EXPECT_TRUE(same_vectors_bits(many.product, one.product)) << where;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
            }
        }
}

TEST(TetrahedronFemConcurrent, NewElementsMakeTheSplitAgain) {
    // the same count of elements in another order: a split kept from before would mark the
    // wrong terms
    const MeshTopology spatial = test::kuhn_tetrahedra(tetrahedron_grid());
    Vec3Object state;
    state.position = tetrahedron_grid().points();
    state.init();
    TetrahedronFEMForceField fem(state, spatial, 3e4, 0.35, FemMethod::Large);
    fem.init();
    const ElementProducts before = run_tetrahedra(fem, state, 2);
    ASSERT_EQ(before.chunks, 4U);
    std::vector<Tetrahedron> reversed = spatial.tetrahedra();
    std::reverse(reversed.begin(), reversed.end());
    fem.set_elements(reversed);
    fem.init();
    const ElementProducts many = run_tetrahedra(fem, state, 2);
    const ElementProducts one = run_tetrahedra(fem, state, 1);
    EXPECT_TRUE(same_vectors_bits(many.force, one.force));
    EXPECT_TRUE(same_vectors_bits(many.product, one.product));
    EXPECT_FALSE(same_vectors_bits(one.product, before.product));  // the order of the sums changed
}

TEST(TetrahedronFemConcurrent, EveryOtherMethodOnThreadsGivesTheBitsOfOneThread) {
    // small (its own product), polar and svd (their frames element by element, large's product)
    const MeshTopology spatial = test::kuhn_tetrahedra(tetrahedron_grid());
    for (const FemMethod method : {FemMethod::Small, FemMethod::Polar, FemMethod::Svd})
        for (const KernelPath path : paths_here()) {
            Vec3Object state;
            state.position = tetrahedron_grid().points();
            state.init();
            TetrahedronFEMForceField fem(state, spatial, 3e4, 0.35, method);
            fem.set_kernel_path(path);
            fem.init();
            const ElementProducts one = run_tetrahedra(fem, state, 1);
            EXPECT_EQ(one.chunks, 0U);
            EXPECT_GT(one.energy, 0.0);
            for (const int threads : {2, 8}) {
                const ElementProducts many = run_tetrahedra(fem, state, threads);
                const std::string where = std::string(to_string(path)) + ", method " +
                                          std::to_string(static_cast<int>(method)) + ", " + std::to_string(threads) +
                                          " threads";
                EXPECT_GT(many.chunks, 1U) << where;
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_TRUE(same_vectors_bits(many.force, one.force)) << where;
                EXPECT_TRUE(same_vectors_bits(many.product, one.product)) << where;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
            }
        }
}

TEST(TetrahedronFemConcurrent, FewElementsRunOnOneThread) {
    const RegularGridTopology small({4, 4, 4}, Vec3::Zero(), Vec3::Ones());
    const MeshTopology mesh = test::kuhn_tetrahedra(small);
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small, FemMethod::Polar, FemMethod::Svd}) {
        Vec3Object state;
        state.position = small.points();
        state.init();
        TetrahedronFEMForceField fem(state, mesh, 3e4, 0.35, method);
        fem.init();
        EXPECT_EQ(run_tetrahedra(fem, state, 4).chunks, 0U);
    }
}

}  // namespace
}  // namespace penalty
