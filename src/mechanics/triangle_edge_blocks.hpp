#pragma once
// What SOFA's TriangularQuadraticSpringsForceField and TriangularBiquadraticSpringsForceField share:
// vector helpers with SOFA's type::Vec operation order (sofa_vector_ops.hpp), and the derivative
// stored as one 3×3 block DfDx[k] per triangle edge k, for the pair (i, j) = (t_{k+1}, t_{k+2}).
#include "kernels/mechanics/triangle_edge_blocks.hpp"
#include "penalty/core/error.hpp"
#include "penalty/mechanics/edge_triangle_scatter.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/topology.hpp"
#include "sofa_vector_ops.hpp"

#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace penalty::edge_blocks {

using sofa_vec::dot3;
using sofa_vec::scaled;
using sofa_vec::times;
using sofa_vec::transpose_times;

/// The Lamé coefficients of both (updateLameCoefficients): λ = Eν/(1 − ν²), μ = E(1 − ν)/(1 − ν²)
/// (Pa), after the parameters' checks: E finite and ≥ 0, ν finite with ν² ≠ 1, the damping ratio
/// finite (std::invalid_argument naming `component` otherwise).
struct LameCoefficients {
    double lambda = 0.0;
    double mu = 0.0;
};
[[nodiscard]] inline LameCoefficients checked_lame(const char* component, double young_modulus, double poisson_ratio,
                                                   double damping_ratio) {
    if (!std::isfinite(young_modulus) || young_modulus < 0)
        throw_invalid_argument(component, ": youngModulus must be finite and >= 0, got ", young_modulus);
    if (!std::isfinite(poisson_ratio) || poisson_ratio * poisson_ratio == 1.0)
        throw_invalid_argument(component, ": poissonRatio must be finite and not +-1, got ", poisson_ratio);
    if (!std::isfinite(damping_ratio))
        throw_invalid_argument(component, ": dampingRatio must be finite, got ", damping_ratio);
    const double e = young_modulus;
    const double nu = poisson_ratio;
    return {e * nu / (1 - nu * nu), e * (1 - nu) / (1 - nu * nu)};
}

/// std::invalid_argument naming `component` for a triangle's point past the state's `points`.
inline void check_triangle_points(const char* component, const std::vector<Triangle>& triangles, std::size_t points) {
    for (const Triangle& t : triangles)
        for (const PointId v : t)
            if (v < 0 || static_cast<std::size_t>(v) >= points)
                throw_invalid_argument(component, ": point ", v, " out of range for a state of ", points, " points");
}

/// The stiffness of one edge block D between vertex rows i and j (3·vertex + offset):
/// ∂f_i/∂x_i = D, ∂f_i/∂x_j = −D, ∂f_j/∂x_i = −Dᵀ, ∂f_j/∂x_j = Dᵀ.
inline void add_edge_block_triplets(TripletList& t, Index ri, Index rj, const Mat3& m) {
    for (Index r = 0; r < 3; ++r)
        for (Index c = 0; c < 3; ++c) {
            t.emplace_back(ri + r, ri + c, m(r, c));
            t.emplace_back(ri + r, rj + c, -m(r, c));
            t.emplace_back(rj + r, ri + c, -m(c, r));
            t.emplace_back(rj + r, rj + c, m(c, r));
        }
}

/// factor·K as triplets: one edge block factor·DfDx[k] per triangle edge k.
template <class PerTriangle>
void add_stiffness_triplets(const std::vector<Triangle>& triangles, const std::vector<PerTriangle>& data,
                            TripletList& t, Index offset, double factor) {
    for (std::size_t ti = 0; ti < triangles.size(); ++ti) {
        const Triangle& tri = triangles[ti];
        for (int k = 0; k < 3; ++k) {
            const Index ri = offset + 3 * tri[static_cast<std::size_t>((k + 1) % 3)];
            const Index rj = offset + 3 * tri[static_cast<std::size_t>((k + 2) % 3)];
            add_edge_block_triplets(t, ri, rj, factor * data[ti].dfdx[static_cast<std::size_t>(k)]);
        }
    }
}

}  // namespace penalty::edge_blocks

namespace penalty::detail {

/// addDForce: δ = dx_i − dx_j, df_i += (DfDx[k] δ)·k_factor, df_j −= (DfDx[k]ᵀ δ)·k_factor, edge
/// k's pair (i, j) = (t_{k+1}, t_{k+2}); `data[t].dfdx` holds the three blocks of triangle t.
/// From OrderedScatter::kMinElements triangles with more than one thread, in `scatter`'s chunks
/// with the bits of the loop; else the loop itself, by the kernel (detail::triangle_edge_dforce,
/// on `path`'s instructions) over the blocks packed again after each change (invalidate()).
template <class PerTriangle>
void EdgeBlockProduct::add_dforce(KernelPath path, EdgeTriangleScatter& scatter, const std::vector<Triangle>& triangles,
                                  const std::vector<PerTriangle>& data, std::span<Vec3> df, std::span<const Vec3> dx,
                                  double k_factor) {
    PENALTY_DEMAND(data.size() == triangles.size());
    if (!OrderedScatter::worth_threads(triangles.size())) {
        if (!current_) {
            size_triangle_edge_blocks(blocks_, triangles.size());
            for (std::size_t ti = 0; ti < triangles.size(); ++ti)
                set_triangle_edge_lane(blocks_, ti, triangles[ti], data[ti].dfdx);
            current_ = true;
        }
        triangle_edge_dforce(path, blocks_, triangles.size(), df.data(), dx.data(), k_factor);
        return;
    }
    // the same terms, vertex slots (k + 1, k + 2) of each edge k
    (void)scatter.triangle_loop(triangles, df, 0.0, [&](std::size_t ti, auto& terms) {
        const Triangle& t = triangles[ti];
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t i = (k + 1) % 3;
            const std::size_t j = (k + 2) % 3;
            const Vec3 delta = dx[static_cast<std::size_t>(t[i])] - dx[static_cast<std::size_t>(t[j])];
            const Mat3& m = data[ti].dfdx[k];
            terms.add(i, sofa_vec::scaled(sofa_vec::times(m, delta), k_factor));
            terms.subtract(j, sofa_vec::scaled(sofa_vec::transpose_times(m, delta), k_factor));
        }
    });
}

}  // namespace penalty::detail
