#pragma once
// Aabb::overlaps (SOFA's proximity cube test: disjoint iff on some axis min1 > max2 + margin or
// min2 > max1 + margin) with its six comparisons combined without a branch, for loops whose
// result the branch predictor cannot guess (the candidate cache's kept keys). The same result as
// overlaps(), a NaN bound never separating: the sums max + m rounded as overlaps() rounds them,
// ordered compares (NaN is false).

#include "penalty/collision/collision_model.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace penalty::detail {

/// The scalar reference: each axis' two tests or-ed, no branch.
[[nodiscard]] inline bool boxes_overlap_branch_free_scalar(const Aabb& a, const Aabb& b, double margin) {
    bool apart = false;
    for (int i = 0; i < 3; ++i) {
        apart |= a.min[i] > b.max[i] + margin;
        apart |= b.min[i] > a.max[i] + margin;
    }
    return !apart;
}

/// With SSE2, two comparisons an instruction: (x, y) of min1 > max2 + m, of min2 > max1 + m, and
/// both z tests; the scalar reference elsewhere.
[[nodiscard]] inline bool boxes_overlap_branch_free(const Aabb& a, const Aabb& b, double margin) {
#if defined(__SSE2__)
    const __m128d m = _mm_set1_pd(margin);
    const __m128d apart_xy =
        _mm_or_pd(_mm_cmpgt_pd(_mm_loadu_pd(a.min.data()), _mm_add_pd(_mm_loadu_pd(b.max.data()), m)),
                  _mm_cmpgt_pd(_mm_loadu_pd(b.min.data()), _mm_add_pd(_mm_loadu_pd(a.max.data()), m)));
    const __m128d apart_z =
        _mm_cmpgt_pd(_mm_setr_pd(a.min[2], b.min[2]), _mm_add_pd(_mm_setr_pd(b.max[2], a.max[2]), m));
    return _mm_movemask_pd(_mm_or_pd(apart_xy, apart_z)) == 0;
#else
    return boxes_overlap_branch_free_scalar(a, b, margin);
#endif
}

}  // namespace penalty::detail
