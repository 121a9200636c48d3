// The tunnelling guard's stiffening (tunnelling_guard.hpp): the law of one contact
// (StiffeningLaw) and its application to the live contacts, the retries' stiffer springs.
//
// An implicit contact (its field in an ODE solver's subtree, spec §2.1) gets a tangent: its
// stiffness grows, its force at the solve's start is kept. An explicit contact (stored above the
// solvers of its sides) acts with its force at the solve's start only, so a stiffer spring is a
// stronger force there (F = ks'·pen₀, the energy ½·(ks' − ks)·pen₀² added) and is bounded to keep
// symplectic Euler stable: ks' ≤ m/h² (ω·h ≤ 1, m the reduced mass of its contact points); halving
// the solve lets it grow fourfold.
#include "penalty/simulation/tunnelling_guard.hpp"

#include "penalty/mechanics/mechanical_object.hpp"
#include "simulation_internal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty {

// With p_s = f·D, g_s = D − p_s, g = D − pen and the cap p_c = D − g_s/√κ:
//   m(pen) = 1 (pen ≤ p_s), (g_s/g)² (p_s < pen < p_c), κ (pen ≥ p_c)
//   F(pen) = ks·pen, ks·(p_s + g_s²/g − g_s), F(p_c) + κ·ks·(pen − p_c)
//   E(pen) = ½·ks·pen², ½·ks·p_s² + ks·(p_s − g_s)·(pen − p_s) + ks·g_s²·ln(g_s/g),
//            E(p_c) + F(p_c)·(pen − p_c) + ½·κ·ks·(pen − p_c)²
// (dE/dpen = F, dF/dpen = ks·m: tests/simulation/test_tunnelling_guard.cpp checks both by
// finite differences).

double StiffeningLaw::cap_penetration() const {
    const double gs = (1.0 - fraction) * reach;
    return reach - gs / std::sqrt(max_factor);
}

double StiffeningLaw::factor(double pen) const {
    if (!acts(pen)) return 1.0;
    if (pen >= cap_penetration()) return max_factor;
    const double gs = (1.0 - fraction) * reach;
    const double g = reach - pen;
    return (gs / g) * (gs / g);
}

double StiffeningLaw::force(double pen) const {
    if (!acts(pen)) return ks * pen;
    const double ps = fraction * reach, gs = reach - ps;
    const double pc = cap_penetration();
    const auto barrier = [&](double p) { return ks * (ps + gs * gs / (reach - p) - gs); };
    if (pen < pc) return barrier(pen);
    return barrier(pc) + max_factor * ks * (pen - pc);
}

double StiffeningLaw::energy(double pen) const {
    if (!acts(pen)) return 0.5 * ks * pen * pen;
    const double ps = fraction * reach, gs = reach - ps;
    const double pc = cap_penetration();
    const auto barrier = [&](double p) {
        return 0.5 * ks * ps * ps + ks * (ps - gs) * (p - ps) + ks * gs * gs * std::log(gs / (reach - p));
    };
    if (pen < pc) return barrier(pen);
    const double fc = ks * (ps + gs * gs / (reach - pc) - gs);
    return barrier(pc) + fc * (pen - pc) + 0.5 * max_factor * ks * (pen - pc) * (pen - pc);
}

namespace {

/// Whether the solve treats a pair's contacts implicitly: its field lies in an ODE solver's
/// subtree (spec §2.1); otherwise its forces are computed once, at the (sub)step's start.
bool implicit_contact(const ContactGraphEntry& e) {
    for (const Node* n = e.host; n != nullptr; n = n->parent())
        if (n->ode_solver() != nullptr) return true;
    return false;
}

/// u₀ = (x2 − x1)·n of contact c at the current positions; false when its DOFs are out of range.
bool start_gap(const ContactGraphEntry& e, const PenaltyContact& c, double& u0) {
    const auto& x1 = e.point_states[0]->position;
    const auto& x2 = e.point_states[1]->position;
    if (std::size_t(c.m1) >= x1.size() || std::size_t(c.m2) >= x2.size()) return false;
    u0 = (x2[std::size_t(c.m2)] - x1[std::size_t(c.m1)]).dot(c.normal);
    return true;
}

bool usable(const ContactGraphEntry& e) {
    return e.force_field != nullptr && e.contact != nullptr && e.point_states[0] != nullptr &&
           e.point_states[1] != nullptr;
}

}  // namespace

double TunnellingGuard::contact_point_mass(const ContactGraphEntry& e, ContactSide contact_side) {
    const std::size_t side = contact_side == ContactSide::first ? 0 : 1;  // point_nodes, point_states
    constexpr double kInf = std::numeric_limits<double>::infinity();
    if (node_of_version_ != simulation_->root().structure_version()) {
        node_of_.clear();
        detail::for_each_node(simulation_->root(), [&](Node& n) {
            if (n.state() != nullptr) node_of_[n.state()] = &n;
        });
        node_of_version_ = simulation_->root().structure_version();
    }
    // the contact points' own node (an identity side), or their parent: the model's node
    const Node* n = e.point_nodes[side] != nullptr ? e.point_nodes[side]->parent() : nullptr;
    if (n == nullptr) {
        const auto it = node_of_.find(e.point_states[side]);
        if (it == node_of_.end()) return kInf;
        n = it->second;
    }
    if (n->state() != nullptr && n->state()->is_static()) return kInf;
    for (; n != nullptr; n = n->parent())
        if (n->mass() != nullptr && n->state() != nullptr && n->state()->num_dofs() > 0)
            return n->mass()->total_mass() / double(n->state()->num_dofs());
    return kInf;
}

