#include "penalty/scene/runner.hpp"

#include "penalty/output/output_file.hpp"

#include "penalty/io/error.hpp"
#include "penalty/output/format.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/output/vtk_writer.hpp"
#include "penalty/simulation/solver.hpp"

#include <Eigen/Geometry>
#include "penalty/scene/viewer.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace penalty::scene {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Whether the n doubles at x are all finite: x·0 is 0 for a finite x and NaN otherwise, and a
/// sum with a NaN term is NaN. Four independent sums, so the compiler keeps them in vector lanes
/// (one multiply and one add a value, against a compare and a branch for each).
bool all_finite(const double* x, std::size_t n) {
    double acc[4] = {0.0, 0.0, 0.0, 0.0};
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
        for (std::size_t k = 0; k < 4; ++k) acc[k] += x[i + k] * 0.0;
    for (; i < n; ++i) acc[0] += x[i] * 0.0;
    return acc[0] + acc[1] + acc[2] + acc[3] == 0.0;
}

bool all_finite(const std::vector<Vec3>& v) { return v.empty() || all_finite(v.data()->data(), 3 * v.size()); }

/// The largest |x[i] − y[i]| over n ≥ 1 doubles (Eigen's vectorized reduction). With a NaN
/// difference the result is unspecified, but check_finite_states has run first.
double largest_change(const double* x, const double* y, std::size_t n) {
    using Array = Eigen::Map<const Eigen::ArrayXd>;
    return (Array(x, Eigen::Index(n)) - Array(y, Eigen::Index(n))).abs().maxCoeff();
}

/// Whether a step may move the state: it is in an ODE solver's subtree or a mapping's output.
/// The others (static obstacles) keep their positions and velocities unless code run between
/// the steps changes them (RunOptions::states_change_between_steps).
bool moved_by_steps(const output::StateRecord& r) { return r.mapped || r.in_solver_subtree; }

/// Throws when a state holds a NaN or an infinite position (the run diverged). `static_states`:
/// false skips the states no step moves (moved_by_steps).
void check_finite_states(const Scene& scene, std::int64_t step, double time, bool static_states = true) {
    for (const output::StateRecord& r : scene.states()) {
        if (!static_states && !moved_by_steps(r)) continue;
        std::optional<std::size_t> bad;
        if (const auto* v = dynamic_cast<const Vec3Object*>(r.state)) {
            if (all_finite(v->position) && all_finite(v->velocity)) continue;  // the common case, in one pass
            for (std::size_t i = 0; i < v->position.size() && !bad; ++i)
                if (!v->position[i].allFinite() || !v->velocity[i].allFinite()) bad = i;
        } else if (const auto* g = dynamic_cast<const Rigid3Object*>(r.state)) {
            for (std::size_t i = 0; i < g->position.size() && !bad; ++i)
                if (!g->position[i].center.allFinite() || !g->position[i].orientation.coeffs().allFinite() ||
                    !g->velocity[i].linear.allFinite() || !g->velocity[i].angular.allFinite())
                    bad = i;
        } else if (const auto* s = dynamic_cast<const Vec1Object*>(r.state)) {
            for (std::size_t i = 0; i < s->position.size() && !bad; ++i)
                if (!std::isfinite(s->position[i]) || (i < s->velocity.size() && !std::isfinite(s->velocity[i])))
                    bad = i;
        }
        if (bad) {
            throw output::NonFiniteValueError("simulation diverged at step " + std::to_string(step) +
                                              " (t = " + output::format_number(time) + " s): state '" +
                                              output::state_label(r) + "' DOF " + std::to_string(*bad) +
                                              " is not finite (position or velocity); try a smaller --dt");
        }
    }
}

/// `Type 'name' (file:line)` of the component that built `object`, or `fallback`.
std::string component_label(const Scene& scene, const void* object, const std::string& fallback) {
    const io::SceneComponent* c = object != nullptr ? scene.component_of(object) : nullptr;
    if (c == nullptr) return fallback;
    return c->describe() + " (" + c->file + ":" + std::to_string(c->line) + ")";
}

