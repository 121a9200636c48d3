// TetrahedronFEMForceField's force and product on TBB's threads (src/mechanics/fem.cpp, through
// LinearElementForceField::scatter_in_order): f, df, the energy and the frames the product reads
// are the bits of one thread, for every method, on every kernel path this CPU runs, for elements
// numbered in space or shuffled, and after the elements change.
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/grid_meshes.hpp"

#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/sanitizer.hpp"

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
            for (const int threads : test::thread_counts_to_compare({2, 3, 8})) {
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
            for (const int threads : test::thread_counts_to_compare({2, 8})) {
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

// init on TBB's threads (LinearElementForceField::init_from, then the lane blocks of
// TetrahedronFEMForceField::init_large): each element's K^e, and the force and product that read
// the lanes (on one thread), the bits of one thread's init, for every method and kernel path;
// with degenerate elements, the error raised names the first of them in element order.
TEST(TetrahedronFemConcurrent, InitOnThreadsIsTheBitsOfOneThreadAndRaisesTheFirstElementsError) {
    const MeshTopology mesh = test::kuhn_tetrahedra(tetrahedron_grid());
    ASSERT_GE(mesh.tetrahedra().size(), detail::OrderedScatter::kMinElements);
    Vec3Object state;
    state.position = tetrahedron_grid().points();
    state.init();
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small, FemMethod::Polar, FemMethod::Svd})
        for (const KernelPath path : paths_here()) {
            SCOPED_TRACE(testing::Message() << "method " << static_cast<int>(method) << ", path " << to_string(path));
            std::vector<TetrahedronFEMForceField::ElementMatrix> one;
            ElementProducts one_products;
            for (const int threads : test::thread_counts_to_compare({1, 2, 8})) {
                TetrahedronFEMForceField fem(state, mesh, 3e4, 0.35, method);
                fem.set_kernel_path(path);
                tbb::task_arena(threads).execute([&] { fem.init(); });
                const auto& k = fem.element_stiffness();
                ASSERT_EQ(k.size(), mesh.tetrahedra().size());
                const ElementProducts products = run_tetrahedra(fem, state, 1);
                if (threads == 1) {
                    one = k;
                    one_products = products;
                    continue;
                }
                EXPECT_EQ(std::memcmp(k.data(), one.data(), k.size() * sizeof(k[0])), 0) << threads << " threads";
                EXPECT_TRUE(same_vectors_bits(products.force, one_products.force)) << threads << " threads";
                EXPECT_TRUE(same_vectors_bits(products.product, one_products.product)) << threads << " threads";
            }
        }
    // tetrahedra 7000 and 3000 flattened (a vertex repeated): "tetrahedron 3000", on any thread count
    std::vector<Tetrahedron> flattened = mesh.tetrahedra();
    for (const std::size_t e : {std::size_t{7000}, std::size_t{3000}}) flattened[e][3] = flattened[e][0];
    MeshTopology bad;
    bad.set_tetrahedra(flattened);
    for (const int threads : {1, 8}) {
        TetrahedronFEMForceField fem(state, bad, 3e4, 0.35, FemMethod::Large);
        std::string message;
        tbb::task_arena(threads).execute([&] {
            try {
                fem.init();
            } catch (const std::invalid_argument& e) {
                message = e.what();
            }
        });
        EXPECT_NE(message.find("tetrahedron 3000 is degenerate"), std::string::npos) << threads << ": " << message;
    }
}

}  // namespace
}  // namespace penalty
