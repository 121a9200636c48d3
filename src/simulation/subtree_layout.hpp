#pragma once
/// @file
/// The const layout of a solver subtree's system (private to the simulation stage): the states,
/// masses, force fields, mappings and constraints one solve touches, the independent states'
/// offsets in the flat vectors, and the order of the force contributions. Built when the graph's
/// structure changes (SubtreeSystemCache), only read by the solve; the numbers a product needs
/// from one call to the next are in SubtreeScratch.

#include "penalty/core/pointer_index.hpp"
#include "penalty/simulation/node.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace penalty::detail {

/// One contribution to the forces, in the system's order: a node's mass (with its node's
/// gravity), a force field, or a mapped node's Jᵀ into its parent.
struct ForceStep {
    BaseMass* mass = nullptr;               ///< with `gravity`; or
    BaseForceField* force_field = nullptr;  ///< or
    BaseMapping* mapping = nullptr;
    std::size_t mapping_index = 0;  ///< of `mapping` in SubtreeLayout::mappings
    /// Index of `force_field` in the fused block's fields or of `mapping` in its mappings;
    /// -1: not fused (FusedContactBlock)
    std::ptrdiff_t fused = -1;
    Vec3 gravity = Vec3::Zero();
};

/// Who reads a mapped state's dx in the subtree: the force fields acting on it and the mappings
/// from it. When its mapping can map selected rows (BaseMapping::maps_selected_rows) and every
/// reader can tell which DOFs it reads (and so writes in df), a product maps dx only in those
/// rows, zeroes df only there and takes Jᵀ over them: the other rows' dx is read by nobody,
/// their df would be +0, and the rows kept get the same operations (same bits).
struct DxReaders {
    BaseMapping* mapping = nullptr;
    bool selective = false;  ///< mapping->maps_selected_rows()
    std::vector<const BaseForceField*> force_fields;
    std::vector<const BaseMapping*> mappings;
};

/// Per external state: the subtree's force fields acting on it and the mappings reading it.
struct ExternalReaders {
    std::vector<const BaseForceField*> force_fields;
    std::vector<const BaseMapping*> mappings;
};

/// A product's force steps and mappings' J passes split into chains of disjoint written states
/// (step_chains.hpp).
struct StepChains {
    /// Chain c's steps are steps_of[step_first[c] … step_first[c + 1]), indices into the step
    /// list, ascending.
    std::vector<std::size_t> step_first;
    std::vector<std::uint32_t> steps_of;
    /// Chain c's mappings (J passes) are mappings_of[mapping_first[c] … mapping_first[c + 1]),
    /// indices into SubtreeLayout::mappings, in the pass list's order (parents first).
    std::vector<std::size_t> mapping_first;
    std::vector<std::uint32_t> mappings_of;
    [[nodiscard]] std::size_t size() const { return step_first.empty() ? 0 : step_first.size() - 1; }
    [[nodiscard]] std::size_t largest() const;  ///< steps of the longest chain
};

/// What a SubtreeSystem is made of.
struct SubtreeLayout {
    // independent states, concatenated in depth-first order of their nodes
    std::vector<BaseState*> independent;
    std::vector<Index> offsets;  ///< scalar offset of each in the flat vectors
    /// scalar_size() and deriv_size() of each when the layout was built (the CG's passes read
    /// them for every state and iteration; a size change makes the cache build again)
    std::vector<Index> sizes;
    std::vector<Index> widths;
    PointerIndex<BaseState> independent_index;  ///< each independent state's place in `independent`
    Eigen::Index size = 0;
    /// The scalar offset of `s` in the flat vectors, or `size` when it is not independent.
    [[nodiscard]] Index offset_of(const BaseState* s) const {
        const std::size_t i = independent_index.find(s);
        return i == PointerIndex<BaseState>::npos ? static_cast<Index>(size) : offsets[i];
    }
    [[nodiscard]] bool is_independent(const BaseState* s) const { return independent_index.contains(s); }
    // mapped states and their mappings, pre-order: parents before children (J·dx)
    std::vector<BaseState*> mapped;
    std::vector<BaseMapping*> mappings;
    std::vector<DxReaders> dx_readers;      ///< one per mappings entry, same order
    std::vector<std::size_t> all_mappings;  ///< 0 … mappings.size() − 1: a product's J passes
    /// states used by the subtree's force fields and mappings but outside it, with their readers
    std::vector<BaseState*> external;
    std::vector<ExternalReaders> external_readers;
    std::vector<std::pair<BaseMass*, Vec3>> masses;  ///< with the gravity of their node
    std::vector<BaseForceField*> force_fields;
    std::vector<BaseProjectiveConstraint*> constraints;
    /// The contributions in the order computeForce, addMBKv and the CG's product sum them:
    /// SOFA's visitors' (MechanicalComputeForceVisitor: top-down a node's mass then its force
    /// fields; bottom-up, post-order, a mapped node's Jᵀ) or SOFA HEAD's MappingGraph's
    /// (mapping_graph_order).
    std::vector<ForceStep> steps;
    /// steps and all_mappings in chains (find_step_chains).
    StepChains chains;

    /// Empties the layout for another build, keeping the capacity of every list, and the reader
    /// entries with their lists (build_subtree_layout sizes and refills them): a pile of bodies
    /// builds its solver's layout again at nearly every step, as contacts come and go.
    void clear();
};

/// Builds the layout of the subtree of `root` (into `layout`, cleared first); std::invalid_argument for a mapping whose
/// output is not its node's state and for a mass on a mapped state.
void build_subtree_layout(Node& root, bool mapping_graph_order, SubtreeLayout& layout);

/// The order of SOFA HEAD's MappingGraph (EulerImplicitSolver::solve →
/// MappingGraphMechanicalOperations) for the subtree of `root`: force fields and masses by
/// component group (one group per distinct list of states acted on, groups in order of first
/// appearance, members in visiting order), then every mapping's Jᵀ in the reverse of the graph's
/// breadth-first order (MappingGraphAlgorithms::traverseBottomUp: siblings last first), from the
/// visitors' order `steps` (mapping_graph_order.cpp). The CG's product uses it too: measured,
/// not read in SOFA's code, whose GraphScatteredMatrix::apply calls MechanicalOperations::addMBKdx
/// (visitors); with the visitors' order for the product, AdvancedSolversMultipleGroupsSolver
/// parts from SOFA at step 20, with this order it is bit for bit over 300 steps
/// (docs/sofa-compatibility.md).
void order_as_mapping_graph(Node& root, const std::vector<BaseMapping*>& mappings, std::vector<ForceStep>& steps);

}  // namespace penalty::detail