/// A non-finite value inside the solve of step `step`. At the first step, with finite states and
/// a known component, the scene's parameters make a product overflow: invalid input naming the
/// component (io::SceneError, exit 1). Otherwise the run diverged (NonFiniteValueError, exit 3)
/// naming the step, the state and, where known, the force field or mass.
[[noreturn]] void report_non_finite_solve(const Scene& scene, std::int64_t step, double time,
                                          const NonFiniteSolveError& e) {
    const void* source =
        e.force_field() != nullptr ? static_cast<const void*>(e.force_field()) : static_cast<const void*>(e.mass());
    const io::SceneComponent* c = source != nullptr ? scene.component_of(source) : nullptr;
    if (step == 0 && c != nullptr) {
        // Name the attributes that hold large numbers (and the node's gravity for a mass).
        std::string large;
        const auto scan = [&](const io::SceneElement& element, const std::string& prefix) {
            for (const io::SceneAttribute& a : element.attributes) {
                bool big = false;
                std::size_t i = 0;
                while (i < a.value.size() && !big) {
                    const std::size_t end = std::min(a.value.find(' ', i), a.value.size());
                    const std::string token = a.value.substr(i, end - i);
                    char* stop = nullptr;
                    const double v = std::strtod(token.c_str(), &stop);
                    big = !token.empty() && stop == token.c_str() + token.size() && std::abs(v) >= 1e30;
                    i = end + 1;
                }
                if (big) large += (large.empty() ? "" : ", ") + prefix + "attribute '" + a.name + "' = " + a.value;
            }
        };
        scan(*c, "");
        if (e.mass() != nullptr)
            for (const io::SceneNode* n = c->node; n != nullptr; n = n->parent) scan(*n, "node " + n->path() + " ");
        io::throw_element_error(*c,
                                std::string(e.what()) + ", at the first step from finite initial states: " +
                                    (large.empty() ? std::string("a parameter is too large") : "too large: " + large) +
                                    " (a product overflows)");
    }
    std::string where;
    if (e.force_field() != nullptr)
        where = "; from " + component_label(scene, e.force_field(), "contact springs added by a collision pipeline");
    else if (e.mass() != nullptr) where = "; from " + component_label(scene, e.mass(), "a mass");
    throw output::NonFiniteValueError("simulation diverged at step " + std::to_string(step) +
                                      " (t = " + output::format_number(time) + " s): " + e.what() + where +
                                      "; try a smaller --dt or a softer contact stiffness");
}

}  // namespace

template <class F>
void DivergenceBound::for_each_position(const Scene& scene, F&& f) {
    for (const output::StateRecord& r : scene.states()) {
        if (const auto* v = dynamic_cast<const Vec3Object*>(r.state)) {
            for (std::size_t i = 0; i < v->position.size(); ++i) f(r, i, v->position[i]);
        } else if (const auto* g = dynamic_cast<const Rigid3Object*>(r.state)) {
            for (std::size_t i = 0; i < g->position.size(); ++i) f(r, i, g->position[i].center);
        }
    }
}

DivergenceBound::DivergenceBound(const Scene& scene, double factor) : factor_(factor) {
    if (!(factor >= 0.0) || !std::isfinite(factor))
        throw std::invalid_argument("the divergence factor must be a finite number >= 0, got " +
                                    output::format_number(factor));
    Eigen::AlignedBox3d box;
    for_each_position(scene, [&](const output::StateRecord&, std::size_t, const Vec3& p) {
        box.extend(p);
        previous_.push_back(p);
    });
    if (box.isEmpty()) {
        factor_ = 0.0;  // nothing to watch
        return;
    }
    const double diagonal = box.diagonal().norm();
    // One point, or all at one place: the scene's own scale is its distance from the origin.
    size_ = diagonal > 0.0 ? diagonal : std::max(1.0, box.center().norm());
    // The force fields report their stored energy as of their last force evaluation, which is
    // the first step's, at these positions: the stored part is added at the first check.
    initial_energy_ = scene.kinetic_energy() + scene.potential_energy() - scene.stored_energy();
    energy_scale_ = scene.kinetic_energy() + scene.gravity_energy_scale(box.min(), box.max());
}

