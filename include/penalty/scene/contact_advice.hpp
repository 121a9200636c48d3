#pragma once
/// @file
/// `penalty info --contact-advice` (beyond SOFA, docs/no-tunnelling.md, "Advice"): for each model
/// pair a scene's pipelines keep, the largest time step and the smallest contact stiffness at
/// which a body of the scene's masses and impact speed cannot tunnel through the other model, and
/// where the solve of the stiff springs stays stable.

#include "penalty/scene/scene.hpp"

#include <optional>
#include <string>
#include <vector>

namespace penalty::scene {

/// The advice numbers of one model pair (SI units). With v the impact speed, m the mass per
/// contact point (the reduced mass m1·m2/(m1 + m2) when both sides move), D the spring's reach
/// (its rest distance: the contact distances, plus the radii of spheres) and A the alarm distance
/// plus the models' contact distances and radii (how far from the far side a body is first seen):
///   detection   dt ≤ A / v                  a body moving farther than A in a step is not seen
///   energy      ks ≥ m·v² / D²              the spring stores ½·m·v² within its reach
///   implicit    ks ≥ m·(v·dt − D)/(dt²·D)   one implicit Euler step from first contact stops the
///                                           body within D (x₁ = m·(x₀ + dt·v)/(m + dt²·ks), x₀ = 0)
///   explicit    dt ≤ 2·√(m/ks)              a contact stored above the solvers of both sides is
///                                           explicit (§2.1): symplectic Euler's stability limit
///   CG          √(1 + dt²·ks/m)·ln(2/tol)   CG iterations the implicit solve of the spring needs
struct PairAdvice {
    std::string model1, model2;
    double impact_speed = 0.0;      ///< v (m/s)
    double mass = 0.0;              ///< m (kg); +inf when neither side moves
    double reach = 0.0;             ///< D (m)
    double alarm = 0.0;             ///< A (m)
    double ks = 0.0;                ///< the scene's spring stiffness (N/m)
    double dt = 0.0;                ///< the scene's time step (s)
    double max_dt_detection = 0.0;  ///< A / v
    double min_ks_energy = 0.0;     ///< m·v²/D²
    double min_ks_implicit = 0.0;   ///< m·(v·dt − D)/(dt²·D), 0 when v·dt ≤ D
    bool explicit_contact = false;  ///< both sides simulated by different solvers
    double max_dt_explicit = 0.0;   ///< 2·√(m/ks) (explicit contacts)
    double cg_iterations = 0.0;     ///< estimated, implicit contacts
    int cg_limit = 0;               ///< the solver's `iterations` (0: none found)
    /// Whether the scene's dt and ks meet every condition.
    [[nodiscard]] bool safe() const;
};

/// The impact speed `penalty info --contact-advice` assumes without --impact-speed (m/s): the
/// largest initial speed of a moving state plus √(2·|g|·H), H the extent of every state's
/// positions along gravity (the highest fall the scene allows).
[[nodiscard]] double estimated_impact_speed(const Scene& scene);

/// The advice of every model pair the pipelines keep and whose features can tunnel (at least one
/// side simulated), in pipeline and broad-phase order.
[[nodiscard]] std::vector<PairAdvice> contact_advice_pairs(const Scene& scene,
                                                           std::optional<double> impact_speed = std::nullopt);

/// The text `penalty info --contact-advice` prints.
[[nodiscard]] std::string contact_advice(const Scene& scene, std::optional<double> impact_speed = std::nullopt);

}  // namespace penalty::scene
