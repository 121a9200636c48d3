#include "blocked_reductions.hpp"

#include "flat_vector_ops.hpp"
#include "subtree_layout.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace penalty::detail {

ReductionBlocks reduction_blocks(const SubtreeLayout& layout, Eigen::Index values_per_block) {
    ReductionBlocks blocks;
    Eigen::Index open = 0;  // values in the block being filled
    const auto close = [&] {
        if (open > 0) blocks.first.push_back(blocks.segments.size());
        open = 0;
    };
    for (std::size_t s = 0; s < layout.independent.size(); ++s) {
        const Eigen::Index width = std::max<Eigen::Index>(1, layout.widths[s]);
        const Eigen::Index begin = layout.offsets[s], size = layout.sizes[s], end = begin + size;
        if (size == 0) continue;
        if (size > values_per_block) {  // a large state: blocks of its own
            close();
            const Eigen::Index step = std::max<Eigen::Index>(1, values_per_block / width) * width;
            for (Eigen::Index b = begin; b < end; b += step) {
                blocks.segments.push_back({b, std::min(end, b + step), width});
                blocks.first.push_back(blocks.segments.size());
            }
            continue;
        }
        if (open + size > values_per_block) close();
        blocks.segments.push_back({begin, end, width});
        open += size;
    }
    close();
    return blocks;
}

namespace {

/// Runs body(k) for every block k, on TBB's threads when there are two blocks or more.
template <class Body>
void for_each_block(std::size_t count, const Body& body) {
    if (count < 2) {
        for (std::size_t k = 0; k < count; ++k) body(k);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k) body(k);
    });
}

double sum_in_order(const std::vector<double>& partials) {
    double total = 0.0;
    for (const double s : partials) total += s;
    return total;
}

}  // namespace

double blocked_dot(const ReductionBlocks& blocks, const double* a, const double* b, std::vector<double>& partials) {
    partials.assign(blocks.count(), 0.0);
    for_each_block(blocks.count(), [&](std::size_t k) {
        double sum = 0.0;
        for (std::size_t s = blocks.first[k]; s < blocks.first[k + 1]; ++s) {
            const ReductionSegment& g = blocks.segments[s];
            sum += state_dot(a, b, g.begin, g.end, g.width);
        }
        partials[k] = sum;
    });
    return sum_in_order(partials);
}

double blocked_update_and_residual(const ReductionBlocks& blocks, double alpha, const double* p, const double* q,
                                   double* x, double* r, std::vector<double>& partials) {
    partials.assign(blocks.count(), 0.0);
    for_each_block(blocks.count(), [&](std::size_t k) {
        double sum = 0.0;
        for (std::size_t s = blocks.first[k]; s < blocks.first[k + 1]; ++s) {
            const ReductionSegment& g = blocks.segments[s];
            for (Eigen::Index j = g.begin; j < g.end; ++j) {
                x[j] += alpha * p[j];
                r[j] -= alpha * q[j];
            }
            sum += state_dot(r, r, g.begin, g.end, g.width);
        }
        partials[k] = sum;
    });
    return sum_in_order(partials);
}

}  // namespace penalty::detail