void DivergenceBound::check_energy(const Scene& scene, std::int64_t step, double time) {
    const double kinetic = scene.kinetic_energy();
    const double stored = scene.stored_energy();
    const double energy = kinetic + scene.potential_energy_from(stored);
    if (!stored_energy_known_) {
        initial_energy_ += stored;  // evaluated at the initial positions
        energy_scale_ += std::abs(stored);
        stored_energy_known_ = true;
        previous_energy_ = energy;
        previous_content_ = kinetic + std::abs(stored);
        return;
    }
    const double step_growth = energy - previous_energy_;
    const double step_scale = energy_scale_ + previous_content_;
    previous_energy_ = energy;
    previous_content_ = kinetic + std::abs(stored);
    if (!(energy_scale_ > 0.0)) return;
    const double created = energy - initial_energy_;
    std::string what;
    if (created > 10.0 * factor_ * energy_scale_) {
        what = "the energy grew by " + output::format_number(created) + " J since the start, more than " +
               output::format_number(10.0 * factor_) + " times the scene's energy scale (" +
               output::format_number(energy_scale_) +
               " J: kinetic + stored energy at the start, plus every moving mass dropped through the scene's height)";
    } else if (step_growth > factor_ * step_scale) {
        what = "the energy grew by " + output::format_number(step_growth) + " J in one step, more than " +
               output::format_number(factor_) +
               " times the scene's energy scale plus the kinetic and stored energy "
               "before the step (" +
               output::format_number(step_scale) + " J)";
    } else {
        return;
    }
    throw output::NonFiniteValueError("simulation diverged at step " + std::to_string(step) +
                                      " (t = " + output::format_number(time) + " s): " + what +
                                      "; try a smaller --dt or a softer contact stiffness, or --divergence-factor 0 "
                                      "to turn this check off");
}

void DivergenceBound::check(const Scene& scene, std::int64_t step, double time, bool static_states) {
    if (factor_ == 0.0) return;
    const double limit = factor_ * size_;
    check_energy(scene, step, time);
    // First a pass that only finds the largest change of a coordinate, M, over every DOF (the
    // three of a rigid frame's centre), against the recorded positions: a DOF moved at most
    // √3·M. Far below the limit (3 M² < 0.99 limit², the common case) the positions are only
    // recorded. Otherwise, or if a state changed size, the exact test below finds the first DOF
    // to move more than the limit. The states keep their sizes during a run; a DOF beyond those
    // recorded is only recorded (compared from the next step on).
    // A state skipped (!static_states and not moved_by_steps) keeps its recorded positions,
    // which are its current ones: neither read nor recorded again.
    std::size_t k = 0;
    double largest = 0.0;
    bool sizes_kept = true;
    for (const output::StateRecord& r : scene.states()) {
        const bool skip = !static_states && !moved_by_steps(r);
        if (const auto* v = dynamic_cast<const Vec3Object*>(r.state)) {
            const std::size_t n = v->position.size();
            if (k + n > previous_.size()) {
                sizes_kept = false;
                break;
            }
            if (n > 0 && !skip)
                largest = std::max(largest, largest_change(v->position.data()->data(), previous_[k].data(), 3 * n));
            k += n;
        } else if (const auto* g = dynamic_cast<const Rigid3Object*>(r.state)) {
            const std::size_t n = g->position.size();
            if (k + n > previous_.size()) {
                sizes_kept = false;
                break;
            }
            for (std::size_t i = 0; i < n && !skip; ++i)
                largest = std::max(largest, (g->position[i].center - previous_[k + i]).cwiseAbs().maxCoeff());
            k += n;
        }
    }
    if (sizes_kept && 3.0 * largest * largest < 0.99 * limit * limit) {
        k = 0;
        for (const output::StateRecord& r : scene.states()) {
            const bool skip = !static_states && !moved_by_steps(r);
            if (const auto* v = dynamic_cast<const Vec3Object*>(r.state)) {
                const Eigen::Index n = Eigen::Index(3 * v->position.size());
                if (n > 0 && !skip)
                    Eigen::Map<Eigen::ArrayXd>(previous_[k].data(), n) =
                        Eigen::Map<const Eigen::ArrayXd>(v->position.data()->data(), n);
                k += v->position.size();
            } else if (const auto* g = dynamic_cast<const Rigid3Object*>(r.state)) {
                if (skip) {
                    k += g->position.size();
                    continue;
                }
                for (const RigidFrame& f : g->position) previous_[k++] = f.center;
            }
        }
        previous_.resize(k);
        return;
    }
    k = 0;
    for_each_position(scene, [&](const output::StateRecord& r, std::size_t dof, const Vec3& p) {
        if (k == previous_.size()) previous_.push_back(p);
        const double moved = (p - previous_[k]).norm();
        previous_[k++] = p;
        if (moved > limit) {
            throw output::NonFiniteValueError(
                "simulation diverged at step " + std::to_string(step) + " (t = " + output::format_number(time) +
                " s): state '" + output::state_label(r) + "' DOF " + std::to_string(dof) + " moved " +
                output::format_number(moved) + " m in one step, more than " + output::format_number(factor_) +
                " times the initial scene size (" + output::format_number(size_) +
                " m); try a smaller --dt or a softer contact stiffness, or --divergence-factor 0 to turn this check "
                "off");
        }
    });
    previous_.resize(k);
}

