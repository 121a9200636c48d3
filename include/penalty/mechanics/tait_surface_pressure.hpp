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
/// After a topological change (updateFromTopology, when the topology's revision moved): the
/// pressure triangles are taken again from the topology and V_TC, the volume of the new surface at
/// the rest positions, is kept (volumeAfterTC); addForce then uses V − (V_TC − V_rest) in the
/// equation of state (V0 unchanged: the rest volume of init plus the injected volume). Before any
/// change V_TC = V_rest and the correction is exactly 0.

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
    /// SOFA's updateFromTopology after a topological change: computePressureTriangles from the
    /// topology's current triangles and quads, volumeAfterTC and surfaceAreaAfterTC from the state's
    /// rest positions (which followed the change). The state of the last add_force is dropped.
    void topology_changed();
    /// volumeAfterTC (m³): the rest volume of the surface after the last change (rest_volume()
    /// before any).
    [[nodiscard]] double volume_after_change() const { return volume_after_change_; }
    /// surfaceAreaAfterTC (m²) and initialSurfaceArea: Σ |(b − a)×(c − a)| / 2 at the rest positions.
    [[nodiscard]] double surface_area_after_change() const { return area_after_change_; }
    [[nodiscard]] double rest_surface_area() const { return initial_area_; }

private:
    void pressure_and_stiffness(double volume, double v0);
    /// computePressureTriangles: the triangles, then each quad as (0, 1, 2) and (2, 3, 0).
    void take_pressure_triangles();
    /// computeMeshVolumeAndArea's area at positions x (m²).
    [[nodiscard]] double area_of(std::span<const Vec3> x) const;
    const MeshTopology* topology_;
    TaitParameters p_;
    ContextClock clock_, dt_;
    std::vector<Triangle> triangles_;
    double initial_volume_ = 0, current_injected_ = 0;
    double volume_after_change_ = 0;                   ///< volumeAfterTC (m³)
    double initial_area_ = 0, area_after_change_ = 0;  ///< initialSurfaceArea, surfaceAreaAfterTC (m²)
    double volume_ = 0, pressure_ = 0, stiffness_ = 0, energy_ = 0;
    double last_step_time_ = -1e300;  ///< the step whose start updated the injection
    std::vector<Vec3> grad_v_;        ///< ∇V at the last add_force
    std::vector<Vec3> x_;             ///< positions of the last add_force (SOFA's readX in addDForce)
};

}  // namespace penalty
