// A linear tetrahedral FEM's lane blocks and SOFA's element loops over them, by kernel path.
#include "tetrahedron_large_blocks.hpp"

#include "kernels/mechanics/tetrahedron_large_lanes.hpp"

#include <algorithm>
#include <type_traits>
#include <variant>

namespace penalty::detail {

namespace {
/// The block type of a visited alternative of TetrahedronLargeBlocks.
template <class Blocks>
using BlockOf = typename std::remove_cvref_t<Blocks>::value_type;

std::size_t lanes_of(KernelPath path) { return path == KernelPath::avx512 ? 8 : 4; }
}  // namespace

void resize_large_blocks(TetrahedronLargeBlocks& blocks, std::size_t count, KernelPath path) {
    const bool wide = lanes_of(path) == 8;
    if (wide != (blocks.index() == 1)) {
        TetrahedronLargeBlocks moved{std::in_place_index<0>};
        if (wide) moved.emplace<1>();
        std::visit(
            [](auto& to, const auto& from) {
                using To = BlockOf<decltype(to)>;
                using From = BlockOf<decltype(from)>;
                const std::size_t lanes = from.size() * From::kLanes;
                to.resize((lanes + To::kLanes - 1) / To::kLanes);
                for (std::size_t e = 0; e < lanes; ++e)
                    for_each_entry(to[e / To::kLanes], from[e / From::kLanes],
                                   [&](auto& t, const auto& f) { t[e % To::kLanes] = f[e % From::kLanes]; });
            },
            moved, blocks);
        blocks = std::move(moved);
    }
    std::visit(
        [&](auto& b) {
            constexpr std::size_t kLanes = BlockOf<decltype(b)>::kLanes;
            b.resize((count + kLanes - 1) / kLanes);
            if (count % kLanes == 0) return;
            auto& last = b.back();
            for_each_entry(last, last, [&](auto& t, const auto&) {
                std::fill(t.begin() + static_cast<std::ptrdiff_t>(count % kLanes), t.end(), 0.0);
            });
        },
        blocks);
}

bool large_blocks_fit(const TetrahedronLargeBlocks& blocks, std::size_t count, KernelPath path) {
    return std::visit(
        [&](const auto& b) {
            constexpr std::size_t kLanes = BlockOf<decltype(b)>::kLanes;
            return kLanes == lanes_of(path) && b.size() == (count + kLanes - 1) / kLanes;
        },
        blocks);
}

void copy_large_element(TetrahedronLargeBlocks& blocks, std::size_t from, std::size_t to) {
    std::visit(
        [&](auto& b) {
            constexpr std::size_t kLanes = BlockOf<decltype(b)>::kLanes;
            for_each_entry(b[to / kLanes], b[from / kLanes],
                           [&](auto& t, const auto& f) { t[to % kLanes] = f[from % kLanes]; });
        },
        blocks);
}

Mat3 large_block_rotation(const TetrahedronLargeBlocks& blocks, std::size_t e) {
    return std::visit(
        [&](const auto& b) {
            using Block = BlockOf<decltype(b)>;
            const LaneRotation<Block> lane{b[e / Block::kLanes], e % Block::kLanes};
            Mat3 r;
            for (int i = 0; i < 3; ++i)
                for (int k = 0; k < 3; ++k) r(i, k) = lane(i, k);
            return r;
        },
        blocks);
}

void store_large_element(TetrahedronLargeBlocks& blocks, std::size_t e, const TetrahedronMaterial& m,
                         const std::array<Vec3, 4>& q, const Mat3& r) {
    std::visit(
        [&](auto& b) {
            using Block = BlockOf<decltype(b)>;
            Block& block = b[e / Block::kLanes];
            const std::size_t lane = e % Block::kLanes;
            for (Index i = 0; i < 3; ++i) {
                for (Index k = 0; k < 3; ++k) block.material[static_cast<std::size_t>(3 * i + k)][lane] = m(i, k);
                block.shear[static_cast<std::size_t>(i)][lane] = m(i + 3, i + 3);
            }
            store_lane_rotation(block, lane, r);
            for (std::size_t k = 0; k < 4; ++k) {
                const Vec3& p1 = q[(k + 1) % 4];
                const Vec3& p2 = q[(k + 2) % 4];
                const Vec3& p3 = q[(k + 3) % 4];
                const Vec3 xs(p1[0], p2[0], p3[0]), ys(p1[1], p2[1], p3[1]), zs(p1[2], p2[2], p3[2]);
                const double sign = k % 2 == 0 ? -1.0 : 1.0;
                block.cofactor[k][0][lane] = sign * minor_sum(ys, zs);
                block.cofactor[k][1][lane] = -sign * minor_sum(xs, zs);
                block.cofactor[k][2][lane] = sign * minor_sum(xs, ys);
            }
        },
        blocks);
}

double large_blocks_force(TetrahedronLargeBlocks& blocks, KernelPath path,
                          std::span<const std::array<Vec3, 4>> rest_local, std::span<const Tetrahedron> elements,
                          ElementRange range, std::span<Vec3> f, std::span<const Vec3> x, const DeferredTerms& deferred,
                          double* energies) {
#ifdef PENALTY_HAS_AVX_LANES
    if (path != KernelPath::scalar) {
        // avx, and avx512 (whose eight lanes are the product's only): frames, δ and F four
        // elements at a time; the energy and f += Rᵀ·F element by element in order, as below
        return std::visit(
            [&](auto& b) {
                return large_add_force_avx(std::span(b), rest_local, elements, range, x.data(), f.data(), deferred,
                                           energies);
            },
            blocks);
    }
#else
    (void)path;
#endif
    double total = 0.0;
    auto& b = std::get<0>(blocks);  // four lanes off the avx512 path
    using Block = TetrahedronLargeLanes<4>;
    for (std::size_t e = range.first; e < range.end; ++e) {
        // accumulateForceLarge (tetrahedron_large_element.hpp)
        Block& block = b[e / 4];
        const std::size_t lane = e % 4;
        double energy = 0.0;
        Mat3 r;
        const auto vertex = large_vertices(elements[e]);
        const std::array<Vec3, 4> terms =
            large_element_force_terms(vertex, rest_local[e], LaneStrainDisplacement<OneLane, Block>{block, lane},
                                      LaneMaterial<OneLane, Block>{block, lane}, x, energy, r);
        store_lane_rotation(block, lane, r);
        if (energies) energies[e] = energy;
        else total += energy;
        store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) { f[vertex[k]] += term; });
    }
    return total;
}

