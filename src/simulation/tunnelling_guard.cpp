// The tunnelling guard's step (tunnelling_guard.hpp): the stages of Simulation::step with a
// continuous detection of the motion, and in substep / stiffen the undo and the halving.
#include "penalty/simulation/tunnelling_guard.hpp"

#include "penalty/core/error.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "simulation_internal.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace penalty {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

/// What an undo restores: every state's positions, velocities and applied forces, and every live
/// contact field (its contacts, their friction history and pen, the dissipated energy).
struct TunnellingGuard::Snapshot {
    struct StateCopy {
        BaseState* state = nullptr;
        std::vector<Vec3> x3, v3, f3;
        std::vector<RigidFrame> xr;
        std::vector<RigidDeriv> vr, fr;
    };
    std::vector<StateCopy> states;
    std::size_t state_count = 0;
    std::vector<PenaltyForceField*> fields;
    /// A field with damping or friction, or of a pipeline whose Newton iterates rebuild contacts:
    /// a whole copy (its contacts' history, its dissipated energy or its contact list change during
    /// a solve). Otherwise a solve changes only pen and the normal force,
    /// which the next add_force computes again, and the guard only ks and dist: those are kept.
    std::vector<char> whole;
    std::vector<PenaltyForceField> field_copies;
    std::vector<std::vector<std::pair<double, double>>> laws;  ///< per field: (ks, dist) per contact
    std::uint64_t structure_version = 0;
};

const char* tunnelling_mode_name(TunnellingMode mode) {
    switch (mode) {
        case TunnellingMode::off:
            return "off";
        case TunnellingMode::warn:
            return "warn";
        case TunnellingMode::substep:
            return "substep";
        case TunnellingMode::stiffen:
            return "stiffen";
    }
    return "?";
}

std::optional<TunnellingMode> parse_tunnelling_mode(std::string_view name) {
    for (TunnellingMode m :
         {TunnellingMode::off, TunnellingMode::warn, TunnellingMode::substep, TunnellingMode::stiffen})
        if (name == tunnelling_mode_name(m)) return m;
    return std::nullopt;
}

void TunnellingOptions::validate() const {
    if (max_halvings < 1 || max_halvings > 16)
        throw_invalid_argument("tunnelling guard: max_halvings ", max_halvings, " is outside [1, 16]");
    if (!(stiffen_fraction > 0.0 && stiffen_fraction < 1.0))
        throw_invalid_argument("tunnelling guard: stiffen_fraction ", stiffen_fraction, " is outside (0, 1)");
    if (!(max_stiffening >= 1.0) || !std::isfinite(max_stiffening))
        throw_invalid_argument("tunnelling guard: max_stiffening ", max_stiffening, " must be a finite number >= 1");
    if (!(ccd.touch_tolerance > 0.0 && ccd.touch_tolerance < 1.0))
        throw_invalid_argument("tunnelling guard: touch_tolerance ", ccd.touch_tolerance, " is outside (0, 1)");
    if (!(ccd.advance_fraction > 0.0 && ccd.advance_fraction < 1.0))
        throw_invalid_argument("tunnelling guard: advance_fraction ", ccd.advance_fraction, " is outside (0, 1)");
    if (ccd.max_iterations < 1)
        throw_invalid_argument("tunnelling guard: max_iterations ", ccd.max_iterations, " must be >= 1");
}

TunnellingGuard::TunnellingGuard(Simulation& simulation, std::vector<ContactPipeline*> pipelines,
                                 TunnellingOptions options)
    : simulation_(&simulation), pipelines_(std::move(pipelines)), step_start_(std::make_unique<Snapshot>()) {
    for (const ContactPipeline* p : pipelines_)
        if (p == nullptr) throw_invalid_argument("TunnellingGuard: a null pipeline");
    for (ContactPipeline* p : pipelines_) {
        const std::vector<CollisionModel*>& models = p->collision().models();
        ccd_.add_pipeline_pairs(p->intersection(), models);
    }
    set_options(options);
}

TunnellingGuard::~TunnellingGuard() {
    if (simulation_->step_driver() == this) simulation_->set_step_driver(nullptr);
}

void TunnellingGuard::set_options(const TunnellingOptions& options) {
    options.validate();
    options_ = options;
    if (options_.mode == TunnellingMode::off) {
        if (simulation_->step_driver() == this) simulation_->set_step_driver(nullptr);
    } else {
        simulation_->set_step_driver(this);
    }
}

void TunnellingGuard::detect_and_respond(Simulation& sim) {
    // as Simulation::step: every stage's detection, then every stage's response
    sim.detect_contacts();
    sim.respond_to_contacts();
    for (const ContactPipeline* p : pipelines_) {
        report_.detection_seconds += p->last_timings().detection_seconds;
        report_.response_seconds += p->last_timings().response_seconds;
    }
}