namespace {

/// The guard's step report into the run's totals.
void add_tunnelling(RunSummary::Tunnelling& t, const TunnellingReport& r, std::int64_t step) {
    t.crossings += std::int64_t(r.crossings.size());
    t.crossing_steps += r.crossings.empty() ? 0 : 1;
    t.prevented += std::int64_t(r.prevented);
    t.undone_solves += r.undone_solves;
    t.extra_solves += std::max(0, r.solves - 1);
    t.deepest_halving = std::max(t.deepest_halving, r.deepest_halving);
    t.max_depth = std::max(t.max_depth, r.max_depth);
    if (t.first_crossing.empty() && !r.crossings.empty())
        t.first_crossing = "step " + std::to_string(step) + ": " + r.crossings.front().describe();
    t.stiffened_contacts += std::int64_t(r.stiffened_contacts);
    t.max_stiffening = std::max(t.max_stiffening, r.max_stiffening);
    t.stiffening_energy += r.stiffening_energy;
    t.guard_seconds += r.guard_seconds;
}

/// Where the crossings of the last step met (the viewer's markers); none before the first step.
std::vector<Vec3> crossing_points(const Scene& scene, bool stepped) {
    std::vector<Vec3> out;
    if (const TunnellingReport* r = scene.tunnelling_report(); r != nullptr && stepped)
        for (const Crossing& c : r->crossings) out.push_back(c.point);
    return out;
}

/// The first kept crossing as the stats column: "kind model1:feature1 model2:feature2 toi", a
/// feature v<dof> (vertex), e<dof>-<dof> (edge), t<element> (triangle), s<element> (sphere).
std::string first_crossing_column(const Crossing& c) {
    std::string s = crossing_kind_name(c.kind);
    const auto model = [&](const CollisionModel* m) {
        s.push_back(' ');
        s.append(m ? m->name() : std::string("?"));
        s.push_back(':');
    };
    const bool edges = c.kind == CrossingKind::edge_edge;
    model(c.model1);
    if (c.element1 >= 0) {
        s.push_back('s');
        s.append(std::to_string(c.element1));
    } else {
        s.push_back(edges ? 'e' : 'v');
        s.append(std::to_string(c.dofs1[0]));
        if (edges) {
            s.push_back('-');
            s.append(std::to_string(c.dofs1[1]));
        }
    }
    model(c.model2);
    if (edges) {
        s.push_back('e');
        s.append(std::to_string(c.dofs2[0]));
        s.push_back('-');
        s.append(std::to_string(c.dofs2[1]));
    } else {
        s.push_back(c.kind == CrossingKind::sphere_sphere ? 's' : 't');
        s.append(std::to_string(c.element2));
    }
    s.push_back(' ');
    output::append_number(s, c.toi);
    return s;
}

output::StepStats::Tunnelling tunnelling_columns(const TunnellingReport& r) {
    output::StepStats::Tunnelling t;
    t.crossings = r.crossings.size();
    t.prevented = r.prevented;
    if (!r.crossings.empty()) t.first_crossing = first_crossing_column(r.crossings.front());
    t.max_depth = r.max_depth;
    t.solves = r.solves;
    t.stiffened_contacts = r.stiffened_contacts;
    t.stiffening_energy = r.stiffening_energy;
    t.guard_seconds = r.guard_seconds;
    return t;
}

/// One step; an error names the step and its time, and the state that diverged first, if one did.
void step_naming_failures(Scene& scene, std::int64_t k, double t) {
    try {
        scene.step();
    } catch (const output::NonFiniteValueError&) {
        throw;
    } catch (const NonFiniteSolveError& e) {
        check_finite_states(scene, k, t);
        report_non_finite_solve(scene, k, t, e);
    } catch (const SingularSystemError& e) {
        // a scene without a mass under a direct solver: bad input, naming the solver's component
        if (const io::SceneComponent* c = scene.component_of(e.solver()))
            io::throw_element_error(*c, "step " + std::to_string(k) + ": " + e.what());
        throw std::invalid_argument("step " + std::to_string(k) + " (t = " + output::format_number(t) +
                                    " s): " + e.what());
    } catch (const io::LoadError& e) {
        // Bad input met during the step (a topological change file naming elements that do not
        // exist, an incision path outside the mesh): still bad input (exit 1), with the step named.
        check_finite_states(scene, k, t);
        throw io::LoadError("step " + std::to_string(k) + " (t = " + output::format_number(t) + " s): " + e.what());
    } catch (const std::invalid_argument& e) {
        check_finite_states(scene, k, t);
        throw std::invalid_argument("step " + std::to_string(k) + " (t = " + output::format_number(t) +
                                    " s): " + e.what());
    } catch (const std::exception& e) {
        // Any other error of the step: name the state that diverged first, if one did
        // (non-finite solves are NonFiniteSolveError, handled above).
        check_finite_states(scene, k, t);
        throw std::runtime_error("step " + std::to_string(k) + " (t = " + output::format_number(t) +
                                 " s): " + e.what());
    }
}

/// Step k's row of the --stats file, after the step.
output::StepStats stats_row(Scene& scene, std::int64_t k, const output::ContactSummary& cs, double output_seconds) {
    const StepTimings& timing = scene.last_timings();
    const StepSolverStats& solver = scene.last_solver_stats();
    output::StepStats row;
    row.step = k;
    row.time = scene.simulation().time();
    row.contacts = cs.contacts;
    row.active_contacts = cs.active_contacts;
    row.max_penetration = cs.max_penetration;
    row.contact_energy = cs.contact_energy;
    row.kinetic_energy = scene.kinetic_energy();
    row.dissipated_energy = cs.dissipated_energy;
    row.detection_seconds = timing.detection_seconds;
    row.response_seconds = timing.response_seconds;
    row.solve_seconds = timing.solve_seconds;
    row.output_seconds = output_seconds;
    row.cg_iterations = solver.cg_iterations;
    row.newton_iterations = solver.newton_iterations;
    if (const TunnellingReport* r = scene.tunnelling_report()) row.tunnelling = tunnelling_columns(*r);
    return row;
}

}  // namespace

