// HexahedronFEMForceField (src/mechanics/hexahedron_fem.cpp) on TBB's threads: from
// OrderedScatter::kMinElements elements its force and product split into chunks of consecutive
// elements, f, df and the energy the bits of one thread for methods small, large and polar, with
// the hexahedra in the grid's order or shuffled. (Its SOFA fidelity and derivatives: test_fem.cpp,
// test_fem_polar.cpp.)
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/sanitizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace penalty {
namespace {

/// 21 × 20 × 20 cells: 8 400 hexahedra.
const RegularGridTopology& hexahedron_grid() {
    static const RegularGridTopology g({22, 21, 21}, Vec3::Zero(), Vec3(2.1, 2.0, 2.0));
    return g;
}

using test::ElementProducts;
using test::same_vectors_bits;

ElementProducts run_hexahedra(HexahedronFEMForceField& fem, const Vec3Object& state, int threads) {
    return test::element_products_on_threads(fem, state, threads, 0.03, -0.61);
}

TEST(HexahedronFem, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    const MeshTopology& in_order = hexahedron_grid().mesh();
    ASSERT_GE(in_order.hexahedra().size(), detail::OrderedScatter::kMinElements);
    std::vector<Hexahedron> shuffled = in_order.hexahedra();
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(9));
    MeshTopology random_order;
    random_order.set_hexahedra(shuffled);
    for (const MeshTopology* mesh : {&in_order, static_cast<const MeshTopology*>(&random_order)})
        for (const FemMethod method : {FemMethod::Small, FemMethod::Large, FemMethod::Polar}) {
            Vec3Object state;
            state.position = hexahedron_grid().points();
            state.init();
            HexahedronFEMForceField fem(state, *mesh, 2e4, 0.3, method);
            fem.init();
            const ElementProducts one = run_hexahedra(fem, state, 1);
            EXPECT_EQ(one.chunks, 0U);
            EXPECT_GT(one.energy, 0.0);
            for (const int threads : test::thread_counts_to_compare({2, 8})) {
                const ElementProducts many = run_hexahedra(fem, state, threads);
                const std::string where = std::to_string(int(method)) + ", " + std::to_string(threads) + " threads" +
                                          (mesh == &in_order ? "" : ", shuffled");
                EXPECT_EQ(many.chunks, detail::OrderedScatter::chunks_for(mesh->hexahedra().size(), threads)) << where;
                EXPECT_GT(many.chunks, 1U) << where;
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_TRUE(same_vectors_bits(many.force, one.force)) << where;
                EXPECT_TRUE(same_vectors_bits(many.product, one.product)) << where;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
            }
        }
}

// The element products' K·d on the scalar and AVX paths (kernels/mechanics/hexahedron_stiffness):
// force, product and energy the same bits for each method; avx512 (eight lanes) is refused.
TEST(HexahedronFem, KernelPathsGiveTheSameBits) {
    const RegularGridTopology grid({5, 4, 4}, Vec3::Zero(), Vec3(0.4, 0.3, 0.3));
    for (const FemMethod method : {FemMethod::Small, FemMethod::Large, FemMethod::Polar}) {
        Vec3Object state;
        state.position = grid.points();
        state.init();
        HexahedronFEMForceField fem(state, grid.mesh(), 2e4, 0.3, method);
        fem.init();
        EXPECT_EQ(fem.kernel_path(), best_kernel_path());
        EXPECT_THROW(fem.set_kernel_path(KernelPath::avx512), std::invalid_argument);
        test::expect_kernel_paths_give_the_same_bits(fem, state, "method " + std::to_string(int(method)));
    }
}

}  // namespace
}  // namespace penalty