void TunnellingGuard::run_step(Simulation& sim, double dt) {
    report_ = TunnellingReport{};
    const auto t0 = Clock::now();
    if (options_.mode == TunnellingMode::warn) {
        // SOFA's stages, untouched; the detection only reads the states
        ccd_.record_start();
        report_.guard_seconds += seconds_since(t0);
        detect_and_respond(sim);
        sim.solve(dt);
        sim.map_back();
        const auto t1 = Clock::now();
        report_.crossings = ccd_.detect(options_.ccd);
        report_.guard_seconds += seconds_since(t1);
        report_.solves = 1;
    } else {
        take_snapshot(*step_start_);  // the step's start: applied forces, and the rewind below
        report_.guard_seconds += seconds_since(t0);
        time_step_of_.clear();
        detect_and_respond(sim);
        const bool stiffen = options_.mode == TunnellingMode::stiffen;
        if (stiffen) stiffen_contacts(dt);
        if (!advance(sim, dt, 0, true, stiffen) && !stiffen) {
            // halving did not stop the body: its springs are too weak for its speed at any step
            // length. The step again from its start, as stiffen makes it.
            rewind_step();
            detect_and_respond(sim);
            stiffen_contacts(dt);
            advance(sim, dt, 0, true, true);
        }
        if (!time_step_of_.empty()) set_contact_time_step(0.0);  // back to each field's own
    }
    for (const Crossing& c : report_.crossings) report_.max_depth = std::max(report_.max_depth, c.depth);
    total_stiffening_energy_ += report_.stiffening_energy;
    sim.end_step(dt);
}

bool TunnellingGuard::advance(Simulation& sim, double h, int depth, bool contacts_current, bool stiffen) {
    if (!contacts_current) {
        const auto t0 = Clock::now();
        restore_applied_forces(*step_start_);
        report_.guard_seconds += seconds_since(t0);
        detect_and_respond(sim);
        if (stiffen) stiffen_contacts(h);
    }
    report_.deepest_halving = std::max(report_.deepest_halving, depth);
    if (depth > 0) set_contact_time_step(h);
    if (snapshots_.size() <= std::size_t(depth)) snapshots_.push_back(std::make_unique<Snapshot>());
    Snapshot& snap = *snapshots_[std::size_t(depth)];
    const auto t0 = Clock::now();
    take_snapshot(snap);
    report_.guard_seconds += seconds_since(t0);
    if (!solve_and_check(sim, h)) {
        keep_solve();
        return true;
    }
    // stiffen: stiffer springs between the crossing surfaces first; then (no contact between
    // them yet: the body moved farther than the alarm distance) halving, whose second half
    // detects at the half step
    if (stiffen) {
        if (retry_stiffer(sim, h, snap)) return true;  // else back at the snapshot
    } else if (depth < options_.max_halvings) {
        undo(snap);
    }
    if (depth < options_.max_halvings) {
        const bool first = advance(sim, 0.5 * h, depth + 1, true, stiffen);
        const bool second = advance(sim, 0.5 * h, depth + 1, false, stiffen);
        return first && second;
    }
    // the deepest level: crossings the guard could not prevent here are kept and reported
    if (stiffen) (void)solve_and_check(sim, h);  // retry_stiffer left the snapshot's state
    keep_solve();
    report_.crossings.insert(report_.crossings.end(), ccd_.crossings().begin(), ccd_.crossings().end());
    return ccd_.crossings().empty();
}

void TunnellingGuard::keep_solve() {
    ++report_.solves;
    report_.stiffened_contacts += attempt_.stiffened_contacts;
    report_.max_stiffening = std::max(report_.max_stiffening, attempt_.max_stiffening);
    report_.stiffening_energy += attempt_.stiffening_energy;
    attempt_ = Attempt{};
}

void TunnellingGuard::undo(const Snapshot& snap) {
    attempt_ = Attempt{};  // what the undone solve's retry changed is undone with it
    report_.prevented += ccd_.crossings().size();
    ++report_.undone_solves;
    const auto t0 = Clock::now();
    restore_snapshot(snap);
    report_.guard_seconds += seconds_since(t0);
}

void TunnellingGuard::undo_stiffening(const Snapshot& snap) {
    attempt_ = Attempt{};
    const auto t0 = Clock::now();
    restore_snapshot(snap);  // the fields as they were (no solve ran since the last undo)
    report_.guard_seconds += seconds_since(t0);
}