RunSummary run_scene(Scene& scene, const RunOptions& options, const ProgressCallback& progress) {
    if (options.steps < 0) throw std::invalid_argument("steps must be >= 0");
    if (options.export_every < 1) throw std::invalid_argument("--export-every must be >= 1");
    if (options.vtk_every < 1) throw std::invalid_argument("--vtk-every must be >= 1");
    if (options.view_every < 1) throw std::invalid_argument("--view-every must be >= 1");

    RunSummary summary;
    summary.dt = scene.dt();
    std::optional<output::StateExporter> exporter;
    if (options.states_directory) {
        exporter.emplace(*options.states_directory,
                         output::select_exported_states(scene.states(), options.export_mapped));
        summary.state_files = exporter->files();
        summary.values_per_dof = exporter->values_per_dof();
    }
    std::optional<output::VtkSeriesWriter> vtk;
    if (options.vtk_directory) {
        std::vector<const output::StateRecord*> all;
        for (const auto& r : scene.states())
            if (output::has_points_in_space(r)) all.push_back(&r);
        vtk.emplace(*options.vtk_directory, std::move(all));
    }
    std::optional<output::StatsCsvWriter> stats;
    if (options.stats_file) stats.emplace(*options.stats_file, scene.tunnelling_report() != nullptr);
    if (scene.tunnelling_report() != nullptr)
        summary.tunnelling.mode = tunnelling_mode_name(scene.tunnelling_options().mode);
    std::unique_ptr<output::ViewerWriter> viewer;
    if (options.view_directory) viewer = open_viewer(scene, *options.view_directory, options.view_title);

    Simulation& sim = scene.simulation();
    DivergenceBound bound(scene, options.divergence_factor);
    const auto run_start = Clock::now();
    double contact_sum = 0.0;
    double cg_sum = 0.0, newton_sum = 0.0;
    summary.cg = scene.uses_cg();
    summary.newton = scene.uses_newton();
    for (std::int64_t k = 0; k < options.steps; ++k) {
        const double t = sim.time();
        const auto out_start = Clock::now();
        if (exporter && (k % options.export_every == 0 || k == options.steps - 1)) exporter->write(t);
        if (vtk && k % options.vtk_every == 0) vtk->write_step(t, scene.contacts());
        if (viewer && k % options.view_every == 0)
            viewer->write_frame(t, scene.contacts(), scene.kinetic_energy(), crossing_points(scene, k > 0));
        double output_seconds = seconds_since(out_start);

        step_naming_failures(scene, k, t);
        // the states no step moves: after the first step only, unless code between the steps may move them
        const bool static_states = options.states_change_between_steps || k == 0;
        check_finite_states(scene, k, sim.time(), static_states);
        if (options.debug_step && *options.debug_step == k) {
            const auto debug_start = Clock::now();
            output::write_output_file(options.debug_file, step_debug_text(scene, k, t));
            output_seconds += seconds_since(debug_start);
        }
        bound.check(scene, k, sim.time(), static_states);

        const StepTimings& timing = scene.last_timings();
        summary.detection_seconds += timing.detection_seconds;
        summary.response_seconds += timing.response_seconds;
        summary.solve_seconds += timing.solve_seconds;
        const StepSolverStats& solver = scene.last_solver_stats();
        cg_sum += solver.cg_iterations;
        newton_sum += solver.newton_iterations;
        summary.max_cg_iterations = std::max(summary.max_cg_iterations, solver.cg_iterations);
        summary.max_newton_iterations = std::max(summary.max_newton_iterations, solver.newton_iterations);
        summary.cg_limit_steps += solver.cg_limit_reached ? 1 : 0;
        summary.newton_unconverged_steps += solver.newton_unconverged ? 1 : 0;
        if (const TunnellingReport* r = scene.tunnelling_report()) add_tunnelling(summary.tunnelling, *r, k);
        const output::ContactSummary cs = output::summarize_contacts(scene.contacts());
        contact_sum += double(cs.contacts);
        summary.max_contacts = std::max(summary.max_contacts, cs.contacts);
        summary.max_penetration = std::max(summary.max_penetration, cs.max_penetration);
        summary.contact_energy = cs.contact_energy;
        summary.dissipated_energy = cs.dissipated_energy;
        if (stats) {
            const auto stats_start = Clock::now();
            stats->write(stats_row(scene, k, cs, output_seconds));
            output_seconds += seconds_since(stats_start);
        }
        summary.output_seconds += output_seconds;
        summary.steps = k + 1;
        summary.simulated_time = sim.time();
        if (progress) progress(k + 1, options.steps, summary);
    }
    {
        // The final state: VTK gets it after the last step; a run of 0 steps writes its initial
        // state (the state at its end) into the state files too, so no file is left empty.
        const auto out_start = Clock::now();
        if (vtk) vtk->write_step(sim.time(), scene.contacts());
        if (exporter && options.steps == 0) exporter->write(sim.time());
        summary.output_seconds += seconds_since(out_start);
    }
    if (viewer) {
        const auto out_start = Clock::now();
        viewer->write_frame(sim.time(), scene.contacts(), scene.kinetic_energy(),
                            crossing_points(scene, options.steps > 0));  // the end (or t = 0 without steps)
        viewer->finish();
        summary.output_seconds += seconds_since(out_start);
    }
    summary.wall_seconds = seconds_since(run_start);
    summary.mean_contacts = options.steps > 0 ? contact_sum / double(options.steps) : 0.0;
    summary.mean_cg_iterations = options.steps > 0 ? cg_sum / double(options.steps) : 0.0;
    summary.mean_newton_iterations = options.steps > 0 ? newton_sum / double(options.steps) : 0.0;
    summary.kinetic_energy = scene.kinetic_energy();
    return summary;
}

