#pragma once
/// @file
/// One force and one product of an element force field in an arena of a given thread count, for
/// the tests that compare thread counts to the bit (OrderedScatter's users), and a sheet of
/// triangles large enough to run on threads.

#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"

#include "penalty_test/grid_meshes.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace penalty::test {

/// What add_force and add_dforce gave, and how the field split them.
struct ElementProducts {
    std::vector<Vec3> force, product;
    double energy = 0.0;
    std::size_t chunks = 0, deferred = 0;
};

inline bool same_vectors_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

/// add_force at x = rest + `perturbation`·(random in [−1, 1]³) onto zero, then add_dforce of a
/// random dx with `k_factor` onto a random df (none when !with_product), in an arena of `threads`
/// threads (the random draws the same for every call).
template <class Field>
ElementProducts element_products_on_threads(Field& field, const Vec3Object& state, int threads, double perturbation,
                                            double k_factor, bool with_product = true) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vec3> x = state.rest_position;
    for (Vec3& p : x) p += perturbation * Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> dx(x.size()), v(x.size(), Vec3::Zero());
    for (Vec3& d : dx) d = Vec3(u(rng), u(rng), u(rng));
    ElementProducts out;
    out.force.assign(x.size(), Vec3::Zero());
    out.product.resize(x.size());
    for (Vec3& d : out.product) d = Vec3(u(rng), u(rng), u(rng));
    tbb::task_arena arena(threads);
    arena.execute([&] {
        field.add_force(out.force, x, v);
        if (with_product) field.add_dforce(out.product, dx, k_factor, 0.0);
    });
    out.energy = field.potential_energy();
    out.chunks = field.product_scatter().chunk_count();
    out.deferred = field.product_scatter().deferred_terms();
    return out;
}

/// add_force and add_dforce of `field` at 2, 3 and 8 threads split into chunks, with deferred
/// terms, and the bits of one thread (force, product, energy); `what` names the case.
template <class Field>
void expect_threads_give_one_threads_bits(Field& field, const Vec3Object& state, const std::string& what) {
    const ElementProducts one = element_products_on_threads(field, state, 1, 0.01, -0.37);
    EXPECT_EQ(one.chunks, 0U) << what;
    for (const int threads : {2, 3, 8}) {
        const ElementProducts many = element_products_on_threads(field, state, threads, 0.01, -0.37);
        const std::string where = what + ", " + std::to_string(threads) + " threads";
        EXPECT_GT(many.chunks, 1U) << where;
        EXPECT_GT(many.deferred, 0U) << where;
        EXPECT_TRUE(same_vectors_bits(many.force, one.force)) << where;
        EXPECT_TRUE(same_vectors_bits(many.product, one.product)) << where;
        EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
    }
}

/// The product follows each force evaluation (data a kernel packs is made again): `field`'s
/// product after a force at one perturbation, a product, and a force at another is the bits of a
/// `fresh` field's after the same two forces with no product between (a field may keep history
/// from one force to the next), and not the first product; `what` names the case.
template <class Field>
void expect_product_follows_each_force_evaluation(Field& field, Field& fresh, const Vec3Object& state,
                                                  const std::string& what) {
    const ElementProducts first = element_products_on_threads(field, state, 1, 0.01, -0.37);
    const ElementProducts second = element_products_on_threads(field, state, 1, 0.05, -0.37);
    (void)element_products_on_threads(fresh, state, 1, 0.01, -0.37, /*with_product=*/false);
    const ElementProducts expected = element_products_on_threads(fresh, state, 1, 0.05, -0.37);
    EXPECT_FALSE(same_vectors_bits(second.product, first.product)) << what;
    EXPECT_TRUE(same_vectors_bits(second.product, expected.product)) << what;
}

/// add_force and add_dforce of `field` (one thread) on each kernel path this machine runs, the
/// bits of the scalar path's (force, product, energy), and not all zero; `what` names the case.
template <class Field>
void expect_kernel_paths_give_the_same_bits(Field& field, const Vec3Object& state, const std::string& what) {
    field.set_kernel_path(KernelPath::scalar);
    const ElementProducts scalar = element_products_on_threads(field, state, 1, 0.03, -0.61);
    EXPECT_GT(scalar.energy, 0.0) << what;
    EXPECT_TRUE(std::any_of(scalar.force.begin(), scalar.force.end(), [](const Vec3& f) { return f != Vec3::Zero(); }))
        << what;
    if (!kernel_path_supported(KernelPath::avx)) GTEST_SKIP() << "this CPU has no AVX";
    field.set_kernel_path(KernelPath::avx);
    const ElementProducts avx = element_products_on_threads(field, state, 1, 0.03, -0.61);
    EXPECT_TRUE(same_vectors_bits(avx.force, scalar.force)) << what;
    EXPECT_TRUE(same_vectors_bits(avx.product, scalar.product)) << what;
    EXPECT_EQ(std::memcmp(&avx.energy, &scalar.energy, sizeof(double)), 0) << what;
}

/// A 64 × 64-quad sheet over x, y ∈ [−1, 1], 8 192 triangles (OrderedScatter::kMinElements),
/// curved (z = 0.1·x²), in the grid's order or shuffled.
struct TriangleSheet {
    std::vector<Vec3> points;
    MeshTopology topology;
    explicit TriangleSheet(bool shuffle) {
        grid_mesh(
            64, 1.0, [](const GridVertex& v) { return 0.1 * v.x * v.x; }, points, topology);
        for (Vec3& p : points) std::swap(p[1], p[2]);  // (the small-strain TriangleFEM reads x, y)
        if (shuffle) {
            std::vector<Triangle> triangles = topology.triangles();
            std::shuffle(triangles.begin(), triangles.end(), std::mt19937(12));
            topology.set_triangles(std::move(triangles));
        }
    }
};

/// A triangle field (Field(state, topology, parameters)) on the shuffled sheet, one thread: the
/// field starts on best_kernel_path() and refuses avx512; its scalar and AVX paths give the same
/// force, product and energy; and on every path its product follows each force evaluation (the
/// packed data made again). `what` names the field.
template <class Field, class Parameters>
void expect_sheet_kernel_paths(const Parameters& parameters, const std::string& what) {
    const TriangleSheet sheet(/*shuffle=*/true);
    Vec3Object state;
    state.position = sheet.points;
    state.init();
    std::vector<KernelPath> paths = {KernelPath::scalar};
    if (kernel_path_supported(KernelPath::avx)) paths.push_back(KernelPath::avx);
    for (const KernelPath path : paths) {
        Field field(state, sheet.topology, parameters);
        Field fresh(state, sheet.topology, parameters);
        field.init();
        fresh.init();
        EXPECT_EQ(field.kernel_path(), best_kernel_path()) << what;
        EXPECT_THROW(field.set_kernel_path(KernelPath::avx512), std::invalid_argument) << what;
        field.set_kernel_path(path);
        expect_product_follows_each_force_evaluation(field, fresh, state, what + ", " + to_string(path));
    }
    Field field(state, sheet.topology, parameters);
    field.init();
    expect_kernel_paths_give_the_same_bits(field, state, what);
}

}  // namespace penalty::test