void TunnellingGuard::rewind_step() {
    // what the step kept so far is undone: its solves and crossings count as undone and prevented
    const auto t0 = Clock::now();
    report_.undone_solves += report_.solves;
    report_.prevented += report_.crossings.size();
    report_.solves = 0;
    report_.crossings.clear();
    report_.stiffened_contacts = 0;
    report_.max_stiffening = 1.0;
    report_.stiffening_energy = 0.0;
    attempt_ = Attempt{};
    // the scene's own states back to the step's start (the contact-point states the pipelines
    // made are made again by the response); every state of the start still in the graph
    std::vector<const BaseState*> contact_points;
    for (ContactPipeline* p : pipelines_)
        for (const ContactGraphEntry& e : p->graph_entries())
            for (const Node* n : e.point_nodes)
                if (n != nullptr && n->state() != nullptr) contact_points.push_back(n->state());
    std::vector<BaseState*> live;
    detail::for_each_node(simulation_->root(), [&](Node& n) {
        if (n.state() != nullptr) live.push_back(n.state());
    });
    for (std::size_t i = 0; i < step_start_->state_count; ++i) {
        const Snapshot::StateCopy& c = step_start_->states[i];
        if (std::find(live.begin(), live.end(), c.state) == live.end() ||
            std::find(contact_points.begin(), contact_points.end(), c.state) != contact_points.end())
            continue;
        if (auto* v = dynamic_cast<Vec3Object*>(c.state); v && v->position.size() == c.x3.size()) {
            v->position = c.x3;
            v->velocity = c.v3;
            v->external_force = c.f3;
        } else if (auto* r = dynamic_cast<Rigid3Object*>(c.state); r && r->position.size() == c.xr.size()) {
            r->position = c.xr;
            r->velocity = c.vr;
            r->external_force = c.fr;
        }
    }
    if (!time_step_of_.empty()) set_contact_time_step(0.0);
    report_.guard_seconds += seconds_since(t0);
}

bool TunnellingGuard::retry_stiffer(Simulation& sim, double h, const Snapshot& snap) {
    // the surfaces whose features crossed: their contacts' springs were too weak (without a
    // contact between them no stiffness helps: the caller halves)
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    const auto add_pairs = [&] {
        for (const Crossing& c : ccd_.crossings()) {
            const auto key = detail::ordered(c.surface1, c.surface2);
            if (std::find(pairs.begin(), pairs.end(), key) == pairs.end()) pairs.push_back(key);
        }
    };
    add_pairs();
    double factor = 1.0, reached = 1.0;
    while (factor < options_.max_stiffening) {
        undo(snap);
        factor = std::min(options_.max_stiffening, factor * kRetryStiffening);
        // nothing to stiffen, or nothing stiffer than the last try (explicit contacts at their
        // stable bound): the caller halves
        if (stiffen_pairs(pairs, factor, h) == 0 || !(attempt_.max_stiffening > reached)) {
            undo_stiffening(snap);
            return false;
        }
        reached = attempt_.max_stiffening;
        if (!solve_and_check(sim, h)) {
            keep_solve();
            return true;
        }
        add_pairs();
    }
    undo(snap);
    return false;
}

bool TunnellingGuard::solve_and_check(Simulation& sim, double h) {
    auto t0 = Clock::now();
    ccd_.record_start();
    report_.guard_seconds += seconds_since(t0);
    sim.solve(h);
    sim.map_back();
    t0 = Clock::now();
    const bool crossed = !ccd_.detect(options_.ccd).empty();
    report_.guard_seconds += seconds_since(t0);
    return crossed;
}

void TunnellingGuard::set_contact_time_step(double h) {
    // h > 0: each live field's time step h (its own kept the first time it is changed);
    // h = 0: every changed field back to its own
    for (ContactPipeline* p : pipelines_)
        for (const ContactGraphEntry& e : p->graph_entries()) {
            if (e.force_field == nullptr) continue;
            PenaltyForceField& f = e.force_field->field();
            auto it =
                std::find_if(time_step_of_.begin(), time_step_of_.end(), [&](const auto& x) { return x.first == &f; });
            if (it == time_step_of_.end()) {
                if (h == 0.0) continue;
                time_step_of_.emplace_back(&f, f.parameters().time_step);
                it = time_step_of_.end() - 1;
            }
            PenaltyParameters q = f.parameters();
            q.time_step = h > 0.0 ? h : it->second;
            if (q.time_step != f.parameters().time_step) f.set_parameters(q);
        }
}