std::string step_debug_text(const Scene& scene, std::int64_t step, double t_start) {
    std::ostringstream out;
    char buf[128];
    const auto number = [&](double v) {
        std::snprintf(buf, sizeof buf, "%.17g", v);
        return std::string(buf);
    };
    const auto vec3 = [&](const Vec3& v) { return number(v.x()) + " " + number(v.y()) + " " + number(v.z()); };
    out << "# penalty debug export: step " << step << ", t_start " << number(t_start) << " s, dt " << number(scene.dt())
        << " s, scene " << scene.file().path.string() << "\n";
    out << "contacts:\n";
    for (const output::ContactRecord& r : scene.contacts()) {
        const auto contacts = r.field->contacts();
        out << "pair " << r.name << " (" << contacts.size() << " contacts)\n";
        for (std::size_t i = 0; i < contacts.size(); ++i) {
            const PenaltyContact& c = contacts[i];
            out << "contact " << i << " elements " << c.index1 << " " << c.index2 << " point1 "
                << vec3(r.state1->position[std::size_t(c.m1)]) << " point2 "
                << vec3(r.state2->position[std::size_t(c.m2)]) << " normal " << vec3(c.normal) << " distance "
                << number(c.dist) << " penetration " << number(c.pen) << " stiffness " << number(c.ks) << " force "
                << number(c.normal_force) << "\n";
        }
    }
    out << "solves:\n";
    for (const auto& [path, solver] : scene.implicit_solvers()) {
        const auto& solves = solver->last_step_cg_solves();
        for (std::size_t j = 0; j < solves.size(); ++j)
            out << "solve " << path << " linear solve " << j << ": iterations " << solves[j].iterations << " end "
                << solves[j].end_condition << " residual " << number(solves[j].error) << "\n";
    }
    out << "forces:\n";
    for (const output::StateRecord& r : scene.states()) {
        const std::string label = output::state_label(r);
        if (const auto* v = dynamic_cast<const Vec3Object*>(r.state)) {
            for (std::size_t i = 0; i < v->force.size(); ++i)
                out << "force " << label << " " << i << " " << vec3(v->force[i]) << "\n";
        } else if (const auto* g = dynamic_cast<const Rigid3Object*>(r.state)) {
            for (std::size_t i = 0; i < g->force.size(); ++i)
                out << "force " << label << " " << i << " " << vec3(g->force[i].linear) << " "
                    << vec3(g->force[i].angular) << "\n";
        } else if (const auto* d = dynamic_cast<const Vec1Object*>(r.state)) {
            for (std::size_t i = 0; i < d->force.size(); ++i)
                out << "force " << label << " " << i << " " << number(d->force[i]) << "\n";
        }
    }
    return out.str();
}

