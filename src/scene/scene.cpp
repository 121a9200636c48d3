// Scene: what a built scene offers its users (stepping, states, contacts, energies, roles);
// src/scene/builder/ builds it.
#include "penalty/scene/scene.hpp"

#include "penalty/io/overrides.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/output/contact_records.hpp"
#include "penalty/scene/components.hpp"
#include "scene/builder/scene_builder.hpp"
#include "scene/live_edits.hpp"
#include "scene/topology/topology_runtime.hpp"

#include <algorithm>
#include <chrono>

namespace penalty::scene {

Scene::Scene() : simulation_(std::make_unique<Simulation>()), live_(std::make_unique<LiveEdits>()) {}
Scene::~Scene() {
    topology_runtime_.reset();  // its handlers refer to the components below
    if (contact_phase_) simulation_->remove_contact_stage(*contact_phase_);
    // The Newton hooks call the pipelines (collision_pipelines.cpp): cleared first.
    for (EulerImplicitSolver* s : implicit_solvers_) s->newton.update_geometry = nullptr;
    guard_.reset();      // it holds the pipelines
    pipelines_.clear();  // they remove what they added to the graph
}

double Scene::dt() const { return const_cast<Simulation&>(*simulation_).root().dt(); }

void Scene::step() {
    apply_pending_writes();  // writes of Data after init that SOFA takes at this step (live_writes.cpp)
    timings_ = StepTimings{};
    const auto t0 = std::chrono::steady_clock::now();
    live_->stepping = true;  // the event listener may write Data: they wait for the next step
    try {
        if (topology_runtime_) topology_runtime_->begin_step(simulation_->time());  // AnimateBeginEvent
        live_->update_engines();  // the step reads the states that follow an engine over moving states
        simulation_->step();
        live_->update_engines();  // and so do the writers and Python after it
        if (topology_runtime_) topology_runtime_->end_step(simulation_->time());  // AnimateEndEvent
    } catch (...) {
        live_->stepping = false;
        throw;
    }
    live_->stepping = false;
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // the contact phase adds every detection and response of the step (several when the guard
    // split it); the guard's own time (continuous detection, snapshots) is apart
    if (const TunnellingReport* r = tunnelling_report()) timings_.guard_seconds = r->guard_seconds;
    timings_.solve_seconds =
        std::max(0.0, total - timings_.detection_seconds - timings_.response_seconds - timings_.guard_seconds);
    solver_stats_ = StepSolverStats{};
    for (const EulerImplicitSolver* s : implicit_solvers_) {
        solver_stats_.cg_iterations += s->last_step_cg_iterations();
        solver_stats_.cg_limit_reached = solver_stats_.cg_limit_reached || s->last_step_cg_limit_reached();
        if (s->newton.enabled) {
            solver_stats_.newton_iterations += s->last_newton_iterations();
            solver_stats_.newton_unconverged = solver_stats_.newton_unconverged || !s->last_newton_converged();
        }
    }
    refresh_contacts();
    release_held_gravity();  // a root gravity written after init reaches the other nodes now
}

void Scene::set_tunnelling(const TunnellingOptions& options) {
    options.validate();
    if (options.mode == TunnellingMode::off) {
        guard_.reset();
        return;
    }
    if (simulation_->collision_steps() != 1 || simulation_->integration_steps() != 1)
        throw std::invalid_argument("the tunnelling guard checks single steps, not a MultiStepAnimationLoop's");
    if (guard_) {
        guard_->set_options(options);
        return;
    }
    std::vector<ContactPipeline*> pipelines;
    for (const ScenePipeline& p : pipelines_) pipelines.push_back(p.pipeline.get());
    guard_ = std::make_unique<TunnellingGuard>(*simulation_, std::move(pipelines), options);
}

TunnellingOptions Scene::tunnelling_options() const { return guard_ ? guard_->options() : TunnellingOptions{}; }

const TunnellingReport* Scene::tunnelling_report() const { return guard_ ? &guard_->last_report() : nullptr; }

void Scene::set_blocked_reductions(bool on) {
    options_.blocked_reductions = on;
    for (EulerImplicitSolver* s : implicit_solvers_) s->blocked_reductions = on;
}

std::vector<std::pair<std::string, const EulerImplicitSolver*>> Scene::implicit_solvers() const {
    std::vector<std::pair<std::string, const EulerImplicitSolver*>> out;
    for (std::size_t i = 0; i < implicit_solvers_.size(); ++i)
        out.emplace_back(implicit_solver_paths_[i], implicit_solvers_[i]);
    return out;
}

bool Scene::uses_newton() const {
    return std::any_of(implicit_solvers_.begin(), implicit_solvers_.end(),
                       [](const EulerImplicitSolver* s) { return s->newton.enabled; });
}

void Scene::refresh_contacts() {
    // Same live pairs as the list (same force fields, point states and models, same order)? Then
    // the records stand (no allocation while the pairs stay).
    std::size_t n = 0;
    bool same = true;
    for (const ScenePipeline& p : pipelines_) {
        for (const ContactGraphEntry& e : p.pipeline->graph_entries()) {
            if (e.contact == nullptr || e.force_field == nullptr) continue;
            same = same && n < contacts_.size() && output::is_record_of(contacts_[n], e);
            ++n;
        }
    }
    if (same && n == contacts_.size()) return;
    // a pile's pairs change at most steps, but most stay: their records (and names) are moved
    previous_contacts_.swap(contacts_);
    previous_contact_of_.clear();
    for (std::size_t i = 0; i < previous_contacts_.size(); ++i)
        previous_contact_of_.emplace(previous_contacts_[i].field, i);
    contacts_.clear();
    for (const ScenePipeline& p : pipelines_) {
        for (const ContactGraphEntry& e : p.pipeline->graph_entries()) {
            if (e.contact == nullptr || e.force_field == nullptr) continue;
            const std::size_t at = previous_contact_of_.find(&e.contact->force_field());
            if (at != PointerIndex<PenaltyForceField>::npos && output::is_record_of(previous_contacts_[at], e)) {
                contacts_.push_back(std::move(previous_contacts_[at]));
                continue;
            }
            contacts_.push_back(output::contact_record(e));
        }
    }
}

std::string Scene::role(const io::SceneComponent& component) const {
    const auto it = roles_.find(&component);
    return it == roles_.end() ? std::string() : it->second;
}

const io::SceneComponent* Scene::component_of(const void* built) const {
    const auto it = built_from_.find(built);
    return it == built_from_.end() ? nullptr : it->second;
}

const Node* Scene::node_of(const io::SceneNode& node) const {
    const auto it = nodes_.find(&node);
    return it == nodes_.end() ? nullptr : it->second;
}

double Scene::kinetic_energy() const {
    double e = 0.0;
    for (const BaseMass* m : masses_) e += m->kinetic_energy();
    return e;
}

namespace {
double force_field_energy(const Node& node) {
    double e = 0.0;
    for (const auto& ff : node.force_fields()) e += ff->potential_energy();
    for (const auto& child : node.children()) e += force_field_energy(*child);
    return e;
}
}  // namespace

double Scene::potential_energy() const { return potential_energy_from(stored_energy()); }

double Scene::potential_energy_from(double stored) const {
    double e = stored;
    for (std::size_t i = 0; i < masses_.size(); ++i)
        e += masses_[i]->gravity_potential_energy(mass_nodes_[i]->gravity());
    return e;
}

double Scene::stored_energy() const { return force_field_energy(simulation_->root()); }

double Scene::gravity_energy_scale(const Vec3& lo, const Vec3& hi) const {
    const Vec3 extent = (hi - lo).cwiseAbs();
    double e = 0.0;
    for (std::size_t i = 0; i < masses_.size(); ++i) {
        const auto record = std::find_if(states_.begin(), states_.end(),
                                         [&](const output::StateRecord& r) { return r.state == masses_[i]->state(); });
        if (record == states_.end() || !record->in_solver_subtree) continue;
        const Vec3& g = mass_nodes_[i]->gravity();
        const double g_norm = g.norm();
        if (!(g_norm > 0.0)) continue;
        const double along = (g.cwiseAbs() / g_norm).dot(extent);
        e += masses_[i]->total_mass() * g_norm * (along > 0.0 ? along : extent.norm());
    }
    return e;
}

std::vector<std::string> Scene::warnings() const {
    std::vector<std::string> out = build_warnings_;
    for (const ScenePipeline& p : pipelines_) {
        for (const std::string& s : p.pipeline->skipped_pairs()) out.push_back(p.name + ": " + s);
        for (const std::string& s : p.pipeline->response().warnings()) out.push_back(p.name + ": " + s);
    }
    return out;
}

// ---- entry points: overrides, then the builder (src/scene/builder/) ------------------------------

void apply_overrides(io::SceneFile& file, const std::vector<std::string>& overrides) {
    std::vector<io::Override> parsed;
    parsed.reserve(overrides.size());
    for (const std::string& o : overrides) parsed.push_back(io::parse_override(o));
    const auto reads = [](const io::SceneElement& e, std::string_view attribute) {
        const std::vector<std::string> known = read_attributes(e.type);
        return std::find(known.begin(), known.end(), attribute) != known.end();
    };
    const auto known = [](const io::SceneElement& e) {
        const std::vector<std::string> names = read_attributes(e.type);
        if (names.empty()) return std::string("it reads none");
        std::string out = "it reads:";
        for (const std::string& n : names) out += " " + n;
        return out;
    };
    io::apply_overrides(file, parsed, reads, known);
}

std::unique_ptr<Scene> build_scene(io::SceneFile file, const BuildOptions& options) {
    return Scene::build_from(std::move(file), options, nullptr);
}

std::unique_ptr<Scene> Scene::build_from(io::SceneFile file, const BuildOptions& options, const LiveEdits* carried) {
    std::vector<std::string> notes = apply_sofa_renames(file);  // first: overrides name the new types' Data
    if (!options.overrides.empty()) apply_overrides(file, options.overrides);
    const std::vector<std::string> prefixes = read_number_prefixes(file, options.sofa_quirk_fixes);
    notes.insert(notes.end(), prefixes.begin(), prefixes.end());
    const std::vector<std::string> detached = detach_unresolved_data_links(file);
    notes.insert(notes.end(), detached.begin(), detached.end());
    auto scene = std::make_unique<Scene>();
    scene->file_ = std::move(file);
    scene->options_ = options;
    scene->options_.overrides.clear();  // applied to file_ already
    if (carried != nullptr) {
        scene->live_->box_roi_writes = carried->box_roi_writes;
        scene->live_->rebuilt = true;
    }
    SceneBuilder(scene->file_, options, *scene).build();
    scene->build_warnings_.insert(scene->build_warnings_.end(), notes.begin(), notes.end());
    scene->install_contact_stage();
    scene->refresh_contacts();
    return scene;
}

std::unique_ptr<Scene> load_scene(const std::filesystem::path& file, const BuildOptions& options) {
    return build_scene(io::parse_scene_file(file, options.data_dirs), options);  // data folders: <include>s too
}

}  // namespace penalty::scene