double TunnellingGuard::explicit_stiffness_bound(const ContactGraphEntry& e, double h) {
    const double m1 = contact_point_mass(e, ContactSide::first), m2 = contact_point_mass(e, ContactSide::second);
    const double m = !std::isfinite(m1) ? m2 : !std::isfinite(m2) ? m1 : m1 * m2 / (m1 + m2);
    return std::isfinite(m) && h > 0.0 ? m / (h * h) : 0.0;  // no mass known: no stiffening
}

void TunnellingGuard::stiffen_contacts(double h) {
    for (ContactPipeline* p : pipelines_)
        for (const ContactGraphEntry& e : p->graph_entries()) {
            if (!usable(e)) continue;
            PenaltyForceField& field = e.force_field->field();
            const bool implicit = implicit_contact(e);
            const double bound = implicit ? 0.0 : explicit_stiffness_bound(e, h);
            const std::span<const PenaltyContact> contacts = field.contacts();
            for (std::size_t i = 0; i < contacts.size(); ++i) {
                // NOLINTNEXTLINE(performance-unnecessary-copy-initialization): set_normal_law changes the field's
                const PenaltyContact c = contacts[i];  // a copy
                double u0 = 0.0;
                if (!(c.ks > 0.0) || !start_gap(e, c, u0)) continue;
                const double pen = c.dist - u0;
                const StiffeningLaw law{c.ks, c.dist, options_.stiffen_fraction, options_.max_stiffening};
                if (!law.acts(pen)) continue;
                const double force = law.force(pen);
                double ks = 0.0, dist = c.dist;
                if (implicit) {
                    // the law's tangent at pen: ks'·(dist' − u) with ks'·(dist' − u₀) = F(pen)
                    ks = c.ks * law.factor(pen);
                    dist = u0 + force / ks;
                } else {
                    // the law's secant: the force F(pen) at the start, within the stable bound
                    ks = std::min(force / pen, bound);
                    if (!(ks > c.ks)) continue;
                }
                report_.stiffening_energy += 0.5 * ks * (dist - u0) * (dist - u0) - 0.5 * c.ks * pen * pen;
                field.set_normal_law(i, ks, dist);
                ++report_.stiffened_contacts;
                report_.max_stiffening = std::max(report_.max_stiffening, ks / c.ks);
            }
        }
}

std::size_t TunnellingGuard::stiffen_pairs(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, double factor,
                                           double h) {
    std::size_t count = 0;
    for (ContactPipeline* p : pipelines_)
        for (const ContactGraphEntry& e : p->graph_entries()) {
            if (!usable(e)) continue;
            const std::optional<std::size_t> s1 = ccd_.surface_of(e.contact->model1());
            const std::optional<std::size_t> s2 = ccd_.surface_of(e.contact->model2());
            if (!s1 || !s2 || std::find(pairs.begin(), pairs.end(), detail::ordered(*s1, *s2)) == pairs.end()) continue;
            PenaltyForceField& field = e.force_field->field();
            const bool implicit = implicit_contact(e);
            const double bound = implicit ? 0.0 : explicit_stiffness_bound(e, h);
            const std::span<const PenaltyContact> contacts = field.contacts();
            for (std::size_t i = 0; i < contacts.size(); ++i) {
                // NOLINTNEXTLINE(performance-unnecessary-copy-initialization): set_normal_law changes the field's
                const PenaltyContact c = contacts[i];  // a copy
                double u0 = 0.0;
                if (!(c.ks > 0.0) || !start_gap(e, c, u0)) continue;
                const double pen = c.dist - u0;
                double ks = c.ks * factor;
                if (!implicit) {
                    // a stronger force at the start, within the stable bound: ½·(ks − ks₀)·pen² more stored
                    ks = std::min(ks, bound);
                    if (!(ks > c.ks)) continue;
                    if (pen > 0.0) attempt_.stiffening_energy += 0.5 * (ks - c.ks) * pen * pen;
                    field.set_normal_law(i, ks, c.dist);
                } else if (pen > 0.0) {
                    // the same force at the start, factor times the stiffness: the stored energy
                    // ½·F²/ks drops by ½·F²·(1/ks₀ − 1/ks)
                    const double force = c.ks * pen;
                    attempt_.stiffening_energy += 0.5 * force * force / ks - 0.5 * c.ks * pen * pen;
                    field.set_normal_law(i, ks, u0 + force / ks);
                } else {
                    field.set_normal_law(i, ks, c.dist);
                }
                ++count;
                attempt_.max_stiffening = std::max(attempt_.max_stiffening, ks / c.ks);
            }
        }
    attempt_.stiffened_contacts += count;
    return count;
}

}  // namespace penalty
