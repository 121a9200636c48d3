/// TetrahedronFEMForceField's method-large force and product on TBB's threads, with the bits of
/// one thread:
/// chunks of consecutive elements as tasks, each vertex's terms subtracted in element order
/// (detail::OrderedScatter), which is the order of the one-thread loop
/// (accumulateForceLarge's f[vertex] += Rᵀ·F_k and applyStiffnessCorotational's df[vertex] −= Rᵀ·F_k,
/// element by element).
#include "penalty/mechanics/fem.hpp"

#include "kernels/mechanics/tetrahedron_large.hpp"

namespace penalty {

void TetrahedronFEMForceField::concurrent_large_dforce(std::span<Vec3> df, std::span<const Vec3> dx,
                                                       double k_factor) const {
    // the chunks' first elements on a lane block's boundary (eight lanes, four dividing it)
    product_scatter_.prepare(std::span<const Element>(elements_), 8);
    const detail::DeferredTerms deferred = product_scatter_.deferred();
    product_scatter_.for_each_chunk(
        [&](std::size_t first, std::size_t end) { large_dforce(first, end, df, dx, k_factor, deferred); });
    product_scatter_.subtract_deferred(df);
}

void TetrahedronFEMForceField::concurrent_large_force(std::span<Vec3> f, std::span<const Vec3> x) {
    product_scatter_.prepare(std::span<const Element>(elements_), 8);
    const detail::DeferredTerms deferred = product_scatter_.deferred();
    element_energies_.resize(elements_.size());
    product_scatter_.for_each_chunk(
        [&](std::size_t first, std::size_t end) { large_force(first, end, f, x, deferred, element_energies_.data()); });
    product_scatter_.add_deferred(f);
    energy_ = 0.0;  // ½ δᵀF of each element, in element order
    for (const double e : element_energies_) energy_ += e;
}

}  // namespace penalty
