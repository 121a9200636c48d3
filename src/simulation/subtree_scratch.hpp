#pragma once
/// @file
/// The numbers a subtree's products keep from one call to the next (private to the simulation
/// stage): which rows each mapped state's readers read, the scratch of the row lists, and whether
/// the external states' work vectors are clear.

#include "blocked_reductions.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penalty::detail {

/// The rows of one mapped state a product maps (SubtreeLayout::dx_readers, same index).
struct DxRows {
    bool restricted = false;  ///< restricted to `rows` (ascending), or every row
    std::vector<std::uint32_t> rows;
    bool found = false;  ///< `restricted` and `rows` found under the current FixedReaders
};

/// The row lists of list_rows_read and find_read_rows.
struct RowLists {
    std::vector<std::uint32_t> listed;  ///< the rows the readers list
    std::vector<std::uint8_t> read;     ///< one flag per DOF
};

struct SubtreeScratch {
    std::vector<DxRows> dx_rows;
    RowLists row_lists;  ///< the calling thread's
    /// Each TBB thread's, for the products that find their rows in chains.
    tbb::enumerable_thread_specific<RowLists> task_row_lists;
    bool external_work_zeroed = false;    ///< the external states' dx and df zeroed since the last compute_force
    bool readers_fixed = false;           ///< a FixedReaders lives
    std::size_t concurrent_products = 0;  ///< products whose chains ran on TBB's threads
    std::size_t concurrent_force_evaluations = 0;  ///< compute_force calls likewise
    std::size_t concurrent_state_passes = 0;       ///< vector passes state by state on TBB's threads
    /// Each independent state's part of a dot product, summed in order after a concurrent pass
    std::vector<double> state_sums;
    /// A piece of a state's unknowns [begin, end) (for_each_piece's tasks, listed at its first
    /// concurrent pass).
    struct StatePiece {
        std::size_t state;
        Eigen::Index begin;
        Eigen::Index end;
    };
    std::vector<StatePiece> state_pieces;
    /// The blocked reductions' blocks (made when they are turned on) and their sums.
    ReductionBlocks reduction_blocks;
    std::vector<double> block_sums;

    /// Back to a new system's numbers for a layout of `mapped` mapped and `independent`
    /// independent states, keeping the capacity of the lists (a build again of the system).
    void reset(std::size_t mapped, std::size_t independent) {
        dx_rows.resize(mapped);
        for (DxRows& r : dx_rows) {
            r.restricted = false;
            r.rows.clear();
            r.found = false;
        }
        external_work_zeroed = false;
        concurrent_products = 0;
        concurrent_force_evaluations = 0;
        concurrent_state_passes = 0;
        state_sums.assign(independent, 0.0);
        state_pieces.clear();
        reduction_blocks.segments.clear();
        reduction_blocks.first.assign(1, 0);
        block_sums.clear();
    }
};

}  // namespace penalty::detail
