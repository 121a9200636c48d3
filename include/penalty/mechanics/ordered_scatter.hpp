#pragma once
/// @file
/// An element loop's scatter on several threads with the bits of one. Internal (namespace
/// detail): element force fields hold one.
#include "penalty/core/types.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace penalty::detail {

/// The terms of an element product that are stored rather than subtracted (OrderedScatter): bit
/// k of mask[e] set: element e's term k goes to terms[e·N + k]. A null mask: none.
struct DeferredTerms {
    const std::uint8_t* mask = nullptr;
    Vec3* terms = nullptr;
};

/// The one-thread loop's deferred terms: none. store_or_apply applies every term, with no mask
/// to test (a pass written for `const auto&` gets this path compiled apart); it converts to an
/// empty DeferredTerms for a pass that takes one.
struct NoDeferredTerms {
    operator DeferredTerms() const { return {}; }  // NOLINT(google-explicit-constructor)
};

template <std::size_t N, class Apply>
void store_or_apply(NoDeferredTerms, std::size_t, const std::array<Vec3, N>& terms, const Apply& apply) {
    for (std::size_t k = 0; k < N; ++k) apply(k, terms[k]);
}

/// Element e's N terms: each stored where `deferred` marks it, else apply(k, term) (the loop's
/// out[vertex k] += or −= term).
template <std::size_t N, class Apply>
void store_or_apply(const DeferredTerms& deferred, std::size_t e, const std::array<Vec3, N>& terms,
                    const Apply& apply) {
    const unsigned mask = deferred.mask ? deferred.mask[e] : 0U;
    for (std::size_t k = 0; k < N; ++k) {
        if ((mask >> k) & 1U) deferred.terms[N * e + k] = terms[k];
        else apply(k, terms[k]);
    }
}

/// Where an OrderedScatter's deferred terms go: out[v]; or, for an interaction force field
/// between two states whose vertices the scatter numbers one after the other (the second state's
/// vertex v as low.size() + v), low[v] for v < low.size() and high[v − low.size()] after.
struct ScatterTarget {
    ScatterTarget(std::span<Vec3> out) : low(out) {}     // NOLINT(google-explicit-constructor)
    ScatterTarget(std::vector<Vec3>& out) : low(out) {}  // NOLINT(google-explicit-constructor)
    ScatterTarget(std::span<Vec3> first_state, std::span<Vec3> second_state) : low(first_state), high(second_state) {}
    std::span<Vec3> low;
    std::span<Vec3> high;
};

/// The scatter `for e, for k: out[vertex(e, k)] −= term(e, k)` (or +=) of an element loop (e ascending, k
/// the element's vertex slot) split into chunks of consecutive elements that run on different
/// threads, with every vertex's subtractions in the loop's order, hence its bits:
///  - a vertex's owner is the first chunk that touches it; that chunk's task subtracts the vertex's
///    terms itself (they come first in element order, and no other task writes the vertex);
///  - the other chunks' terms of the vertex are deferred: stored at e·N + k, then subtracted
///    vertex by vertex in element order (subtract_deferred) once every chunk is done.
/// On a mesh numbered in space a small share is deferred (the soft body on the organ, 196 608
/// tetrahedra: 12 % of the terms in 16 chunks, 24 % in 32; a cube of 24³ points numbered cell by
/// cell: 7 %, 34 % and 49 % in 4, 16 and 32 chunks). The chunking changes no bit.
class OrderedScatter {
public:
    /// An element force field's product runs on threads from kMinElements elements, in
    /// kChunksPerThread chunks a thread of the arena of at least kMinElementsPerChunk elements.
    static constexpr std::size_t kMinElements = 8192;
    static constexpr std::size_t kChunksPerThread = 2;
    static constexpr std::size_t kMinElementsPerChunk = 2048;
    /// The chunks of `elements` elements on `threads` threads: 0 or 1 (the loop on one thread)
    /// below kMinElements elements or with one thread.
    [[nodiscard]] static std::size_t chunks_for(std::size_t elements, int threads);
    /// Whether `elements` elements' products run on threads in the calling arena (chunks_for > 1).
    [[nodiscard]] static bool worth_threads(std::size_t elements);

