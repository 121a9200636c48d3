// detail::OrderedScatter: an element loop's scatter split into chunks of consecutive elements
// (each chunk's own vertices at once, the others' terms stored and subtracted after) gives each
// vertex the loop's bits for any chunk count and any order of the chunks.
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <vector>

namespace penalty {
namespace {

using Element4 = std::array<PointId, 4>;

/// Random elements of four distinct vertices of `vertices`, in no spatial order.
std::vector<Element4> random_elements(std::size_t count, PointId vertices, std::mt19937& rng) {
    std::vector<Element4> elements;
    std::uniform_int_distribution<PointId> pick(0, vertices - 1);
    while (elements.size() < count) {
        Element4 e{pick(rng), pick(rng), pick(rng), pick(rng)};
        if (e[0] == e[1] || e[0] == e[2] || e[0] == e[3] || e[1] == e[2] || e[1] == e[3] || e[2] == e[3]) continue;
        elements.push_back(e);
    }
    return elements;
}

using test::same_bits;

/// out after the scatter split by `scatter`, its chunks run last to first (any order must do),
/// each element's terms through store_or_apply, the stored terms applied on four threads; Add: +=
/// (a force), else −= (a product). The storage starts as NaN: a term applied that was not stored
/// shows.
template <bool Add>
std::vector<Vec3> split_scatter(detail::OrderedScatter& scatter, const std::vector<Element4>& elements,
                                const std::vector<Vec3>& terms, std::vector<Vec3> out) {
    const detail::DeferredTerms deferred = scatter.deferred();
    std::fill(deferred.terms, deferred.terms + terms.size(), Vec3::Constant(std::nan("")));
    for (std::size_t c = scatter.chunk_count(); c-- > 0;) {
        const auto [first, end] = scatter.chunk(c);
        for (std::size_t e = first; e < end; ++e) {
            const std::array<Vec3, 4> element_terms{terms[4 * e], terms[4 * e + 1], terms[4 * e + 2], terms[4 * e + 3]};
            detail::store_or_apply(deferred, e, element_terms, [&](std::size_t k, const Vec3& term) {
                if (Add) out[static_cast<std::size_t>(elements[e][k])] += term;
                else out[static_cast<std::size_t>(elements[e][k])] -= term;
            });
        }
    }
    tbb::task_arena arena(4);
    arena.execute([&] {
        if (Add) scatter.add_deferred(out);
        else scatter.subtract_deferred(out);
    });
    return out;
}

TEST(OrderedScatter, ChunksInAnyOrderGiveEachVertexTheLoopsBits) {
    std::mt19937 rng(7);
    const PointId vertices = 400;
    const std::vector<Element4> elements = random_elements(3001, vertices, rng);
    // terms of many magnitudes, so that another order of a vertex's sums gives other bits
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-20, 20);
    std::vector<Vec3> terms(4 * elements.size());
    for (Vec3& t : terms)
        for (int c = 0; c < 3; ++c) t[c] = std::ldexp(mantissa(rng), exponent(rng));
    std::vector<Vec3> start(static_cast<std::size_t>(vertices));
    for (Vec3& v : start) v = Vec3(mantissa(rng), mantissa(rng), mantissa(rng));
    std::vector<Vec3> loop = start, loop_added = start, reversed = start;
    for (std::size_t e = 0; e < elements.size(); ++e)
        for (std::size_t k = 0; k < 4; ++k) {
            loop[static_cast<std::size_t>(elements[e][k])] -= terms[4 * e + k];
            loop_added[static_cast<std::size_t>(elements[e][k])] += terms[4 * e + k];
        }
    for (std::size_t e = elements.size(); e-- > 0;)
        for (std::size_t k = 0; k < 4; ++k) reversed[static_cast<std::size_t>(elements[e][k])] -= terms[4 * e + k];
    ASSERT_FALSE(same_bits(loop, reversed)) << "the terms do not tell one order from another";

