#pragma once
/// @file
/// SOFA's TriangularFEMForceFieldOptim: corotational linear-elastic membrane triangles (plane
/// stress, unit thickness), SOFA's fast variant of TriangularFEMForceField. Per triangle (a, b, c),
/// the frame (X along ab, Y in the plane; computeTriangleRotation) of the rest shape gives
/// b = (bx, 0), c = (cx, cy) (TriangleInfo); at each add_force the current frame F is rebuilt and
///   d = (bx − F_X·ab, cx − F_X·ac, cy − F_Y·ac),
///   strain s = (cy·d_bx, bx·d_cy, bx·d_cx − cx·d_bx),
///   stress σ = (μ s₀ + γ(s₀+s₁), μ s₁ + γ(s₀+s₁), ½ μ s₂)·(1/(2 bx cy)),
///   μ = E/(1 + ν), γ = E ν/(1 − ν²),
///   f_b = F_X (cy σ₀ − cx σ₂) + F_Y (cy σ₂ − cx σ₁), f_c = F_X bx σ₂ + F_Y bx σ₁, f_a = −f_b − f_c.
/// add_dforce is the same map on dx in the frame of the last add_force (SOFA's addDForce: the
/// frame's rotation not differentiated, exact at a stress-free shape). E = ½ Σ σ·s (J), the
/// energy of which f is the gradient when the frame is held.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <optional>
#include <vector>

namespace penalty {

struct TriangularFemOptimParameters {
    std::vector<double> young_modulus{5000};  ///< Pa, one per triangle or one for all
    std::vector<double> poisson_ratio{0.45};  ///< one per triangle or one for all
    std::optional<double> rest_scale;         ///< SOFA's restScale when set: rest edges scaled
};

class TriangularFEMForceFieldOptim final : public ForceField<Vec3Types> {
public:
    struct RestTriangle {
        double bx = 0, cx = 0, cy = 0, ss_factor = 0;  ///< SOFA's TriangleInfo
    };
    TriangularFEMForceFieldOptim(Vec3Object& state, const MeshTopology& topology, TriangularFemOptimParameters p)
        : ForceField(state), topology_(&topology), p_(std::move(p)) {}
    /// Rest triangles from the rest positions, frames from the positions (reinit).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] const std::vector<RestTriangle>& rest_triangles() const { return rest_; }
    /// From OrderedScatter::kMinElements triangles on several threads, the force and the product
    /// run on TBB's threads with the bits of one thread; their split as the last of them made it.
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }

private:
    struct Frame {
        Vec3 x = Vec3::UnitX(), y = Vec3::UnitY();
    };
    [[nodiscard]] std::pair<double, double> mu_gamma(std::size_t triangle) const;
    const MeshTopology* topology_;
    TriangularFemOptimParameters p_;
    std::vector<RestTriangle> rest_;
    std::vector<Frame> frame_;  ///< SOFA's TriangleState::frame, updated by add_force
    double energy_ = 0;
    mutable detail::OrderedScatter scatter_;  ///< made again when the triangles change (init clears it)
    std::vector<double> element_energies_;    ///< the force's on threads, summed in triangle order
};

}  // namespace penalty
