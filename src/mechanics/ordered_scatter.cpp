#include "penalty/mechanics/ordered_scatter.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace penalty::detail {
namespace {
constexpr std::size_t kDeferredVerticesPerTask = 1024;
constexpr std::uint32_t kNoChunk = std::numeric_limits<std::uint32_t>::max();
}  // namespace

std::size_t OrderedScatter::chunks_for(std::size_t elements, int threads) {
    if (threads < 2 || elements < kMinElements) return 0;
    return std::min(kChunksPerThread * static_cast<std::size_t>(threads), elements / kMinElementsPerChunk);
}

int OrderedScatter::arena_threads() { return tbb::this_task_arena::max_concurrency(); }

bool OrderedScatter::worth_threads(std::size_t elements) {
    return elements >= kMinElements && chunks_for(elements, arena_threads()) > 1;
}

void OrderedScatter::for_each_chunk(const std::function<void(std::size_t, std::size_t)>& pass) const {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, chunk_count(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t c = range.begin(); c < range.end(); ++c) pass(chunk_first_[c], chunk_first_[c + 1]);
        },
        tbb::simple_partitioner{});
}

void for_each_range_on_threads(std::size_t count, std::size_t per_task,
                               const std::function<void(std::size_t, std::size_t)>& pass) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, per_task),
                      [&pass](const tbb::blocked_range<std::size_t>& r) { pass(r.begin(), r.end()); });
}

void OrderedScatter::clear() {
    element_count_ = 0;
    requested_chunks_ = 0;
    chunk_first_.clear();
    deferred_mask_.clear();
    deferred_before_.clear();
    per_element_ = 0;
    deferred_vertex_.clear();
    deferred_first_.clear();
    deferred_term_.clear();
    terms_ = {};
}

void OrderedScatter::build_flat(std::span<const PointId> vertices, std::size_t per_element, std::size_t chunks,
                                std::size_t alignment) {
    clear();
    PENALTY_DEMAND(per_element > 0 && per_element <= 8 && vertices.size() % per_element == 0 && chunks > 0 &&
                   alignment > 0 && vertices.size() <= std::numeric_limits<std::uint32_t>::max());
    const std::size_t count = vertices.size() / per_element;
    if (count == 0) return;
    PENALTY_DEMAND(*std::min_element(vertices.begin(), vertices.end()) >= 0);
    const auto vertex_count = static_cast<std::size_t>(*std::max_element(vertices.begin(), vertices.end())) + 1;
    // chunks of `size` elements, a multiple of the alignment, the last one shorter
    const std::size_t per_chunk = (count + chunks - 1) / chunks;
    const std::size_t size = (per_chunk + alignment - 1) / alignment * alignment;
    for (std::size_t first = 0; first < count; first += size) chunk_first_.push_back(first);
    chunk_first_.push_back(count);
    // each vertex's owner: the chunk of its first element; the other chunks' terms deferred
    std::vector<std::uint32_t> owner(vertex_count, kNoChunk);
    std::vector<std::uint32_t> deferred_count(vertex_count, 0);
    deferred_mask_.assign(count, 0);
    for (std::size_t c = 0; c + 1 < chunk_first_.size(); ++c)
        for (std::size_t e = chunk_first_[c]; e < chunk_first_[c + 1]; ++e)
            for (std::size_t k = 0; k < per_element; ++k) {
                const auto v = static_cast<std::size_t>(vertices[per_element * e + k]);
                if (owner[v] == kNoChunk) owner[v] = static_cast<std::uint32_t>(c);
                if (owner[v] == c) continue;
                deferred_mask_[e] = static_cast<std::uint8_t>(deferred_mask_[e] | (1U << k));
                ++deferred_count[v];
            }
    // the deferred terms by vertex (a counting sort, stable: element order within a vertex)
    std::vector<std::uint32_t> slot(vertex_count, 0);
    deferred_first_.push_back(0);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        if (deferred_count[v] == 0) continue;
        slot[v] = deferred_first_.back();
        deferred_vertex_.push_back(static_cast<PointId>(v));
        deferred_first_.push_back(deferred_first_.back() + deferred_count[v]);
    }
    deferred_term_.resize(deferred_first_.back());
    for (std::size_t e = 0; e < count; ++e)
        for (std::size_t k = 0; k < per_element; ++k)
            if ((deferred_mask_[e] >> k) & 1U) {
                const auto v = static_cast<std::size_t>(vertices[per_element * e + k]);
                deferred_term_[slot[v]++] = static_cast<std::uint32_t>(per_element * e + k);
            }
    deferred_before_.resize(count);
    std::uint32_t before = 0;
    for (std::size_t e = 0; e < count; ++e) {
        deferred_before_[e] = before;
        before += static_cast<std::uint32_t>(__builtin_popcount(deferred_mask_[e]));
    }
    per_element_ = per_element;
    element_count_ = count;
    requested_chunks_ = chunks;
}

template <bool Add>
void OrderedScatter::apply_deferred(ScatterTarget out) const {
    if (deferred_vertex_.empty()) return;
    PENALTY_DEMAND(static_cast<std::size_t>(deferred_vertex_.back()) < out.low.size() + out.high.size());
    PENALTY_DEMAND(terms_.size() == per_element_ * element_count_);  // (deferred() made them)
    const Vec3* terms = terms_.data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, deferred_vertex_.size(), kDeferredVerticesPerTask),
                      [out, terms, this](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i < range.end(); ++i) {
                              const auto v = static_cast<std::size_t>(deferred_vertex_[i]);
                              Vec3& target = v < out.low.size() ? out.low[v] : out.high[v - out.low.size()];
                              for (std::uint32_t t = deferred_first_[i]; t < deferred_first_[i + 1]; ++t) {
                                  if constexpr (Add) target += terms[deferred_term_[t]];
                                  else target -= terms[deferred_term_[t]];
                              }
                          }
                      });
}

void OrderedScatter::for_each_deferred_slot(const std::function<void(std::size_t, std::size_t)>& apply) const {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, deferred_vertex_.size(), kDeferredVerticesPerTask),
        [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t i = range.begin(); i < range.end(); ++i) {
                const auto vertex = static_cast<std::size_t>(deferred_vertex_[i]);
                for (std::uint32_t t = deferred_first_[i]; t < deferred_first_[i + 1]; ++t)
                    apply(vertex, deferred_slot(deferred_term_[t] / per_element_, deferred_term_[t] % per_element_));
            }
        });
}

void OrderedScatter::subtract_deferred(ScatterTarget out) const { apply_deferred<false>(out); }

void OrderedScatter::add_deferred(ScatterTarget out) const { apply_deferred<true>(out); }

}  // namespace penalty::detail