    for (const std::size_t chunks : {1, 2, 3, 7, 16, 64}) {
        detail::OrderedScatter scatter;
        scatter.build(std::span<const Element4>(elements), chunks, 8);
        ASSERT_EQ(scatter.element_count(), elements.size());
        // whole chunks of a multiple of 8 elements: 3001 in 64 asked for are 63 of 48 and one of 25
        const std::size_t size = (elements.size() + chunks - 1) / chunks;
        const std::size_t aligned = (size + 7) / 8 * 8;
        ASSERT_EQ(scatter.chunk_count(), (elements.size() + aligned - 1) / aligned) << chunks;
        ASSERT_LE(scatter.chunk_count(), chunks);
        EXPECT_EQ(scatter.requested_chunks(), chunks);
        for (std::size_t c = 0; c + 1 < scatter.chunk_count(); ++c) {
            EXPECT_EQ(scatter.chunk(c)[1] - scatter.chunk(c)[0], aligned) << chunks;
            EXPECT_EQ(scatter.chunk(c)[1], scatter.chunk(c + 1)[0]) << chunks;
        }
        EXPECT_EQ(scatter.chunk(0)[0], 0U);
        EXPECT_EQ(scatter.chunk(scatter.chunk_count() - 1)[1], elements.size());
        // a vertex's own terms lie in one chunk, the first that touches it
        std::vector<std::size_t> owner(static_cast<std::size_t>(vertices), chunks);
        std::size_t deferred = 0;
        for (std::size_t c = 0; c < scatter.chunk_count(); ++c)
            for (std::size_t e = scatter.chunk(c)[0]; e < scatter.chunk(c)[1]; ++e)
                for (std::size_t k = 0; k < 4; ++k) {
                    auto& o = owner[static_cast<std::size_t>(elements[e][k])];
                    if (o == chunks) o = c;
                    const bool is_deferred = (scatter.deferred_mask()[e] >> k) & 1U;
                    EXPECT_EQ(is_deferred, o != c);
                    deferred += is_deferred ? 1 : 0;
                }
        EXPECT_EQ(scatter.deferred_terms(), deferred);
        if (chunks > 1) {
            EXPECT_GT(deferred, terms.size() / 4) << chunks;  // random elements share vertices
        }
        EXPECT_TRUE(same_bits(split_scatter<false>(scatter, elements, terms, start), loop)) << chunks;
        EXPECT_TRUE(same_bits(split_scatter<true>(scatter, elements, terms, start), loop_added)) << chunks;
    }
}

TEST(OrderedScatter, DeferredSlotsNumberTheStoredTermsInElementOrderAndVisitEachVertexsInOrder) {
    // a caller storing its own terms (FastTetrahedralCorotationalForceField's edge matrices):
    // the slots are 0, 1, … in element order, and for_each_deferred_slot gives each vertex its
    // slots in element order, each slot once
    std::mt19937 rng(13);
    const std::vector<Element4> elements = random_elements(2003, 300, rng);
    detail::OrderedScatter scatter;
    scatter.build(std::span<const Element4>(elements), 5, 1);
    ASSERT_GT(scatter.deferred_terms(), 0U);
    std::size_t next = 0;
    std::vector<std::vector<std::size_t>> expected(300);  // per vertex, its slots in element order
    for (std::size_t e = 0; e < elements.size(); ++e)
        for (std::size_t k = 0; k < 4; ++k)
            if ((scatter.deferred_mask()[e] >> k) & 1U) {
                EXPECT_EQ(scatter.deferred_slot(e, k), next) << e << ' ' << k;
                expected[static_cast<std::size_t>(elements[e][k])].push_back(next++);
            }
    ASSERT_EQ(next, scatter.deferred_terms());
    std::vector<std::vector<std::size_t>> visited(300);
    std::vector<int> visits(next, 0);
    tbb::task_arena arena(1);  // (the visits of a vertex are in order on any thread count)
    arena.execute([&] {
        scatter.for_each_deferred_slot([&](std::size_t vertex, std::size_t slot) {
            visited[vertex].push_back(slot);
            ++visits[slot];
        });
    });
    EXPECT_EQ(visited, expected);
    EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), std::ptrdiff_t(next));
}

TEST(OrderedScatter, CallerStoredGroupsOfTermsGiveEachVertexTheLoopsBits) {
    // scatter_stored_in_order: each vertex slot subtracts two terms in a row (as a bending
    // element's product does); on threads a deferred slot's two are stored together and
    // subtracted in element order after. 9 000 elements (above kMinElements) on 700 vertices: at
    // 1, 2, 3 and 8 threads the bits of the loop.
    std::mt19937 rng(21);
    const std::vector<Element4> elements = random_elements(9000, 700, rng);
    std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-20, 20);
    using Pair = std::array<Vec3, 2>;
    std::vector<Pair> terms(4 * elements.size());
    for (Pair& p : terms)
        for (Vec3& t : p)
            for (int c = 0; c < 3; ++c) t[c] = std::ldexp(mantissa(rng), exponent(rng));
    std::vector<Vec3> loop(700, Vec3(0.5, -0.25, 1.0));
    for (std::size_t e = 0; e < elements.size(); ++e)
        for (std::size_t k = 0; k < 4; ++k)
            for (const Vec3& t : terms[4 * e + k]) loop[static_cast<std::size_t>(elements[e][k])] -= t;
    for (const int threads : {1, 2, 3, 8}) {
        detail::OrderedScatter scatter;
        std::vector<Pair> stored;
        std::vector<Vec3> out(700, Vec3(0.5, -0.25, 1.0));
        std::atomic<bool> stored_some = false;
        tbb::task_arena(threads).execute([&] {
            detail::scatter_stored_in_order(
                scatter, std::span<const Element4>(elements), stored,
                [&](std::size_t first, std::size_t end, const std::uint8_t* mask) {
                    for (std::size_t e = first; e < end; ++e)
                        for (std::size_t k = 0; k < 4; ++k) {
                            if (mask != nullptr && ((mask[e] >> k) & 1U) != 0) {
                                stored[scatter.deferred_slot(e, k)] = terms[4 * e + k];
                                continue;
                            }
                            for (const Vec3& t : terms[4 * e + k]) out[static_cast<std::size_t>(elements[e][k])] -= t;
                        }
                },
                [&](std::size_t vertex, const Pair& pair) {
                    stored_some = true;
                    for (const Vec3& t : pair) out[vertex] -= t;
                });
        });
        EXPECT_EQ(stored_some.load(), threads > 1) << threads;
        EXPECT_TRUE(same_bits(out, loop)) << threads;
    }
}