void TunnellingGuard::take_snapshot(Snapshot& s) {
    s.state_count = 0;
    detail::for_each_node(simulation_->root(), [&](Node& n) {
        BaseState* st = n.state();
        if (st == nullptr) return;
        if (s.states.size() <= s.state_count) s.states.emplace_back();
        Snapshot::StateCopy& c = s.states[s.state_count++];
        c.state = st;
        if (auto* v = dynamic_cast<Vec3Object*>(st)) {
            c.x3 = v->position;
            c.v3 = v->velocity;
            c.f3 = v->external_force;
        } else if (auto* r = dynamic_cast<Rigid3Object*>(st)) {
            c.xr = r->position;
            c.vr = r->velocity;
            c.fr = r->external_force;
        }
    });
    s.fields.clear();
    s.whole.clear();
    std::size_t k = 0;
    for (ContactPipeline* p : pipelines_)
        for (const ContactGraphEntry& e : p->graph_entries()) {
            if (e.force_field == nullptr) continue;
            const PenaltyForceField& f = e.force_field->field();
            const PenaltyParameters& q = f.parameters();
            const bool whole = q.damping != 0.0 || q.friction != FrictionModel::ignored ||
                               q.tangential_damping != 0.0 ||
                               p->keeps_step_start();  // Newton iterates rebuild the contact list
            s.fields.push_back(&e.force_field->field());
            s.whole.push_back(whole ? 1 : 0);
            if (s.field_copies.size() <= k) s.field_copies.emplace_back();
            if (s.laws.size() <= k) s.laws.emplace_back();
            if (whole) {
                s.field_copies[k] = f;
            } else {
                auto& laws = s.laws[k];
                laws.resize(f.size());
                const std::span<const PenaltyContact> c = f.contacts();
                for (std::size_t i = 0; i < c.size(); ++i) laws[i] = {c[i].ks, c[i].dist};
            }
            ++k;
        }
    s.structure_version = simulation_->root().structure_version();
}

void TunnellingGuard::restore_snapshot(const Snapshot& s) {
    PENALTY_DEMAND(s.structure_version == simulation_->root().structure_version());
    for (std::size_t i = 0; i < s.state_count; ++i) {
        const Snapshot::StateCopy& c = s.states[i];
        if (auto* v = dynamic_cast<Vec3Object*>(c.state)) {
            std::copy(c.x3.begin(), c.x3.end(), v->position.begin());
            std::copy(c.v3.begin(), c.v3.end(), v->velocity.begin());
            std::copy(c.f3.begin(), c.f3.end(), v->external_force.begin());
        } else if (auto* r = dynamic_cast<Rigid3Object*>(c.state)) {
            std::copy(c.xr.begin(), c.xr.end(), r->position.begin());
            std::copy(c.vr.begin(), c.vr.end(), r->velocity.begin());
            std::copy(c.fr.begin(), c.fr.end(), r->external_force.begin());
        }
    }
    for (std::size_t k = 0; k < s.fields.size(); ++k) {
        if (s.whole[k]) {
            *s.fields[k] = s.field_copies[k];
            continue;
        }
        PenaltyForceField& f = *s.fields[k];
        const std::span<const PenaltyContact> c = f.contacts();
        if (c.size() != s.laws[k].size())
            throw std::logic_error("TunnellingGuard: a contact field changed its contact list within a solve");
        for (std::size_t i = 0; i < c.size(); ++i)
            if (c[i].ks != s.laws[k][i].first || c[i].dist != s.laws[k][i].second)
                f.set_normal_law(i, s.laws[k][i].first, s.laws[k][i].second);
    }
}

void TunnellingGuard::restore_applied_forces(const Snapshot& start) {
    // the applied forces of the step's start (a state made since: none); the explicit fields add
    // theirs again during the solve
    std::size_t i = 0;
    detail::for_each_node(simulation_->root(), [&](Node& n) {
        BaseState* st = n.state();
        if (st == nullptr) return;
        const Snapshot::StateCopy* c = nullptr;
        if (i < start.state_count && start.states[i].state == st) c = &start.states[i++];
        else
            for (std::size_t k = 0; k < start.state_count && c == nullptr; ++k)
                if (start.states[k].state == st) c = &start.states[k];
        if (auto* v = dynamic_cast<Vec3Object*>(st)) {
            if (c && c->f3.size() == v->external_force.size())
                std::copy(c->f3.begin(), c->f3.end(), v->external_force.begin());
            else std::fill(v->external_force.begin(), v->external_force.end(), Vec3::Zero());
        } else if (auto* r = dynamic_cast<Rigid3Object*>(st)) {
            if (c && c->fr.size() == r->external_force.size())
                std::copy(c->fr.begin(), c->fr.end(), r->external_force.begin());
            else std::fill(r->external_force.begin(), r->external_force.end(), RigidDeriv{});
        }
    });
}

}  // namespace penalty