    /// `chunks` chunks (fewer if there are few elements), each a multiple of `alignment` elements
    /// but the last. O(elements).
    template <std::size_t N>
    void build(std::span<const std::array<PointId, N>> elements, std::size_t chunks, std::size_t alignment) {
        static_assert(N <= 8, "the deferred terms of an element are one byte's bits");
        build_flat(std::span<const PointId>(elements.empty() ? nullptr : elements.front().data(), N * elements.size()),
                   N, chunks, alignment);
    }
    /// build() for the chunks_for of the calling arena's threads, unless it was last built for as
    /// many elements and chunks (a caller whose elements change clears it).
    template <std::size_t N>
    void prepare(std::span<const std::array<PointId, N>> elements, std::size_t alignment) {
        const std::size_t chunks = chunks_for(elements.size(), arena_threads());
        if (element_count_ != elements.size() || requested_chunks_ != chunks) build(elements, chunks, alignment);
    }
    void clear();
    /// pass(first, end) for the elements [first, end) of each chunk, one TBB task a chunk.
    void for_each_chunk(const std::function<void(std::size_t, std::size_t)>& pass) const;
    [[nodiscard]] std::size_t element_count() const { return element_count_; }
    [[nodiscard]] std::size_t chunk_count() const { return chunk_first_.empty() ? 0 : chunk_first_.size() - 1; }
    /// The chunk count build() was asked for (chunk_count() can be lower: whole aligned chunks).
    [[nodiscard]] std::size_t requested_chunks() const { return requested_chunks_; }
    /// Elements [first, end) of chunk c.
    [[nodiscard]] std::array<std::size_t, 2> chunk(std::size_t c) const {
        return {chunk_first_[c], chunk_first_[c + 1]};
    }
    /// Bit k of element e: its term k is deferred (the kernel stores it at e·N + k).
    [[nodiscard]] const std::uint8_t* deferred_mask() const { return deferred_mask_.data(); }
    /// The mask and where the chunks store the deferred terms (room for every term e·N + k, made
    /// at the first call after a build).
    [[nodiscard]] DeferredTerms deferred() {
        terms_.resize(per_element_ * element_count_);
        return {deferred_mask_.data(), terms_.data()};
    }
    /// How many terms are deferred.
    [[nodiscard]] std::size_t deferred_terms() const { return deferred_term_.size(); }
    /// For a caller that stores the deferred terms itself, one after another (terms too large to
    /// keep a slot for every term, as terms_ does): the slot of element e's deferred term k, in
    /// [0, deferred_terms()), numbered in element order.
    [[nodiscard]] std::size_t deferred_slot(std::size_t e, std::size_t k) const {
        const unsigned below = deferred_mask_[e] & ((1U << k) - 1U);
        return deferred_before_[e] + static_cast<std::size_t>(__builtin_popcount(below));
    }
    /// apply(vertex, slot) for each vertex's deferred terms in element order, the vertices on TBB's
    /// threads (deferred_slot's numbering).
    void for_each_deferred_slot(const std::function<void(std::size_t, std::size_t)>& apply) const;

    /// out[v] −= term for each vertex v's stored terms in element order, the vertices on TBB's
    /// threads.
    void subtract_deferred(ScatterTarget out) const;
    /// The same with out[v] += term (a force loop's scatter).
    void add_deferred(ScatterTarget out) const;

private:
    /// The calling arena's threads (TBB's max_concurrency).
    [[nodiscard]] static int arena_threads();
    void build_flat(std::span<const PointId> vertices, std::size_t per_element, std::size_t chunks,
                    std::size_t alignment);
    template <bool Add>
    void apply_deferred(ScatterTarget out) const;
    std::size_t element_count_ = 0;
    std::size_t requested_chunks_ = 0;
    std::vector<std::size_t> chunk_first_;        ///< chunk c: elements [chunk_first_[c], chunk_first_[c + 1])
    std::vector<std::uint8_t> deferred_mask_;     ///< per element
    std::vector<std::uint32_t> deferred_before_;  ///< per element: the deferred terms of the elements before it
    std::size_t per_element_ = 0;
    std::vector<PointId> deferred_vertex_;       ///< the vertices with deferred terms, increasing
    std::vector<std::uint32_t> deferred_first_;  ///< their terms: [deferred_first_[i], deferred_first_[i + 1])
    std::vector<std::uint32_t> deferred_term_;   ///< e·N + k, each vertex's in element order
    std::vector<Vec3> terms_;                    ///< the stored terms, at e·N + k
};

/// pass(first, end) for ranges of `per_task` covering [0, count), on TBB's threads.
void for_each_range_on_threads(std::size_t count, std::size_t per_task,
                               const std::function<void(std::size_t, std::size_t)>& pass);

