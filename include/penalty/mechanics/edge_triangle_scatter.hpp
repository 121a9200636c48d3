#pragma once
/// @file
/// The edge and triangle loops of the triangle spring fields (TriangularQuadraticSprings,
/// TriangularBiquadraticSprings, TriangularTensorMass) on TBB's threads with the bits of one
/// thread (OrderedScatter). Internal (namespace detail): those fields hold one.
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace penalty::detail {

/// What an edge (v0, v1) of the loop adds: out[v1] += to_second, then out[v0] −= from_first; and
/// its energy (J), added to the loop's sum in edge order.
struct EdgeTerms {
    Vec3 to_second = Vec3::Zero();
    Vec3 from_first = Vec3::Zero();
    double energy = 0.0;
};

/// A field's edge loop and triangle loop (force and product) as one thread runs them, or, from
/// OrderedScatter::kMinElements edges or triangles with more than one thread in the calling
/// arena, in chunks on TBB's threads with each vertex's additions and the energy's in the loop's
/// order: the same bits.
class EdgeTriangleScatter {
public:
    /// The topology changed: the chunks are made again at the next loop.
    void clear() {
        edges_.clear();
        triangles_.clear();
        edge_points_.clear();
    }
    /// For each edge e in order: terms_of(e) → EdgeTerms, added to `out`; returns the energies
    /// summed from 0 in edge order.
    template <class TermsOf>
    double edge_loop(std::span<const Edge> edges, std::span<Vec3> out, const TermsOf& terms_of);
    /// For each triangle t in order: terms_of(t, sink) gives the triangle's terms to `sink`:
    /// sink.add(k, term) and sink.subtract(k, term) add `term` to out[t[k]] or subtract it, each
    /// vertex's terms in the loop's order, at most three a vertex; sink.add_energy(e) adds an
    /// energy term, at most four a triangle. Returns `energy` plus the energy terms, one after
    /// another in triangle order.
    template <class TermsOf>
    double triangle_loop(std::span<const Triangle> triangles, std::span<Vec3> out, double energy,
                         const TermsOf& terms_of);
    [[nodiscard]] const OrderedScatter& edge_scatter() const { return edges_; }
    [[nodiscard]] const OrderedScatter& triangle_scatter() const { return triangles_; }

private:
    struct SlotTerms {
        std::array<Vec3, 3> terms;
        std::uint8_t count = 0;
    };
    struct EnergyTerms {
        std::array<double, 4> terms{};
        std::uint8_t count = 0;
    };
    OrderedScatter edges_;
    OrderedScatter triangles_;
    std::vector<std::array<PointId, 2>> edge_points_;  ///< (v1, v0): the order of an edge's additions
    std::vector<SlotTerms> stored_;                    ///< a deferred triangle vertex's terms
    std::vector<double> edge_energies_;
    std::vector<EnergyTerms> triangle_energies_;
};

/// Four triangles' edge blocks D_k and vertices, in lanes (the product's kernel:
/// src/kernels/mechanics/triangle_edge_blocks.hpp); a last block's unused lanes hold zeros and
/// vertex 0.
struct TriangleEdgeBlock {
    static constexpr std::size_t kWidth = 4;
    using Lanes = std::array<double, kWidth>;
    alignas(32) std::array<Lanes, 27> dfdx{};                  ///< edge k's D(r, c) at 9k + 3r + c
    std::array<std::array<std::int32_t, kWidth>, 3> vertex{};  ///< the triangle's vertices t_0, t_1, t_2
};

/// The product of the fields whose stiffness is one 3×3 block per triangle edge
/// (TriangularQuadraticSprings, TriangularBiquadraticSprings): addDForce, defined in
/// src/mechanics/triangle_edge_blocks.hpp. One thread: the kernel over the blocks packed again
/// after each change (invalidate()); on threads: `scatter`'s triangle loop.
class EdgeBlockProduct {
public:
    /// The blocks changed (a force evaluation, init): packed again at the next one-thread product.
    void invalidate() { current_ = false; }
    template <class PerTriangle>
    void add_dforce(KernelPath path, EdgeTriangleScatter& scatter, const std::vector<Triangle>& triangles,
                    const std::vector<PerTriangle>& data, std::span<Vec3> df, std::span<const Vec3> dx,
                    double k_factor);

private:
    std::vector<TriangleEdgeBlock> blocks_;
    bool current_ = false;
};

template <class TermsOf>
double EdgeTriangleScatter::edge_loop(std::span<const Edge> edges, std::span<Vec3> out, const TermsOf& terms_of) {
    double energy = 0.0;
    if (!OrderedScatter::worth_threads(edges.size())) {
        for (std::size_t e = 0; e < edges.size(); ++e) {
            const EdgeTerms t = terms_of(e);
            out[static_cast<std::size_t>(edges[e][1])] += t.to_second;
            out[static_cast<std::size_t>(edges[e][0])] -= t.from_first;
            energy += t.energy;
        }
        return energy;
    }
    if (edge_points_.size() != edges.size()) {
        edge_points_.resize(edges.size());
        for (std::size_t e = 0; e < edges.size(); ++e) edge_points_[e] = {edges[e][1], edges[e][0]};
        edges_.clear();
    }
    edge_energies_.resize(edges.size());
    scatter_in_order</*Add=*/true>(edges_, std::span<const std::array<PointId, 2>>(edge_points_), out, 1,
                                   [&](std::size_t first, std::size_t end, const DeferredTerms& deferred) {
                                       for (std::size_t e = first; e < end; ++e) {
                                           const EdgeTerms t = terms_of(e);
                                           store_or_apply(deferred, e,
                                                          std::array<Vec3, 2>{t.to_second, Vec3(-t.from_first)},
                                                          [&](std::size_t k, const Vec3& term) {
                                                              out[static_cast<std::size_t>(edge_points_[e][k])] += term;
                                                          });
                                           edge_energies_[e] = t.energy;
                                       }
                                   });
    for (const double e : edge_energies_) energy += e;
    return energy;
}

template <class TermsOf>
double EdgeTriangleScatter::triangle_loop(std::span<const Triangle> triangles, std::span<Vec3> out, double energy,
                                          const TermsOf& terms_of) {
    if (!OrderedScatter::worth_threads(triangles.size())) {
        struct Direct {  // each term straight into out
            Vec3* out;
            Triangle t;
            double energy;
            void add(std::size_t k, const Vec3& term) { out[static_cast<std::size_t>(t[k])] += term; }
            void subtract(std::size_t k, const Vec3& term) { out[static_cast<std::size_t>(t[k])] -= term; }
            void add_energy(double e) { energy += e; }
        };
        for (std::size_t ti = 0; ti < triangles.size(); ++ti) {
            Direct sink{out.data(), triangles[ti], energy};
            terms_of(ti, sink);
            energy = sink.energy;
        }
        return energy;
    }
    // a deferred vertex's terms stored at its slot, the energy terms per triangle
    struct Deferring {
        std::span<Vec3> out;
        const Triangle* t;
        unsigned mask;
        std::array<SlotTerms*, 3> slots;
        EnergyTerms* energies;
        void add(std::size_t k, const Vec3& term) {
            if ((mask >> k) & 1U) {
                SlotTerms& s = *slots[k];
                s.terms[s.count++] = term;
            } else {
                out[static_cast<std::size_t>((*t)[k])] += term;
            }
        }
        void subtract(std::size_t k, const Vec3& term) {
            if ((mask >> k) & 1U) {
                SlotTerms& s = *slots[k];
                s.terms[s.count++] = -term;  // (x − y is x + (−y): the same bits)
            } else {
                out[static_cast<std::size_t>((*t)[k])] -= term;
            }
        }
        void add_energy(double e) { energies->terms[energies->count++] = e; }
    };
    triangle_energies_.resize(triangles.size());
    const auto pass = [&](std::size_t first, std::size_t end, const std::uint8_t* mask) {
        Deferring sink{out, nullptr, 0U, {}, nullptr};
        for (std::size_t ti = first; ti < end; ++ti) {
            sink.t = &triangles[ti];
            sink.mask = mask != nullptr ? mask[ti] : 0U;
            for (std::size_t k = 0; k < 3; ++k)
                if ((sink.mask >> k) & 1U) {
                    sink.slots[k] = &stored_[triangles_.deferred_slot(ti, k)];
                    sink.slots[k]->count = 0;
                }
            sink.energies = &triangle_energies_[ti];
            sink.energies->count = 0;
            terms_of(ti, sink);
        }
    };
    scatter_stored_in_order(triangles_, triangles, stored_, pass, [&out](std::size_t vertex, const SlotTerms& s) {
        for (std::size_t i = 0; i < s.count; ++i) out[vertex] += s.terms[i];
    });
    for (const EnergyTerms& e : triangle_energies_)
        for (std::size_t m = 0; m < e.count; ++m) energy += e.terms[m];
    return energy;
}

}  // namespace penalty::detail