std::string format_summary(const RunSummary& s) {
    char buf[512];
    std::ostringstream out;
    const double per_step = s.steps > 0 ? 1e3 / double(s.steps) : 0.0;
    std::snprintf(buf, sizeof buf, "steps: %lld  (dt %g s, simulated %g s) in %.3f s wall: %.1f steps/s\n",
                  static_cast<long long>(s.steps), s.dt, s.simulated_time, s.wall_seconds,
                  s.wall_seconds > 0 ? double(s.steps) / s.wall_seconds : 0.0);
    out << buf;
    std::snprintf(buf, sizeof buf, "contacts per step: mean %.1f, max %zu; maximum penetration %.6g m\n",
                  s.mean_contacts, s.max_contacts, s.max_penetration);
    out << buf;
    std::snprintf(buf, sizeof buf,
                  "energies at the end: kinetic %.6g J, stored in contacts %.6g J, dissipated by contacts %.6g J\n",
                  s.kinetic_energy, s.contact_energy, s.dissipated_energy);
    out << buf;
    std::snprintf(buf, sizeof buf,
                  "time per step: detection %.3f ms, response %.3f ms, solve %.3f ms, output %.3f ms\n",
                  s.detection_seconds * per_step, s.response_seconds * per_step, s.solve_seconds * per_step,
                  s.output_seconds * per_step);
    out << buf;
    if (s.cg) {
        std::snprintf(buf, sizeof buf,
                      "CG iterations per step: mean %.1f, max %d; iteration limit reached in %lld steps\n",
                      s.mean_cg_iterations, s.max_cg_iterations, static_cast<long long>(s.cg_limit_steps));
        out << buf;
    }
    if (s.newton) {
        std::snprintf(buf, sizeof buf, "Newton iterations per step: mean %.2f, max %d; not converged in %lld steps\n",
                      s.mean_newton_iterations, s.max_newton_iterations,
                      static_cast<long long>(s.newton_unconverged_steps));
        out << buf;
    }
    if (!s.tunnelling.mode.empty()) out << format_tunnelling_summary(s);
    return out.str();
}

