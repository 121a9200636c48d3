#pragma once
/// @file
/// SOFA's FastTriangularBendingSprings (Volino and Magnenat-Thalmann's linear bending): one
/// bending element per edge shared by exactly two triangles, on the four points A, B (the
/// vertices opposite the edge in the two triangles), C, D (the edge's ends). With the rest
/// weights α (EdgeSpring::setEdgeSpring: α_A = |N_B|/(|N_A| + |N_B|), α_B = |N_A|/(…),
/// α_C = −|N_D|/(|N_C| + |N_D|), α_D = −|N_C|/(…), N_k the corner normals) and the stiffness
/// λ = (2/3)·(h_A + h_B)/(h_A² h_B²)·|CD|·bendingStiffness (h the distances of A and B to the
/// line CD), the bending vector is R = Σ α_k x_k (zero at a flat rest) and
///   E = ½ λ |R|²,  f_k = −λ α_k R,  K = −λ α αᵀ ⊗ I₃ (constant: the force is linear).
/// Elements: in edge order; across an edge, A is in the earlier of its two triangles and B in
/// the later (the later triangle's pass writes the element last, applyTriangleCreation). An
/// element whose |AB|² or |CD|² at rest is at most minDistValidity² is not created.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <vector>

namespace penalty {

class FastTriangularBendingSprings final : public ForceField<Vec3Types> {
public:
    struct Element {
        std::array<Index, 4> vid{};     ///< A, B, C, D
        std::array<double, 4> alpha{};  ///< weights in the bending vector
        double lambda = 0;              ///< N/m
    };
    FastTriangularBendingSprings(Vec3Object& state, const MeshTopology& topology, double bending_stiffness,
                                 double min_dist_validity)
        : ForceField(state), topology_(&topology), stiffness_(bending_stiffness), min_dist_(min_dist_validity) {}
    /// Builds the elements from the rest positions (FastTriangularBendingSprings::reinit).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] const std::vector<Element>& elements() const { return elements_; }

    /// The split of the elements on threads (from OrderedScatter::kMinElements elements and more
    /// than one thread; chunk_count() 0 before a force or product ran on threads).
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }

private:
    using VertexTerms = std::array<Vec3, 4>;  ///< a vertex's four subtractions of one element's product
    const MeshTopology* topology_;
    double stiffness_, min_dist_;
    std::vector<Element> elements_;
    std::vector<std::array<PointId, 4>> points_;  ///< each element's vid, for scatter_
    mutable detail::OrderedScatter scatter_;
    mutable std::vector<VertexTerms> deferred_terms_;  ///< the product's, at OrderedScatter::deferred_slot
    std::vector<double> energies_;                     ///< add_force's per element on threads
    double energy_ = 0;
};

}  // namespace penalty
