#pragma once
/// @file
/// The tunnelling guard (beyond SOFA, opt-in; docs/no-tunnelling.md): penalty contact that says
/// when a body passed through another during a step, and, on request, prevents it.
///
/// A StepDriver of the Simulation. Each step it records the collision models' positions at its
/// start, runs SOFA's stages, and checks the step's motion with continuous detection
/// (collision/ccd_detection.hpp) over the model pairs its pipelines' broad phases keep. Modes:
///   off      no guard (SOFA's step; the scene builder installs none);
///   warn     report only: the stages run exactly as without a guard (the same bits);
///   substep  a solve whose motion has a crossing is undone (every state's positions, velocities
///            and applied forces, every live contact field) and redone as two solves of half the
///            step, the second after a detection at the half step; recursively, at most
///            max_halvings deep (2^max_halvings solves of dt/2^max_halvings). Outputs see the
///            user's dt: one step() is one step. A step without crossing is SOFA's step, bit for
///            bit. A crossing left at the deepest level (the springs cannot stop the body within
///            their reach at any step length) rewinds the whole step to its start and makes it
///            again as stiffen does;
///   stiffen  after each response, contacts whose penetration exceeds stiffen_fraction of their
///            rest distance get the stiffening law (below). A solve with a crossing anyway is
///            undone and retried with the springs between the crossing surfaces 10, 100, …
///            times stiffer (up to max_stiffening; force kept at the start, so only the stiffness
///            changes), then, if that fails or they had no contact at the start (the body moved
///            farther than the alarm distance), redone in halves as by substep.
///
/// The stiffening law (StiffeningLaw): with D the contact's rest distance (pen = D when the two
/// contact points meet along n: the far side), p_s = f·D, g_s = D − p_s and g = D − pen, the
/// normal force is
///     F(pen) = ks·pen                               pen ≤ p_s
///     F(pen) = ks·(p_s + g_s²/g − g_s)              p_s < pen < p_c      (stiffness ks·(g_s/g)²)
///     F(pen) = F(p_c) + κ·ks·(pen − p_c)            pen ≥ p_c,  p_c = D − g_s/√κ
/// a stiffness that grows as (g_s/g)² toward the far side (a barrier, as IPC's, but bounded by
/// κ = max_stiffening). Within a step the contact is the law's tangent at the step's start
/// penetration p₀ (the solve is linear in the springs): ks' = ks·m(p₀), dist' = u₀ + F(p₀)/ks'
/// (u₀ = (x2 − x1)·n at the start), so the force is continuous at p₀ and the implicit solve sees
/// the stiffer spring. The stored energy of the tangent, ½·F(p₀)²/ks', differs from SOFA's
/// ½·ks·p₀² at the same positions: the difference is booked as stiffening_energy (J; negative:
/// removed), so that kinetic + potential + dissipated − stiffening energy is the energy balance.

#include "penalty/collision/ccd_detection.hpp"
#include "penalty/simulation/contact_pipeline.hpp"
#include "penalty/simulation/simulation.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace penalty {

enum class TunnellingMode : std::uint8_t { off, warn, substep, stiffen };

/// "off", "warn", "substep", "stiffen".
[[nodiscard]] const char* tunnelling_mode_name(TunnellingMode mode);
/// The mode named `name` (as tunnelling_mode_name), or nullopt.
[[nodiscard]] std::optional<TunnellingMode> parse_tunnelling_mode(std::string_view name);

/// The stiffening law of one contact (see the file comment). Units: m, N/m, N, J.
struct StiffeningLaw {
    double ks = 0.0;          ///< the contact's stiffness (N/m)
    double reach = 0.0;       ///< D: its rest distance dist (m), > 0 for the law to act
    double fraction = 0.5;    ///< f in (0, 1)
    double max_factor = 1e4;  ///< κ ≥ 1

    /// Whether the law changes anything at penetration `pen` (pen > f·D, D > 0).
    [[nodiscard]] bool acts(double pen) const { return reach > 0.0 && pen > fraction * reach; }
    /// m(pen) = dF/dpen / ks: 1 below p_s, (g_s/g)² up to κ, κ beyond.
    [[nodiscard]] double factor(double pen) const;
    /// F(pen) (N), > 0 pushes the contact points apart.
    [[nodiscard]] double force(double pen) const;
    /// E(pen) = ∫₀^pen F (J).
    [[nodiscard]] double energy(double pen) const;
    /// p_c, where the factor reaches κ (m).
    [[nodiscard]] double cap_penetration() const;
};

struct TunnellingOptions {
    TunnellingMode mode = TunnellingMode::off;
    /// substep, stiffen: a step is split into at most 2^max_halvings solves (1 … 16).
    int max_halvings = 6;
    /// stiffen: f, the fraction of the rest distance beyond which a contact is stiffened (0, 1).
    double stiffen_fraction = 0.5;
    /// κ: the largest stiffness factor of the law (≥ 1).
    double max_stiffening = 1e4;
    CcdOptions ccd;
    /// Throws std::invalid_argument naming the option out of range.
    void validate() const;
};

/// What the guard saw in the last step.
struct TunnellingReport {
    /// Crossings of the step's accepted motion (warn: every crossing; substep, stiffen: those the
    /// guard could not prevent), sorted by toi within each solve, solves in time order.
    std::vector<Crossing> crossings;
    std::size_t prevented = 0;           ///< crossings found by solves the guard undid
    double max_depth = 0.0;              ///< over `crossings` (m)
    int solves = 0;                      ///< solves kept to make the step (1: the user's dt)
    int undone_solves = 0;               ///< solves undone
    int deepest_halving = 0;             ///< the step's shortest solve was dt / 2^deepest_halving
    std::size_t stiffened_contacts = 0;  ///< contact springs given the stiffening law (every solve)
    double max_stiffening = 1.0;         ///< largest ks'/ks applied
    double stiffening_energy = 0.0;      ///< J, this step (see the file comment)
    double detection_seconds = 0.0;      ///< Σ of the pipelines' detections of the step
    double response_seconds = 0.0;       ///< Σ of their responses
    double guard_seconds = 0.0;          ///< continuous detection, snapshots and restores
};

