#pragma once
/// @file
/// One force and one product of an element force field in an arena of a given thread count, for
/// the tests that compare thread counts to the bit (OrderedScatter's users).

#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"

#include <tbb/task_arena.h>

#include <cstring>
#include <random>
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
/// random dx with `k_factor` onto a random df, in an arena of `threads` threads (the random draws
/// the same for every call).
template <class Field>
ElementProducts element_products_on_threads(Field& field, const Vec3Object& state, int threads, double perturbation,
                                            double k_factor) {
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
        field.add_dforce(out.product, dx, k_factor, 0.0);
    });
    out.energy = field.potential_energy();
    out.chunks = field.product_scatter().chunk_count();
    out.deferred = field.product_scatter().deferred_terms();
    return out;
}

}  // namespace penalty::test