std::string format_tunnelling_summary(const RunSummary& s) {
    const RunSummary::Tunnelling& t = s.tunnelling;
    char buf[512];
    std::ostringstream out;
    std::snprintf(buf, sizeof buf,
                  "tunnelling guard (%s): %lld crossings in %lld steps, deepest %.3g m; %.3f ms per step\n",
                  t.mode.c_str(), static_cast<long long>(t.crossings), static_cast<long long>(t.crossing_steps),
                  t.max_depth, s.steps > 0 ? 1e3 * t.guard_seconds / double(s.steps) : 0.0);
    out << buf;
    if (!t.first_crossing.empty()) out << "  first crossing: " << t.first_crossing << "\n";
    if (t.mode != "warn") {
        std::snprintf(buf, sizeof buf,
                      "  prevented %lld crossings: %lld solves undone, %lld extra solves (shortest dt/%lld); "
                      "%lld contacts stiffened (up to x%.3g), stiffening energy %.6g J\n",
                      static_cast<long long>(t.prevented), static_cast<long long>(t.undone_solves),
                      static_cast<long long>(t.extra_solves), 1LL << t.deepest_halving,
                      static_cast<long long>(t.stiffened_contacts), t.max_stiffening, t.stiffening_energy);
        out << buf;
    }
    return out.str();
}

std::vector<std::filesystem::path> reference_files(const std::filesystem::path& reference_dir,
                                                   const std::filesystem::path& scene_file,
                                                   const std::vector<std::filesystem::path>& state_files) {
    std::vector<std::filesystem::path> out;
    out.reserve(state_files.size());
    for (const auto& f : state_files)
        out.push_back(reference_dir / (scene_file.filename().string() + ".reference_" + f.filename().string()));
    return out;
}

}  // namespace penalty::scene
