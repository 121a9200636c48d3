#pragma once
/// @file
/// The map-back stage's plan (private to the simulation stage): after the solve, each node's
/// projective constraints project its positions and velocities, then its mapping maps them from
/// its inputs (SOFA's MechanicalProjectPositionAndVelocityVisitor and
/// MechanicalPropagateOnlyPositionAndVelocityVisitor, depth first). A pile of bodies has a mapped
/// contact-point state per contact pair: thousands of small, independent mappings a step.
///
/// The plan groups the nodes' steps into waves: a step's wave is one after the last wave of any
/// earlier step (depth-first order) that writes a state it reads or writes, or reads a state it
/// writes; a node with a projective constraint (which may read any state) is a wave of its own,
/// after every earlier step and before every later one. The steps of a wave read and write no
/// state another one of the wave writes, so they may run in any order or at once, and every
/// step reads what it reads in depth-first order: the same bits as the sequential pass.

#include "penalty/core/pointer_index.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/simulation/node.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace penalty::detail {

/// Waves of at least this many steps run as TBB tasks when the arena has two threads or more.
inline constexpr std::size_t kMinStepsForConcurrentMapBack = 64;

class MapBackPlan {
public:
    /// Rebuilds the plan when the graph's structure changed since the last build.
    void update(Node& root);
    /// Whether the plan is that of the graph's structure now.
    [[nodiscard]] bool current(const Node& root) const { return version_ == root.structure_version(); }
    /// Every step; the waves' steps as tasks where worth it (concurrent: the calling arena has
    /// two threads or more). An exception is the one the depth-first pass raises first.
    void run(bool concurrent) const;

    [[nodiscard]] std::size_t steps() const { return nodes_.size(); }
    [[nodiscard]] std::size_t waves() const { return wave_first_.empty() ? 0 : wave_first_.size() - 1; }
    /// Wave w's nodes, depth first.
    [[nodiscard]] std::vector<const Node*> wave_nodes(std::size_t w) const;

private:
    void build(Node& root);
    void add_node(Node& node);
    /// The index of `state` in after_writer_ / after_reader_, added (0, 0) when first met.
    std::size_t slot(const BaseState* state);
    /// Runs node `depth_first_index`'s step (constraints, then mapping).
    void run_step(std::size_t depth_first_index) const;

    std::optional<std::uint64_t> version_;
    std::vector<Node*> nodes_;            ///< the nodes with a step, depth first
    std::vector<std::uint32_t> wave_of_;  ///< per step, its wave
    /// Wave w's steps are by_wave_[wave_first_[w] … wave_first_[w + 1]), depth-first indices,
    /// ascending.
    std::vector<std::size_t> wave_first_;
    std::vector<std::uint32_t> by_wave_;
    std::vector<std::size_t> fill_;  ///< build's counting sort
    // build's scratch: per state met, the wave after its last writer and after its last reader
    PointerIndex<BaseState> state_index_;
    std::vector<std::uint32_t> after_writer_, after_reader_;
    std::uint32_t floor_ = 0;      ///< the wave after the last constraint's
    std::uint32_t next_wave_ = 0;  ///< one after the last wave given
};

}  // namespace penalty::detail
