#pragma once
/// @file
/// What the Simulation's files share (private to the simulation stage).

#include "map_back_plan.hpp"
#include "penalty/simulation/simulation.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <utility>

namespace penalty {

/// The TBB arena of a Simulation's concurrent solves and map back, made at the first one, and
/// map back's plan (kept with the arena: only a step with more than one thread needs it).
struct Simulation::ThreadArena {
    explicit ThreadArena(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
    tbb::task_arena arena;
    detail::MapBackPlan map_back_plan;
};

namespace detail {
/// {min(a, b), max(a, b)}: a pair of surfaces as one key whatever their order.
inline std::pair<std::size_t, std::size_t> ordered(std::size_t a, std::size_t b) {
    return {std::min(a, b), std::max(a, b)};
}
/// f(n) for `n` and every node below it, depth first, children in order.
template <class F>
void for_each_node(Node& n, const F& f) {
    f(n);
    for (const auto& c : n.children()) for_each_node(*c, f);
}
}  // namespace detail

}  // namespace penalty
