#pragma once
/// @file
/// The force steps of a subtree's product split into chains that may run concurrently with the
/// same bits (private to the simulation stage).
///
/// Every step writes the force or df of one or two states: a mass and a force field those they
/// act on, a mapping's Jᵀ its parent (reading its child's, which must be complete), a fused
/// mapping's spread its parent. Two steps are in one chain when they write a common state, and a
/// mapping's parent and child are in one chain. A state's every contribution then comes from the
/// steps of its chain, which runs them in the list's order: each state receives the same
/// additions in the same order as from the sequential loop, whatever runs concurrently. The
/// mappings' J passes (parents before children) split the same way.

#include "subtree_layout.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penalty::detail {

/// The chains of `steps` (the layout's, or the fused block's) with the mappings of `mapped` (the
/// layout's mapping indices whose J the product applies, parents first).
void find_step_chains(const SubtreeLayout& layout, const std::vector<ForceStep>& steps,
                      const std::vector<std::size_t>& mapped, StepChains& chains);

}  // namespace penalty::detail