class TunnellingGuard final : public StepDriver {
public:
    /// The factor of each retry with stiffer springs (retry_stiffer).
    static constexpr double kRetryStiffening = 10.0;
    /// Guards `simulation`, whose contact stages include `pipelines`: the model pairs their broad
    /// phases keep are tested. Installs itself as the simulation's step driver unless the mode is
    /// off. Throws std::invalid_argument for invalid options or a null pipeline.
    TunnellingGuard(Simulation& simulation, std::vector<ContactPipeline*> pipelines, TunnellingOptions options);
    ~TunnellingGuard() override;
    TunnellingGuard(const TunnellingGuard&) = delete;
    TunnellingGuard& operator=(const TunnellingGuard&) = delete;

    /// Changes the options (off: uninstalls the driver; otherwise installs it).
    void set_options(const TunnellingOptions& options);
    [[nodiscard]] const TunnellingOptions& options() const { return options_; }
    void run_step(Simulation& simulation, double dt) override;
    [[nodiscard]] const TunnellingReport& last_report() const { return report_; }
    /// Cumulative stiffening energy since construction (J).
    [[nodiscard]] double total_stiffening_energy() const { return total_stiffening_energy_; }
    [[nodiscard]] const ContinuousDetection& detection() const { return ccd_; }

    struct Snapshot;  // tunnelling_guard.cpp

private:
    void detect_and_respond(Simulation& sim);
    /// One solve of length h from the current state (its contacts detected now unless
    /// `contacts_current`), checked; while it has crossings: (stiffen) retried with stiffer
    /// springs, then undone and split in halves while depth < max_halvings. Returns whether the
    /// kept motion has no crossing.
    bool advance(Simulation& sim, double h, int depth, bool contacts_current, bool stiffen);
    /// Undoes everything the step did: the scene's states back to the step's start (the
    /// pipelines' contact-point states follow at the next response).
    void rewind_step();
    /// Solves h, map back, continuous detection; returns whether the motion had crossings.
    bool solve_and_check(Simulation& sim, double h);
    /// Gives the live contacts whose penetration exceeds the fraction the stiffening law, for a
    /// solve of length h (tunnelling_stiffening.cpp).
    void stiffen_contacts(double h);
    /// Counts the last solve as kept (with what its retry stiffened).
    void keep_solve();
    /// Undoes the last solve (back to `snap`), counting its crossings as prevented.
    void undo(const Snapshot& snap);
    /// Back to `snap` after a stiffening without a solve (nothing counted).
    void undo_stiffening(const Snapshot& snap);
    /// After a solve with crossings: undone and solved again with the springs between the
    /// crossing surfaces kRetryStiffening, kRetryStiffening², … times stiffer (up to
    /// max_stiffening), until no crossing. Returns false, the state back at `snap`, when that
    /// does not remove them (or the surfaces have no contact).
    bool retry_stiffer(Simulation& sim, double h, const Snapshot& snap);
    /// Multiplies the stiffness of every live contact between the surfaces of `pairs` by
    /// `factor` for a solve of length h (its force at the current positions kept; an explicit
    /// contact's bounded as in the file comment); returns how many changed.
    std::size_t stiffen_pairs(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, double factor, double h);
    /// The mass (kg) a contact point of `side` of `e` carries: its parent body's mass per DOF
    /// (+inf for a state outside every solver's subtree).
    double contact_point_mass(const ContactGraphEntry& e, ContactSide side);
    /// The largest stiffness an explicit contact of `e` may have in a solve of length h (N/m):
    /// m/h² with m the reduced mass of its sides (ω·h ≤ 1, half of symplectic Euler's limit).
    double explicit_stiffness_bound(const ContactGraphEntry& e, double h);
    /// h > 0: every live contact field's time step (friction, damping) set to h, the field's own
    /// kept; h = 0: the fields changed this step given their own back.
    void set_contact_time_step(double h);
    void take_snapshot(Snapshot& s);
    void restore_snapshot(const Snapshot& s);
    /// Every state's applied (external) forces as at the step's start (0 for a state made since).
    void restore_applied_forces(const Snapshot& start);

    Simulation* simulation_;
    std::vector<ContactPipeline*> pipelines_;
    TunnellingOptions options_;
    ContinuousDetection ccd_;
    TunnellingReport report_;
    double total_stiffening_energy_ = 0.0;
    std::vector<std::unique_ptr<Snapshot>> snapshots_;                 ///< one per depth, reused
    std::unique_ptr<Snapshot> step_start_;                             ///< the step's start (its applied forces)
    std::vector<std::pair<PenaltyForceField*, double>> time_step_of_;  ///< fields' own time steps (this step)
    std::unordered_map<const BaseState*, Node*> node_of_;              ///< contact_point_mass's, at node_of_version_
    std::uint64_t node_of_version_ = ~std::uint64_t(0);
    /// What retry_stiffer changed for the solve under way (kept with it, or undone with it).
    struct Attempt {
        std::size_t stiffened_contacts = 0;
        double max_stiffening = 1.0;
        double stiffening_energy = 0.0;
    } attempt_;
};

}  // namespace penalty
