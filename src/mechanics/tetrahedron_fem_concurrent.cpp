/// TetrahedronFEMForceField's method-large force and product on TBB's threads, with the bits of
/// one thread:
/// chunks of consecutive elements as tasks, each vertex's terms subtracted in element order
/// (detail::OrderedScatter), which is the order of the one-thread loop
/// (accumulateForceLarge's f[vertex] += Rᵀ·F_k and applyStiffnessCorotational's df[vertex] −= Rᵀ·F_k,
/// element by element).
#include "penalty/mechanics/fem.hpp"

#include "kernels/mechanics/tetrahedron_large.hpp"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace penalty {

std::size_t TetrahedronFEMForceField::product_chunks(int threads) const {
    if (method_ != FemMethod::Large || threads < 2 || elements_.size() < kMinElementsForConcurrentProduct) return 0;
    return std::min(kProductChunksPerThread * static_cast<std::size_t>(threads),
                    elements_.size() / kMinElementsPerProductChunk);
}

namespace {
/// chunk_pass(first, end) for each chunk of `scatter`, one task a chunk.
template <class ChunkPass>
void for_each_chunk(const detail::OrderedScatter& scatter, const ChunkPass& chunk_pass) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, scatter.chunk_count(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t c = range.begin(); c < range.end(); ++c) {
                const auto [first, end] = scatter.chunk(c);
                chunk_pass(first, end);
            }
        },
        tbb::simple_partitioner{});
}
}  // namespace

void TetrahedronFEMForceField::prepare_scatter(std::size_t chunks) const {
    if (product_scatter_.element_count() == elements_.size() && product_scatter_.requested_chunks() == chunks) return;
    // the chunks' first elements on a lane block's boundary (eight lanes, four dividing it)
    product_scatter_.build(std::span<const Element>(elements_), chunks, 8);
    product_terms_.resize(4 * elements_.size());
}

void TetrahedronFEMForceField::concurrent_large_dforce(std::span<Vec3> df, std::span<const Vec3> dx,
                                                       double k_factor) const {
    prepare_scatter(product_chunks(tbb::this_task_arena::max_concurrency()));
    const detail::DeferredTerms deferred{product_scatter_.deferred_mask(), product_terms_.data()};
    for_each_chunk(product_scatter_,
                   [&](std::size_t first, std::size_t end) { large_dforce(first, end, df, dx, k_factor, deferred); });
    product_scatter_.subtract_deferred(product_terms_, df);
}

void TetrahedronFEMForceField::concurrent_large_force(std::span<Vec3> f, std::span<const Vec3> x) {
    prepare_scatter(product_chunks(tbb::this_task_arena::max_concurrency()));
    const detail::DeferredTerms deferred{product_scatter_.deferred_mask(), product_terms_.data()};
    element_energies_.resize(elements_.size());
    for_each_chunk(product_scatter_, [&](std::size_t first, std::size_t end) {
        large_force(first, end, f, x, deferred, element_energies_.data());
    });
    product_scatter_.add_deferred(product_terms_, f);
    energy_ = 0.0;  // ½ δᵀF of each element, in element order
    for (const double e : element_energies_) energy_ += e;
}

}  // namespace penalty
