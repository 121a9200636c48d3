#pragma once
/// @file
/// SOFA's TaitSurfacePressureForceField: a closed surface (triangles, and quads split (0,1,2),
/// (2,3,0)) filled with a fluid of Tait's equation of state,
///   p = p0 − B·((V/V0)^γ − 1),  dp/dV = −B·γ·(V/V0)^γ / V   (γ = 1: p0 − B(V/V0 − 1), −B/V0;
///   B, γ or V0 zero: p = p0, no stiffness),
/// V the enclosed volume (computeMeshVolumeAndArea: Σ ((a − c)×(b − c))·(d − c) / 6 about the mean
/// point c), V0 = the rest volume + the injected volume. The force is p·∇V with
/// ∇V_i = Σ_{t ∋ i} (x1 − x0) × (x2 − x0) / 6; K = (dp/dV)·∇V ∇Vᵀ + p·∂∇V/∂x (addDForce), exact.
/// Injection (handleEvent, AnimateBeginEvent): at the start of each step the injected volume
/// moves toward `injectedVolume` by at most maxInjectionRate·dt.
/// E = −p0 V + B (V^{γ+1}/((γ+1) V0^γ) − V) (γ ≠ 1), of which f is minus the gradient (SOFA: none).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <vector>

namespace penalty {

struct TaitParameters {
    double p0 = 0;                       ///< rest pressure (Pa)
    double bulk_modulus = 0;             ///< B (Pa)
    double gamma = 0;                    ///< Tait exponent
    double injected_volume = 0;          ///< target injected volume (m³)
    double max_injection_rate = 1000;    ///< m³/s
    double current_injected_volume = 0;  ///< the injected volume at the start (m³)
};

class TaitSurfacePressureForceField final : public ForceField<Vec3Types> {
public:
    TaitSurfacePressureForceField(Vec3Object& state, const MeshTopology& topology, TaitParameters p, ContextClock clock,
                                  ContextClock dt);
    /// The pressure triangles and the rest volume (from the rest positions).
    void init() override;
    void add_force(std::span<Vec3> f, std::span<const Vec3> x, std::span<const Vec3> v) override;
    void add_dforce(std::span<Vec3> df, std::span<const Vec3> dx, double k_factor, double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] double rest_volume() const { return initial_volume_; }
    [[nodiscard]] double current_volume() const { return volume_; }
    [[nodiscard]] double current_pressure() const { return pressure_; }
    [[nodiscard]] double injected_volume() const { return current_injected_; }
    [[nodiscard]] const std::vector<Triangle>& triangles() const { return triangles_; }
    /// V of the pressure triangles at positions x (m³).
    [[nodiscard]] double volume_of(std::span<const Vec3> x) const;

private:
    void pressure_and_stiffness(double volume, double v0);
    const MeshTopology* topology_;
    TaitParameters p_;
    ContextClock clock_, dt_;
    std::vector<Triangle> triangles_;
    double initial_volume_ = 0, current_injected_ = 0;
    double volume_ = 0, pressure_ = 0, stiffness_ = 0, energy_ = 0;
    double last_step_time_ = -1e300;  ///< the step whose start updated the injection
    std::vector<Vec3> grad_v_;        ///< ∇V at the last add_force
    std::vector<Vec3> x_;             ///< positions of the last add_force (SOFA's readX in addDForce)
};

}  // namespace penalty
