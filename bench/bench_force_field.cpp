// PenaltyForceField throughput: add_force / add_dforce / stiffness assembly over 10^3 … 10^6
// contacts on random states, against a plain loop that streams the same arrays (reads every
// field the kernel reads, gathers the same positions, writes the same outputs, no contact math):
// the memory-bandwidth bound. Items = contacts, so the rates read as contacts per second.
//
// Args: {number of contacts, index order (0 = sequential DOFs, 1 = shuffled DOFs)}.
#include "penalty/response/penalty_force_field.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace penalty {
namespace {

struct BenchScene {
    explicit BenchScene(const PenaltyParameters& parameters) : ff(parameters) {}
    Vec3List x1, x2, v1, v2, f1, f2, dx1, dx2;
    PenaltyForceField ff;
};

BenchScene make_scene(std::size_t contacts, bool shuffled, PenaltyParameters parameters = {}) {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    BenchScene s(parameters);
    const std::size_t n = contacts;  // one contact per DOF pair
    auto random_list = [&] {
        Vec3List list(n);
        for (Vec3& v : list) v = Vec3(unit(rng), unit(rng), unit(rng));
        return list;
    };
    s.x1 = random_list();
    s.x2 = random_list();
    s.v1 = random_list();
    s.v2 = random_list();
    s.dx1 = random_list();
    s.dx2 = random_list();
    s.f1.assign(n, Vec3::Zero());
    s.f2.assign(n, Vec3::Zero());
    std::vector<Index> order1(n), order2(n);
    std::iota(order1.begin(), order1.end(), Index{0});
    std::iota(order2.begin(), order2.end(), Index{0});
    if (shuffled) {
        std::shuffle(order1.begin(), order1.end(), rng);
        std::shuffle(order2.begin(), order2.end(), rng);
    }
    s.ff.clear(contacts);
    for (std::size_t i = 0; i < contacts; ++i) {
        const Vec3 normal = Vec3(unit(rng), unit(rng), unit(rng)).normalized();
        // about half of the contacts penetrate
        s.ff.add_contact(DofIndex(order1[i]), DofIndex(order2[i]), ElementIndex(0), ElementIndex(0), normal,
                         unit(rng) + 0.0, 100.0, 0.3, 0.3, 0);
    }
    s.ff.renew_contacts();
    return s;
}

void set_counters(benchmark::State& state) {
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * state.range(0));
}

void BM_AddForce(benchmark::State& state) {
    BenchScene s = make_scene(static_cast<std::size_t>(state.range(0)), state.range(1) != 0);
    for (auto _ : state) {
        s.ff.add_force(s.f1, s.f2, s.x1, s.x2, s.v1, s.v2);
        benchmark::DoNotOptimize(s.f1.data());
        benchmark::ClobberMemory();
    }
    set_counters(state);
}

void BM_AddForceDampingFriction(benchmark::State& state) {
    PenaltyParameters parameters;
    parameters.damping = 1.0;
    parameters.friction = FrictionModel::coulomb;
    parameters.tangential_damping = 1.0;
    BenchScene s = make_scene(static_cast<std::size_t>(state.range(0)), state.range(1) != 0, parameters);
    for (auto _ : state) {
        s.ff.add_force(s.f1, s.f2, s.x1, s.x2, s.v1, s.v2);
        benchmark::DoNotOptimize(s.f1.data());
        benchmark::ClobberMemory();
    }
    set_counters(state);
}

void BM_AddDForce(benchmark::State& state) {
    BenchScene s = make_scene(static_cast<std::size_t>(state.range(0)), state.range(1) != 0);
    s.ff.add_force(s.f1, s.f2, s.x1, s.x2, s.v1, s.v2);
    for (auto _ : state) {
        s.ff.add_dforce(s.f1, s.f2, s.dx1, s.dx2, -1e-4, -1e-2);
        benchmark::DoNotOptimize(s.f1.data());
        benchmark::ClobberMemory();
    }
    set_counters(state);
}

void BM_StiffnessTriplets(benchmark::State& state) {
    BenchScene s = make_scene(static_cast<std::size_t>(state.range(0)), state.range(1) != 0);
    s.ff.add_force(s.f1, s.f2, s.x1, s.x2, s.v1, s.v2);
    TripletList triplets;
    for (auto _ : state) {
        triplets.clear();
        s.ff.add_stiffness_triplets(triplets, 0, 3 * state.range(0));
        benchmark::DoNotOptimize(triplets.data());
    }
    set_counters(state);
}

/// The bandwidth bound for add_force: the same contact records are read (indices, normal, dist,
/// ks) and pen written back, the same positions gathered and the same forces scattered, with one
/// add per contact instead of the contact math.
void BM_StreamingBound(benchmark::State& state) {
    BenchScene s = make_scene(static_cast<std::size_t>(state.range(0)), state.range(1) != 0);
    // a mutable copy of the records, in the same layout as the force field's
    std::vector<PenaltyContact> records(s.ff.contacts().begin(), s.ff.contacts().end());
    for (auto _ : state) {
        for (PenaltyContact& c : records) {
            const Vec3 sum = s.x2[static_cast<std::size_t>(c.m2)] + s.x1[static_cast<std::size_t>(c.m1)];
            c.pen = c.dist + c.ks + sum.x();
            s.f1[static_cast<std::size_t>(c.m1)] -= c.normal;
            s.f2[static_cast<std::size_t>(c.m2)] += c.normal;
        }
        benchmark::DoNotOptimize(records.data());
        benchmark::DoNotOptimize(s.f1.data());
        benchmark::ClobberMemory();
    }
    set_counters(state);
}

void sizes(benchmark::internal::Benchmark* b) {
    for (int order : {0, 1})
        for (int64_t n : {1000, 10000, 100000, 1000000}) b->Args({n, order});
    b->ArgNames({"contacts", "shuffled"});
}

BENCHMARK(BM_StreamingBound)->Apply(sizes);
BENCHMARK(BM_AddForce)->Apply(sizes);
BENCHMARK(BM_AddForceDampingFriction)->Apply(sizes);
BENCHMARK(BM_AddDForce)->Apply(sizes);
BENCHMARK(BM_StiffnessTriplets)->Apply(sizes);

}  // namespace
}  // namespace penalty
