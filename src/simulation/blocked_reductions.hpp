#pragma once
// Beyond SOFA (opt-in, `--reduction blocked`, BuildOptions::blocked_reductions): the CG's dot
// products summed in fixed blocks so that they run on several threads and give the same bits at
// any thread count. SOFA sums a dot product as one chain: each state's DOFs in order, the states'
// sums added in turn (flat_vector_ops.hpp state_dot). Here each state is cut into blocks of at most
// kReductionBlockValues values (whole DOFs), consecutive small states share one; a block's sum is
// SOFA's chain over its states, and the total adds the blocks' sums in order. A subtree of one
// block gets SOFA's bits exactly; a larger one differs at rounding level (docs/performance.md,
// "Blocked reductions").
#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace penalty::detail {

struct SubtreeLayout;

/// Values of one block: 4 096 Vec3 DOFs.
inline constexpr Eigen::Index kReductionBlockValues = 12288;

/// A state's values [begin, end), `width` values per DOF.
struct ReductionSegment {
    Eigen::Index begin = 0;
    Eigen::Index end = 0;
    Eigen::Index width = 3;
};

/// The flat vectors in blocks: block k is segments[first[k], first[k + 1]), at most
/// kReductionBlockValues values: a run of whole small states, or a part of a large one.
struct ReductionBlocks {
    std::vector<ReductionSegment> segments;
    std::vector<std::size_t> first{0};
    [[nodiscard]] std::size_t count() const { return first.size() - 1; }
};

/// The blocks of a layout's independent states, in state order.
[[nodiscard]] ReductionBlocks reduction_blocks(const SubtreeLayout& layout,
                                               Eigen::Index values_per_block = kReductionBlockValues);

/// a·b over the blocks: each block's sum (its segments' chains, as SOFA sums states, added from
/// 0; on TBB's threads when there are two blocks or more, into `partials`), then the blocks'
/// sums added in order from 0.
[[nodiscard]] double blocked_dot(const ReductionBlocks& blocks, const double* a, const double* b,
                                 std::vector<double>& partials);

/// x += α·p, r −= α·q over the blocks, and r·r as blocked_dot sums it (the same values of x and r
/// as the serial pass: each entry's own operations).
[[nodiscard]] double blocked_update_and_residual(const ReductionBlocks& blocks, double alpha, const double* p,
                                                 const double* q, double* x, double* r, std::vector<double>& partials);

}  // namespace penalty::detail
