// HexahedronFEMForceField (src/mechanics/hexahedron_fem.cpp) on TBB's threads: from
// OrderedScatter::kMinElements elements its force and product split into chunks of consecutive
// elements, f, df and the energy the bits of one thread for methods small, large and polar, with
// the hexahedra in the grid's order or shuffled. (Its SOFA fidelity and derivatives: test_fem.cpp,
// test_fem_polar.cpp.)
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace penalty {
namespace {

/// 21 × 20 × 20 cells: 8 400 hexahedra.
const RegularGridTopology& grid() {
    static const RegularGridTopology g({22, 21, 21}, Vec3::Zero(), Vec3(2.1, 2.0, 2.0));
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

Outcome run(HexahedronFEMForceField& fem, const Vec3Object& state, int threads) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vec3> x = state.rest_position;
    for (Vec3& p : x) p += 0.03 * Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> dx(x.size()), v(x.size(), Vec3::Zero());
    for (Vec3& d : dx) d = Vec3(u(rng), u(rng), u(rng));
    Outcome out;
    out.force.assign(x.size(), Vec3::Zero());
    out.product.resize(x.size());
    for (Vec3& d : out.product) d = Vec3(u(rng), u(rng), u(rng));
    tbb::task_arena arena(threads);
    arena.execute([&] {
        fem.add_force(out.force, x, v);
        fem.add_dforce(out.product, dx, -0.61, 0.0);
    });
    out.energy = fem.potential_energy();
    out.chunks = fem.product_scatter().chunk_count();
    out.deferred = fem.product_scatter().deferred_terms();
    return out;
}

TEST(HexahedronFem, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    const MeshTopology& in_order = grid().mesh();
    ASSERT_GE(in_order.hexahedra().size(), detail::OrderedScatter::kMinElements);
    std::vector<Hexahedron> shuffled = in_order.hexahedra();
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(9));
    MeshTopology random_order;
    random_order.set_hexahedra(shuffled);
    for (const MeshTopology* mesh : {&in_order, static_cast<const MeshTopology*>(&random_order)})
        for (const FemMethod method : {FemMethod::Small, FemMethod::Large, FemMethod::Polar}) {
            Vec3Object state;
            state.position = grid().points();
            state.init();
            HexahedronFEMForceField fem(state, *mesh, 2e4, 0.3, method);
            fem.init();
            const Outcome one = run(fem, state, 1);
            EXPECT_EQ(one.chunks, 0U);
            EXPECT_GT(one.energy, 0.0);
            for (const int threads : {2, 8}) {
                const Outcome many = run(fem, state, threads);
                const std::string where = std::to_string(int(method)) + ", " + std::to_string(threads) +
                                          " threads" + (mesh == &in_order ? "" : ", shuffled");
                EXPECT_EQ(many.chunks, detail::OrderedScatter::chunks_for(mesh->hexahedra().size(), threads)) << where;
                EXPECT_GT(many.chunks, 1U) << where;
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_TRUE(same_bits(many.force, one.force)) << where;
                EXPECT_TRUE(same_bits(many.product, one.product)) << where;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
            }
        }
}

}  // namespace
}  // namespace penalty
