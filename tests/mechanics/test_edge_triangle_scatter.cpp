// detail::EdgeTriangleScatter: a field's edge loop (out[v1] += a, out[v0] −= b) and triangle loop
// (each vertex up to three additions or subtractions, up to four energy terms) give, on threads,
// the bits of the loop written out: each vertex's terms and the energy's in the loop's order.
#include "penalty/mechanics/edge_triangle_scatter.hpp"

#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace penalty {
namespace {

constexpr PointId kVertices = 6000;

using test::same_bits;

Vec3 random_vec(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    return {u(rng), u(rng), u(rng)};
}

/// The values the loops add to: random, with some −0 components (a −0 sum keeps its sign only
/// if every term added to it is −0 too: the order shows).
std::vector<Vec3> start_values() {
    std::mt19937 rng(5);
    std::vector<Vec3> out(kVertices);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = i % 7 == 0 ? Vec3(-0.0, 0.5, -0.0) : random_vec(rng);
    return out;
}

/// One operation of a triangle's script: out[t[slot]] += term (or −=), or an energy term.
struct Operation {
    int slot = 0;  ///< 0 … 2, or −1: an energy term
    bool subtract = false;
    Vec3 term = Vec3::Zero();
    double energy = 0.0;
};

/// Random triangles of distinct vertices in no spatial order, each with a script of at most
/// three operations a vertex (interleaved across its vertices, some terms ±0 and of mixed
/// magnitudes) and at most four energy terms.
struct TriangleLoop {
    std::vector<Triangle> triangles;
    std::vector<std::vector<Operation>> scripts;
    explicit TriangleLoop(std::size_t count) {
        std::mt19937 rng(17);
        std::uniform_int_distribution<PointId> pick(0, kVertices - 1);
        std::uniform_int_distribution<int> slot(0, 2), coin(0, 1), energies(0, 4);
        while (triangles.size() < count) {
            const Triangle t{pick(rng), pick(rng), pick(rng)};
            if (t[0] == t[1] || t[0] == t[2] || t[1] == t[2]) continue;
            triangles.push_back(t);
            std::vector<Operation>& script = scripts.emplace_back();
            int per_slot[3] = {0, 0, 0};
            for (int n = 0; n < 9; ++n) {
                const int k = slot(rng);
                if (per_slot[k] == 3 || coin(rng) == 0) continue;
                ++per_slot[k];
                Vec3 term = random_vec(rng) * std::pow(10.0, slot(rng) * 4 - 4);
                if (coin(rng) == 0 && coin(rng) == 0) term = Vec3(-0.0, 0.0, -0.0);
                script.push_back({k, coin(rng) == 1, term, 0.0});
            }
            for (int e = energies(rng); e > 0; --e)
                script.push_back({-1, false, Vec3::Zero(), random_vec(rng)[0] * std::pow(10.0, slot(rng) * 3)});
        }
    }
    /// The loop written out: returns the energy, from `energy`.
    double reference(std::vector<Vec3>& out, double energy) const {
        for (std::size_t ti = 0; ti < triangles.size(); ++ti)
            for (const Operation& op : scripts[ti]) {
                if (op.slot < 0) {
                    energy += op.energy;
                    continue;
                }
                Vec3& o = out[static_cast<std::size_t>(triangles[ti][static_cast<std::size_t>(op.slot)])];
                if (op.subtract) o -= op.term;
                else o += op.term;
            }
        return energy;
    }
    /// The same through `scatter` in an arena of `threads` threads.
    double on_threads(detail::EdgeTriangleScatter& scatter, std::vector<Vec3>& out, double energy, int threads) const {
        tbb::task_arena arena(threads);
        arena.execute([&] {
            energy = scatter.triangle_loop(triangles, out, energy, [&](std::size_t ti, auto& sink) {
                for (const Operation& op : scripts[ti]) {
                    if (op.slot < 0) sink.add_energy(op.energy);
                    else if (op.subtract) sink.subtract(static_cast<std::size_t>(op.slot), op.term);
                    else sink.add(static_cast<std::size_t>(op.slot), op.term);
                }
            });
        });
        return energy;
    }
};

TEST(EdgeTriangleScatter, TriangleLoopOnThreadsGivesEachVertexAndTheEnergyTheLoopsBits) {
    const TriangleLoop loop(12000);  // (OrderedScatter::kMinElements or more)
    std::vector<Vec3> expected = start_values();
    const double expected_energy = loop.reference(expected, 0.25);
    detail::EdgeTriangleScatter scatter;
    for (const int threads : {1, 2, 3, 8, 2}) {
        std::vector<Vec3> out = start_values();
        const double energy = loop.on_threads(scatter, out, 0.25, threads);
        const std::string where = std::to_string(threads) + " threads";
        EXPECT_TRUE(same_bits(out, expected)) << where;
        EXPECT_EQ(std::memcmp(&energy, &expected_energy, sizeof(double)), 0) << where;
        if (threads == 1) {
            EXPECT_EQ(scatter.triangle_scatter().chunk_count(), 0U);
        } else {
            EXPECT_GT(scatter.triangle_scatter().chunk_count(), 1U) << where;
            EXPECT_GT(scatter.triangle_scatter().deferred_terms(), 1000U) << where << ": random triangles defer many";
        }
    }
}

TEST(EdgeTriangleScatter, EdgeLoopOnThreadsGivesEachVertexAndTheEnergyTheLoopsBits) {
    std::mt19937 rng(23);
    std::uniform_int_distribution<PointId> pick(0, kVertices - 1);
    std::vector<Edge> edges;
    std::vector<detail::EdgeTerms> terms;
    while (edges.size() < 15000) {
        const Edge e{pick(rng), pick(rng)};
        if (e[0] == e[1]) continue;
        edges.push_back(e);
        terms.push_back({random_vec(rng), random_vec(rng) * 1e-3, random_vec(rng)[0] * 1e4});
    }
    std::vector<Vec3> expected = start_values();
    double expected_energy = 0.0;
    for (std::size_t e = 0; e < edges.size(); ++e) {
        expected[static_cast<std::size_t>(edges[e][1])] += terms[e].to_second;
        expected[static_cast<std::size_t>(edges[e][0])] -= terms[e].from_first;
        expected_energy += terms[e].energy;
    }
    detail::EdgeTriangleScatter scatter;
    for (const int threads : {1, 2, 3, 8}) {
        std::vector<Vec3> out = start_values();
        double energy = 0.0;
        tbb::task_arena arena(threads);
        arena.execute([&] { energy = scatter.edge_loop(edges, out, [&](std::size_t e) { return terms[e]; }); });
        const std::string where = std::to_string(threads) + " threads";
        EXPECT_TRUE(same_bits(out, expected)) << where;
        EXPECT_EQ(std::memcmp(&energy, &expected_energy, sizeof(double)), 0) << where;
        if (threads > 1) {
            EXPECT_GT(scatter.edge_scatter().deferred_terms(), 1000U) << where;
        }
    }
    // the edges changed (as many, another order): clear() makes the chunks again
    std::swap(edges.front(), edges.back());
    std::swap(terms.front(), terms.back());
    scatter.clear();
    std::vector<Vec3> out = start_values();
    tbb::task_arena arena(2);
    arena.execute([&] { (void)scatter.edge_loop(edges, out, [&](std::size_t e) { return terms[e]; }); });
    std::vector<Vec3> swapped = start_values();
    for (std::size_t e = 0; e < edges.size(); ++e) {
        swapped[static_cast<std::size_t>(edges[e][1])] += terms[e].to_second;
        swapped[static_cast<std::size_t>(edges[e][0])] -= terms[e].from_first;
    }
    EXPECT_TRUE(same_bits(out, swapped));
}

}  // namespace
}  // namespace penalty