TEST(OrderedScatter, AMeshNumberedInSpaceDefersFewTerms) {
    // a Kuhn grid of 24 × 24 × 24 points, 72 006 tetrahedra numbered cell by cell
    const RegularGridTopology grid({24, 24, 24}, Vec3::Zero(), Vec3::Ones());
    const MeshTopology mesh = test::kuhn_tetrahedra(grid);
    const auto& tetrahedra = mesh.tetrahedra();
    std::vector<Element4> shuffled = tetrahedra;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(2));
    const auto deferred_share = [](const std::vector<Element4>& elements, std::size_t chunks) {
        detail::OrderedScatter scatter;
        scatter.build(std::span<const Element4>(elements), chunks, 8);
        return double(scatter.deferred_terms()) / double(4 * elements.size());
    };
    // measured: 6.8 %, 34 % and 49 %; the shuffled numbering defers most terms
    for (const auto& [chunks, most] : {std::pair{4, 0.08}, std::pair{16, 0.36}, std::pair{32, 0.51}}) {
        const double share = deferred_share(tetrahedra, std::size_t(chunks));
        EXPECT_GT(share, 0.0) << chunks;
        EXPECT_LT(share, most) << chunks;
        EXPECT_GT(deferred_share(shuffled, std::size_t(chunks)), 0.7) << chunks;
    }
}

TEST(OrderedScatter, FewElementsMakeFewerChunksAndNoneMakeNone) {
    std::mt19937 rng(3);
    const std::vector<Element4> elements = random_elements(20, 30, rng);
    detail::OrderedScatter scatter;
    scatter.build(std::span<const Element4>(elements), 16, 8);
    EXPECT_EQ(scatter.chunk_count(), 3U);  // 8 + 8 + 4
    scatter.build(std::span<const Element4>(), 16, 8);
    EXPECT_EQ(scatter.chunk_count(), 0U);
    EXPECT_EQ(scatter.element_count(), 0U);
}

// for_each_range: one call over [0, count) below kMinElements items or on one thread, else ranges
// of at most per_task items on TBB's threads, which cover every item once.
TEST(OrderedScatter, ForEachRangeIsOneCallOrRangesThatCoverEachItemOnce) {
    constexpr std::size_t kPerTask = 1000;
    for (const int threads : {1, 4})
        for (const std::size_t count :
             {detail::OrderedScatter::kMinElements - 1, detail::OrderedScatter::kMinElements + 1001}) {
            std::vector<std::atomic<int>> seen(count);
            std::atomic<int> calls{0};
            std::atomic<std::size_t> longest{0};
            tbb::task_arena(threads).execute([&] {
                detail::for_each_range(count, kPerTask, [&](std::size_t first, std::size_t end) {
                    ++calls;
                    std::size_t seen_longest = longest.load();
                    while (end - first > seen_longest && !longest.compare_exchange_weak(seen_longest, end - first)) {
                    }
                    for (std::size_t i = first; i < end; ++i) ++seen[i];
                });
            });
            EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](const std::atomic<int>& n) { return n.load() == 1; }))
                << threads << " threads, " << count << " items";
            if (threads > 1 && count >= detail::OrderedScatter::kMinElements) {
                EXPECT_GE(calls.load(), static_cast<int>(count / kPerTask)) << count;
                EXPECT_LE(longest.load(), kPerTask) << count;
            } else {
                EXPECT_EQ(calls.load(), 1) << threads << " threads, " << count << " items";
                EXPECT_EQ(longest.load(), count);
            }
        }
}

}  // namespace
}  // namespace penalty
