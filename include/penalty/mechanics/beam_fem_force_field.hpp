#pragma once
/// @file
/// SOFA's BeamFEMForceField<Rigid3d>: each edge (a, b) of the topology is a beam of circular
/// (optionally hollow) section between two frames, with SOFA's 12×12 local stiffness k
/// (BeamFEMForceField::computeStiffness; SOFA sets the shear areas to zero, so the shear
/// parameters φ vanish and the beam is Euler–Bernoulli):
///   axial E A/L, torsion G J/L, bending 12 E I/L³, 6 E I/L², 4 E I/L, 2 E I/L,
///   A = π (r² − r_in²), I_y = I_z = π (r⁴ − r_in⁴)/4, J = I_y + I_z, G = E / (2 (1 + ν)),
///   L the rest length |c_b − c_a|.
/// Large displacements (accumulateForceLarge), in the frame R_a of node a:
///   u = R_a⁻¹ (c_b − c_a) − R_a0⁻¹ (c_b0 − c_a0), θ = rotation vector of qDiff(qDiff(q_b, q_a),
///   qDiff(q_b0, q_a0)) (qDiff(a, b) = b⁻¹ ⊗ ±a, the sign making a·b ≥ 0);
///   F = k · (0, 0, 0, 0, 0, 0, u, θ) (SOFA's Mat × Vec sums of all twelve terms);
///   f_a −= R_a F[0..5], f_b −= R_a F[6..11] (forces then torques, N and N·m).
/// Stiffness (applyStiffnessLarge): df = −R k Rᵀ dx blockwise, R = R_a at the last add_force
/// (the corotational stiffness without the geometric terms, as SOFA). No damping matrix.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"

#include <array>
#include <vector>

namespace penalty {

struct BeamParameters {
    std::vector<double> young_modulus{5000};  ///< Pa, per beam or one for all (SOFA's getYoungModulusInElement)
    std::vector<double> poisson_ratio{0.45};  ///< per beam or one for all
    double radius = 0.1;                      ///< m
    double radius_inner = 0;                  ///< m
    bool symmetric_assembly = false;          ///< SOFA's useSymmetricAssembly (assembled matrix only)
};

class BeamFEMForceField final : public ForceField<Rigid3Types> {
public:
    using Stiffness = Eigen::Matrix<double, 12, 12>;
    BeamFEMForceField(Rigid3Object& state, std::vector<std::array<Index, 2>> beams, BeamParameters p);
    /// Checks the beams and computes each local stiffness from the rest positions.
    void init() override;
    void add_force(std::span<RigidDeriv> f, std::span<const RigidFrame> x, std::span<const RigidDeriv> v) override;
    void add_dforce(std::span<RigidDeriv> df, std::span<const RigidDeriv> dx, double k_factor,
                    double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    /// ½ Σ dᵀ k d over the beams (J), d the local displacement of the last add_force.
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] std::size_t beam_count() const { return beams_.size(); }
    [[nodiscard]] const Stiffness& local_stiffness(std::size_t beam) const { return k_[beam]; }

    /// The split of the beams on threads (from OrderedScatter::kMinElements beams and more than
    /// one thread; chunk_count() 0 before a force or product ran on threads).
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }

private:
    using EndTerms = std::array<Vec3, 2>;  ///< what a beam adds to one end: force (N), torque (N·m)
    /// pass(first, last, deferred mask) over the beams into `out`: one call, or the scatter's
    /// chunks on TBB's threads, the ends the mask marks stored and added in beam order after
    /// (detail::scatter_stored_in_order).
    template <class Pass>
    void scatter_ends_in_order(std::span<RigidDeriv> out, const Pass& pass) const;
    /// Beam `beam`'s terms added to its ends' rows of `out`, or stored where `deferred` marks them.
    void add_end_terms(std::span<RigidDeriv> out, std::size_t beam, unsigned deferred,
                       const std::array<EndTerms, 2>& terms) const;

    std::vector<std::array<Index, 2>> beams_;
    BeamParameters p_;
    std::vector<Stiffness> k_;
    std::vector<Quat> frame_;                   ///< SOFA's beamQuat: q_a normalised at the last add_force
    std::vector<std::array<PointId, 2>> ends_;  ///< beams_ as the scatter's elements
    mutable detail::OrderedScatter scatter_;
    mutable std::vector<EndTerms> deferred_terms_;  ///< at OrderedScatter::deferred_slot
    std::vector<double> energies_;                  ///< add_force's per beam on threads
    double energy_ = 0;
};

}  // namespace penalty