/// Whether for_each_range runs `count` items in ranges on threads in the calling arena (from
/// OrderedScatter::kMinElements items, more than one thread): a caller that keeps per-item
/// results for an ordered sum only then (RestShapeSpringsForceField's energies) asks this.
[[nodiscard]] inline bool ranges_on_threads(std::size_t count) {
    // (a small loop, a body's few DOFs, tests its size here: no call)
    return count >= OrderedScatter::kMinElements && OrderedScatter::worth_threads(count);
}

/// pass(first, end) over [0, count) in one call, or, from OrderedScatter::kMinElements items with
/// more than one thread in the calling arena, in ranges of `per_task` on TBB's threads: for a loop
/// whose iterations write apart (a diagonal mass's df[i] += m_i·dx[i]), the bits of one call.
template <class Pass>
void for_each_range(std::size_t count, std::size_t per_task, const Pass& pass) {
    if (!ranges_on_threads(count)) {
        pass(std::size_t{0}, count);
        return;
    }
    // (a std::function of one reference: no allocation)
    for_each_range_on_threads(count, per_task, [&pass](std::size_t first, std::size_t end) { pass(first, end); });
}

/// pass(first, end, deferred) over `elements`, whose terms go to out[vertex] (+= when Add, else
/// −=) in element order: one call with NoDeferredTerms below OrderedScatter::kMinElements
/// elements or on one thread, else `scatter`'s chunks of consecutive elements (each first element
/// a multiple of `alignment`) on TBB's threads, the terms `deferred` marks applied in element
/// order after: the bits of one thread.
template <bool Add, std::size_t N, class Pass>
void scatter_in_order(OrderedScatter& scatter, std::span<const std::array<PointId, N>> elements, ScatterTarget out,
                      std::size_t alignment, const Pass& pass) {
    if (!OrderedScatter::worth_threads(elements.size())) {
        pass(std::size_t{0}, elements.size(), NoDeferredTerms{});
        return;
    }
    scatter.prepare(elements, alignment);
    const DeferredTerms deferred = scatter.deferred();
    scatter.for_each_chunk([&](std::size_t first, std::size_t end) { pass(first, end, deferred); });
    if constexpr (Add) scatter.add_deferred(out);
    else scatter.subtract_deferred(out);
}

/// scatter_in_order for terms that are not one Vec3 a vertex slot (a vertex's several subtractions
/// of one element, a frame's force and torque), which the caller stores: pass(first, end, mask)
/// applies element e's slot k, or, where bit k of mask[e] is set (mask null: on one thread, none),
/// stores it at stored[scatter.deferred_slot(e, k)]; apply(vertex, stored term) then adds each
/// stored term to its vertex in element order (the vertices on TBB's threads): the bits of one
/// thread.
template <std::size_t N, class Terms, class Pass, class Apply>
void scatter_stored_in_order(OrderedScatter& scatter, std::span<const std::array<PointId, N>> elements,
                             std::vector<Terms>& stored, const Pass& pass, const Apply& apply) {
    if (!OrderedScatter::worth_threads(elements.size())) {
        pass(std::size_t{0}, elements.size(), static_cast<const std::uint8_t*>(nullptr));
        return;
    }
    scatter.prepare(elements, 1);
    stored.resize(scatter.deferred_terms());
    const std::uint8_t* mask = scatter.deferred_mask();
    scatter.for_each_chunk([&](std::size_t first, std::size_t end) { pass(first, end, mask); });
    scatter.for_each_deferred_slot([&](std::size_t vertex, std::size_t slot) { apply(vertex, stored[slot]); });
}

/// scatter_in_order of a force pass, pass(first, end, deferred, energies), that returns its
/// elements' energy summed in element order, or 0 with element e's into energies[e] (not null;
/// `energies` is resized for it): returns every element's energy summed in element order.
template <bool Add, std::size_t N, class Pass>
double force_in_order(OrderedScatter& scatter, std::span<const std::array<PointId, N>> elements, ScatterTarget f,
                      std::size_t alignment, std::vector<double>& energies, const Pass& pass) {
    if (!OrderedScatter::worth_threads(elements.size()))
        return pass(std::size_t{0}, elements.size(), NoDeferredTerms{}, nullptr);
    energies.resize(elements.size());
    scatter_in_order<Add>(scatter, elements, f, alignment,
                          [&](std::size_t first, std::size_t end, const DeferredTerms& deferred) {
                              pass(first, end, deferred, energies.data());
                          });
    double total = 0.0;
    for (const double e : energies) total += e;
    return total;
}

}  // namespace penalty::detail