double per_element_blocks_force(TetrahedronLargeBlocks& blocks, FemMethod method,
                                std::span<const std::array<Vec3, 4>> rest_local, std::span<const Tetrahedron> elements,
                                ElementRange range, std::span<Vec3> f, std::span<const Vec3> x,
                                const DeferredTerms& deferred, double* energies, const ElementRotationOf* rotation_of) {
    // accumulateForceSmall / accumulateForcePolar / accumulateForceSVD
    // (tetrahedron_large_element.hpp), element by element on every path (polar's and svd's
    // product is large's and runs in lanes)
    return std::visit(
        [&](auto& b) {
            using Block = BlockOf<decltype(b)>;
            double total = 0.0;
            for (std::size_t e = range.first; e < range.end; ++e) {
                Block& block = b[e / Block::kLanes];
                const std::size_t lane = e % Block::kLanes;
                const std::array<std::size_t, 4> vertex = large_vertices(elements[e]);
                const LaneStrainDisplacement<OneLane, Block> j{block, lane};
                const LaneMaterial<OneLane, Block> m{block, lane};
                double energy = 0.0;
                std::array<Vec3, 4> terms;
                if (method == FemMethod::Small) {
                    terms = small_element_force_terms(vertex, rest_local[e], j, m, x, energy);
                } else {
                    const Mat3 r =
                        rotation_of != nullptr
                            ? (*rotation_of)({x[vertex[0]], x[vertex[1]], x[vertex[2]], x[vertex[3]]}, e)
                            : polar_rotation(edge_rows(x[vertex[0]], x[vertex[1]], x[vertex[2]], x[vertex[3]]));
                    terms = polar_element_force_terms(vertex, rest_local[e], r, j, m, x, energy);
                    store_lane_rotation(block, lane, r);
                }
                if (energies) energies[e] = energy;
                else total += energy;
                store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) { f[vertex[k]] += term; });
            }
            return total;
        },
        blocks);
}

void large_blocks_dforce(const TetrahedronLargeBlocks& blocks, KernelPath path, std::span<const Tetrahedron> elements,
                         ElementRange range, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                         const DeferredTerms& deferred) {
#ifdef PENALTY_HAS_AVX_LANES
    if (path == KernelPath::avx512) {
        large_dforce_avx512(std::get<1>(blocks).data(), elements, range, df.data(), dx.data(), k_factor, deferred);
        return;
    }
    if (path == KernelPath::avx) {
        large_dforce_avx(std::get<0>(blocks).data(), elements, range, df.data(), dx.data(), k_factor, deferred);
        return;
    }
#else
    (void)path;
#endif
    const auto& b = std::get<0>(blocks);  // four lanes off the avx512 path
    using Block = TetrahedronLargeLanes<4>;
    for (std::size_t e = range.first; e < range.end; ++e) {
        const Block& block = b[e / 4];
        const std::size_t lane = e % 4;
        const LaneRotation<Block> r{block, lane};
        const LaneStrainDisplacement<OneLane, Block> j{block, lane};
        const LaneMaterial<OneLane, Block> m{block, lane};
        const auto vertex = large_vertices(elements[e]);
        const std::array<Vec3, 4> terms = large_element_dforce_terms(vertex, r, j, m, dx, k_factor);
        store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) { df[vertex[k]] -= term; });
    }
}

void small_blocks_dforce(const TetrahedronLargeBlocks& blocks, std::span<const Tetrahedron> elements,
                         ElementRange range, std::span<Vec3> df, std::span<const Vec3> dx, double k_factor,
                         const DeferredTerms& deferred) {
    std::visit(
        [&](const auto& b) {
            using Block = BlockOf<decltype(b)>;
            for (std::size_t e = range.first; e < range.end; ++e) {
                const Block& block = b[e / Block::kLanes];
                const std::size_t lane = e % Block::kLanes;
                const auto vertex = large_vertices(elements[e]);
                const std::array<Vec3, 4> terms =
                    small_element_dforce_terms(vertex, LaneStrainDisplacement<OneLane, Block>{block, lane},
                                               LaneMaterial<OneLane, Block>{block, lane}, dx, k_factor);
                store_or_apply(deferred, e, terms, [&](std::size_t k, const Vec3& term) { df[vertex[k]] -= term; });
            }
        },
        blocks);
}

}  // namespace penalty::detail
