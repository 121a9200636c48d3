// SubtreeSystem's products and vector passes: forces, (m·M + b·B + k·K)·dx, the CG's fused
// passes, dot products, projections.
#include "penalty/simulation/subtree_system.hpp"

#include "flat_vector_ops.hpp"
#include "fused_contact_block.hpp"
#include "kernels/prefetch.hpp"
#include "penalty/core/error.hpp"
#include "penalty/core/first_error.hpp"
#include "step_chains.hpp"
#include "subtree_layout.hpp"
#include "subtree_scratch.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace penalty {

using detail::direction;
using detail::state_dot;

namespace {
/// pass(i) for every independent state i of `l`, on TBB's threads in groups of states when the
/// system is large and has several states and the arena several threads: each state's pass
/// reads and writes only that state's part of the vectors (and its own dx, df, sum).
template <class Pass>
void for_each_state(const detail::SubtreeLayout& l, detail::SubtreeScratch& scratch, const Pass& pass) {
    const std::size_t n = l.independent.size();
    if (n >= 2 && l.size >= SubtreeSystem::kMinUnknownsForConcurrentStatePasses &&
        tbb::this_task_arena::max_concurrency() > 1) {
        ++scratch.concurrent_state_passes;
        const auto grain = static_cast<std::size_t>(
            std::max<Eigen::Index>(1, Eigen::Index(n) * SubtreeSystem::kUnknownsPerStatePassTask / l.size));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) pass(i);
        });
        return;
    }
    for (std::size_t i = 0; i < n; ++i) pass(i);
}

/// pass(i, begin, end) over the unknowns [begin, end) of every independent state i, in pieces of
/// whole DOFs of about kUnknownsPerStatePassTask: an elementwise pass (no sum), on TBB's threads
/// when the system is large and the arena has several threads, a large state split too.
template <class Pass>
void for_each_piece(const detail::SubtreeLayout& l, detail::SubtreeScratch& scratch, const Pass& pass) {
    const std::size_t n = l.independent.size();
    if (l.size < SubtreeSystem::kMinUnknownsForConcurrentStatePasses || tbb::this_task_arena::max_concurrency() < 2) {
        for (std::size_t i = 0; i < n; ++i) pass(i, Eigen::Index(0), l.sizes[i]);
        return;
    }
    auto& pieces = scratch.state_pieces;
    if (pieces.empty())  // once: the layout's states and sizes are fixed
        for (std::size_t i = 0; i < n; ++i) {
            const Eigen::Index width = std::max<Eigen::Index>(1, l.widths[i]);
            const Eigen::Index step =
                std::max<Eigen::Index>(1, SubtreeSystem::kUnknownsPerStatePassTask / width) * width;
            for (Eigen::Index begin = 0; begin < l.sizes[i]; begin += step)
                pieces.push_back({i, begin, std::min(begin + step, l.sizes[i])});
        }
    ++scratch.concurrent_state_passes;
    const auto grain = static_cast<std::size_t>(
        std::max<Eigen::Index>(1, Eigen::Index(pieces.size()) * SubtreeSystem::kUnknownsPerStatePassTask / l.size));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces.size(), grain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t k = r.begin(); k != r.end(); ++k)
                              pass(pieces[k].state, pieces[k].begin, pieces[k].end);
                      });
}

/// Σ sums[i] in order from 0.0: the single chain of SOFA's dot product over the states.
double sum_in_order(const std::vector<double>& sums) {
    double total = 0.0;
    for (const double s : sums) total += s;
    return total;
}

/// The one component a force step calls.
const void* step_object(const detail::ForceStep& s) {
    return s.mass != nullptr          ? static_cast<const void*>(s.mass)
           : s.force_field != nullptr ? static_cast<const void*>(s.force_field)
                                      : static_cast<const void*>(s.mapping);
}
}  // namespace

double SubtreeSystem::dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
    if (blocked_reductions_)
        return detail::blocked_dot(scratch_->reduction_blocks, a.data(), b.data(), scratch_->block_sums);
    std::vector<double>& sums = scratch_->state_sums;
    const detail::SubtreeLayout& l = *layout_;
    for_each_state(l, *scratch_, [&sums, &l, a_data = a.data(), b_data = b.data()](std::size_t s) {
        const Eigen::Index begin = l.offsets[s];
        sums[s] = state_dot(a_data, b_data, begin, begin + l.sizes[s], l.widths[s]);
    });
    return sum_in_order(sums);
}

void SubtreeSystem::gather_velocity(Eigen::VectorXd& v) const {
    v.resize(layout_->size);
    for (std::size_t i = 0; i < layout_->independent.size(); ++i)
        v.segment(layout_->offsets[i], layout_->sizes[i]) = layout_->independent[i]->velocity_flat();
}

void SubtreeSystem::scatter_velocity(const Eigen::VectorXd& v) const {
    for (std::size_t i = 0; i < layout_->independent.size(); ++i)
        layout_->independent[i]->velocity_flat() = v.segment(layout_->offsets[i], layout_->sizes[i]);
}

void SubtreeSystem::add_to_positions(double h, const Eigen::VectorXd& v) const {
    for (std::size_t i = 0; i < layout_->independent.size(); ++i)
        layout_->independent[i]->add_to_position(h, v.segment(layout_->offsets[i], layout_->sizes[i]));
}

void SubtreeSystem::propagate_positions_and_velocities() const {
    for (BaseMapping* m : layout_->mappings) {
        m->apply_position();
        m->apply_velocity();
    }
}

void SubtreeSystem::reset_forces() const {
    for (BaseState* s : layout_->independent) s->force_flat() = s->external_force_flat();
    for (BaseState* s : layout_->mapped) s->force_flat() = s->external_force_flat();
    clear_external_scratch(/*forces=*/true);
}

void SubtreeSystem::compute_force(Eigen::VectorXd& f) const {
    scratch_->external_work_zeroed = false;  // a new solve: another solver may have used the external states
    fused_->forces_computed();               // the contacts' active sets are this evaluation's
    reset_forces();
    // computeForce: SOFA HEAD's MappingGraph order (mapping_graph_order) or its visitors' order
    const auto add_force = [](const detail::ForceStep& s) {
        if (s.mass != nullptr) s.mass->add_gravity_force(s.gravity);
        else if (s.force_field != nullptr) s.force_field->accumulate_force();
        else s.mapping->apply_jt_force();
    };
    const std::vector<detail::ForceStep>& steps = layout_->steps;
    const detail::StepChains& chains = layout_->chains;
    if (chains_worth_tasks(chains, steps.size())) {
        // In the product's chains on TBB's threads: a force step writes the forces of the states
        // whose dforce the product's step writes, and reads positions, velocities and its chain's
        // forces only: the same bits (step_chains.hpp). The error is that of the first failing
        // step in the list's order, as the loop below would raise it (a chain's steps before its
        // failing one see the same states either way).
        ++scratch_->concurrent_force_evaluations;
        FirstErrorInOrder failure;
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, chains.size()), [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t c = r.begin(); c != r.end(); ++c)
                    for (std::size_t i = chains.step_first[c]; i < chains.step_first[c + 1]; ++i)
                        if (!failure.run(chains.steps_of[i], [&] { add_force(steps[chains.steps_of[i]]); })) break;
            });
        failure.rethrow_if_any();
    } else {
        for (const detail::ForceStep& s : steps) add_force(s);
    }
    f.resize(layout_->size);
    for (std::size_t i = 0; i < layout_->independent.size(); ++i)
        f.segment(layout_->offsets[i], layout_->sizes[i]) = layout_->independent[i]->force_flat();
    if (!f.allFinite()) throw_non_finite_force();
}

void SubtreeSystem::apply_mbk(const Eigen::VectorXd& dx, Eigen::VectorXd& out, double m, double b, double k,
                              bool do_project, bool accumulate) const {
    if (accumulate) PENALTY_DEMAND(out.size() == layout_->size);
    for (std::size_t i = 0; i < layout_->independent.size(); ++i) {
        const auto n = layout_->sizes[i];
        layout_->independent[i]->dx_flat() = dx.segment(layout_->offsets[i], n);
        // accumulate: each contribution is added to out's value in turn, as SOFA's addMBKv
        // adds into b = f (((f + c1) + c2) ..., not f + (c1 + c2 ...)).
        if (accumulate) layout_->independent[i]->df_flat() = out.segment(layout_->offsets[i], n);
        else layout_->independent[i]->df_flat().setZero();
    }
    apply_mbk_to_states(m, b, k);
    out.resize(layout_->size);
    for (std::size_t i = 0; i < layout_->independent.size(); ++i)
        out.segment(layout_->offsets[i], layout_->sizes[i]) = layout_->independent[i]->df_flat();
    if (do_project) project(out);
}

double SubtreeSystem::direction_and_mbk(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                        Eigen::VectorXd& q, double m, double b, double k) const {
    PENALTY_DEMAND(r.size() == layout_->size && p.size() == layout_->size && &r != &p);
    // p = r or r + β·p (Eigen's p = r + β·p: each r_j + (β·p_j)), into p and the state's dx
    const detail::SubtreeLayout& l = *layout_;
    const double* r_data = r.data();
    double* p_data = p.data();
    for_each_piece(
        l, *scratch_, [&l, r_data, p_data, first, beta](std::size_t i, Eigen::Index begin, Eigen::Index end) {
            const Eigen::Index at = l.offsets[i] + begin;
            direction(first, beta, r_data + at, p_data + at, l.independent[i]->dx_flat().data() + begin, end - begin);
            double* df = l.independent[i]->df_flat().data();
            std::fill(df + begin, df + end, 0.0);
        });
    apply_mbk_to_states(m, b, k);
    q.resize(layout_->size);
    if (!layout_->constraints.empty()) {  // q is projected before p·q
        for (std::size_t i = 0; i < layout_->independent.size(); ++i)
            q.segment(layout_->offsets[i], layout_->sizes[i]) = layout_->independent[i]->df_flat();
        project(q);
        return dot(p, q);
    }
    if (blocked_reductions_) {
        double* q_data = q.data();
        for_each_piece(l, *scratch_, [&l, q_data](std::size_t i, Eigen::Index begin, Eigen::Index end) {
            const double* df = l.independent[i]->df_flat().data();
            std::copy(df + begin, df + end, q_data + l.offsets[i] + begin);
        });
        return dot(p, q);
    }
    // dot(p, q), each state's sum as its part of q is copied
    std::vector<double>& sums = scratch_->state_sums;
    double* q_data = q.data();
    for_each_state(l, *scratch_, [&sums, &l, p_data, q_data](std::size_t i) {
        const Eigen::Index begin = l.offsets[i];
        const Eigen::Index n = l.sizes[i];
        const double* df = l.independent[i]->df_flat().data();
        std::copy(df, df + n, q_data + begin);
        sums[i] = state_dot(p_data, q_data, begin, begin + n, l.widths[i]);
    });
    return sum_in_order(sums);
}

double SubtreeSystem::update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
                                          Eigen::VectorXd& x, Eigen::VectorXd& r) const {
    PENALTY_DEMAND(p.size() == layout_->size && q.size() == layout_->size && x.size() == layout_->size &&
                   r.size() == layout_->size);
    const double* ps = p.data();
    const double* qs = q.data();
    double* xs = x.data();
    double* rs = r.data();
    if (blocked_reductions_)
        return detail::blocked_update_and_residual(scratch_->reduction_blocks, alpha, ps, qs, xs, rs,
                                                   scratch_->block_sums);
    // dot(r, r), each state's sum over its DOFs as they are updated
    std::vector<double>& sums = scratch_->state_sums;
    const detail::SubtreeLayout& l = *layout_;
    for_each_state(l, *scratch_, [&sums, &l, alpha, ps, qs, xs, rs](std::size_t i) {
        const Eigen::Index begin = l.offsets[i];
        sums[i] = detail::update_state(alpha, ps, qs, xs, rs, begin, begin + l.sizes[i], l.widths[i]);
    });
    return sum_in_order(sums);
}

void MbkCgSystem::apply(const Eigen::VectorXd& p, Eigen::VectorXd& q) { system_.apply_mbk(p, q, m_, b_, k_, true); }

double MbkCgSystem::dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const { return system_.dot(a, b); }

double MbkCgSystem::direction_and_product(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                          Eigen::VectorXd& q) {
    return system_.direction_and_mbk(r, beta, first, p, q, m_, b_, k_);
}

double MbkCgSystem::update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
                                        Eigen::VectorXd& x, Eigen::VectorXd& r) {
    return system_.update_and_residual(alpha, p, q, x, r);
}

void SubtreeSystem::apply_mbk_to_states(double m, double b, double k) const {
    if (!scratch_->external_work_zeroed) {
        clear_external_scratch(/*forces=*/false);
        scratch_->external_work_zeroed = true;
    }
    // The fused contact block: only while the contacts cannot change.
    const bool fused = scratch_->readers_fixed && !fused_->empty();
    // (fused: only the mappings and steps the fused block does not apply, in the same order)
    const std::vector<std::size_t>& maps = fused ? fused_->unfused_mappings() : layout_->all_mappings;
    const std::vector<detail::ForceStep>& steps = fused ? fused_->steps() : layout_->steps;
    // In chains on TBB's threads under a FixedReaders: the same bits (step_chains.hpp). The first
    // product finds each mapped state's read rows in its chain, with its thread's row lists.
    const detail::StepChains& chains = fused ? fused_->chains() : layout_->chains;
    const bool concurrent = scratch_->readers_fixed && chains_worth_tasks(chains, steps.size());
    if (concurrent) {
        ++scratch_->concurrent_products;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chains.size()),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              detail::RowLists& lists = scratch_->task_row_lists.local();
                              for (std::size_t c = r.begin(); c != r.end(); ++c) {
                                  for (std::size_t i = chains.mapping_first[c]; i < chains.mapping_first[c + 1]; ++i)
                                      map_dx(chains.mappings_of[i], lists);
                                  for (std::size_t i = chains.mapping_first[c]; i < chains.mapping_first[c + 1]; ++i)
                                      zero_mapped_df(chains.mappings_of[i]);
                              }
                          });
        if (fused) fused_->begin_product(k, b, /*parallel=*/true);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chains.size()),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              for (std::size_t c = r.begin(); c != r.end(); ++c)
                                  for (std::size_t i = chains.step_first[c]; i < chains.step_first[c + 1]; ++i)
                                      apply_step(steps[chains.steps_of[i]], m, b, k, fused);
                          });
        return;
    }
    // The loops below call thousands of small objects (a contact pair's states and mappings) a
    // product, each a cache miss on its first word: fetched kObjectsAhead iterations earlier.
    namespace prefetch = detail::prefetch;
    const std::size_t ahead = prefetch::kObjectsAhead;
    for (std::size_t j = 0; j < maps.size(); ++j) {
        if (j + ahead < maps.size()) prefetch::first_word(layout_->dx_readers[maps[j + ahead]].mapping);
        map_dx(maps[j], scratch_->row_lists);
    }
    for (std::size_t j = 0; j < maps.size(); ++j) {
        if (j + ahead < maps.size()) prefetch::first_word(layout_->mapped[maps[j + ahead]]);
        zero_mapped_df(maps[j]);
    }
    // the right-hand side's addMBKv and the CG's product in the system's order
    if (fused) fused_->begin_product(k, b, /*parallel=*/false);
    for (std::size_t i = 0; i < steps.size(); ++i) {
        if (i + ahead < steps.size()) prefetch::first_word(step_object(steps[i + ahead]));
        apply_step(steps[i], m, b, k, fused);
    }
}

void SubtreeSystem::zero_mapped_df(std::size_t index) const {
    const detail::DxRows& r = scratch_->dx_rows[index];
    BaseState& state = *layout_->mapped[index];
    if (!r.restricted) {
        state.df_flat().setZero();
        return;
    }
    // only the rows read (and written) by the readers; Jᵀ takes no other (apply_jt_df_rows)
    detail::zero_rows(state.df_flat(), static_cast<Eigen::Index>(state.deriv_size()), r.rows);
}

void SubtreeSystem::apply_step(const detail::ForceStep& s, double m, double b, double k, bool fused) const {
    if (fused && s.fused >= 0) {  // a read fused mapping (the block's steps hold no other fused step)
        fused_->spread(static_cast<std::size_t>(s.fused));
    } else if (s.mass != nullptr) {
        if (m != 0.0) s.mass->add_mdx(m);
    } else if (s.force_field != nullptr) {
        s.force_field->accumulate_dforce(k, b);
    } else {
        const detail::DxRows& r = scratch_->dx_rows[s.mapping_index];
        if (r.restricted) s.mapping->apply_jt_df_rows(r.rows);
        else s.mapping->apply_jt_df();
        // SOFA's addMBKdx: the mapping's geometric stiffness after its Jᵀ (applyDJT)
        if (k != 0.0 && s.mapping->has_geometric_stiffness()) s.mapping->apply_djt(k);
    }
}

bool SubtreeSystem::chains_worth_tasks(const detail::StepChains& chains, std::size_t steps) const {
    // a product of a few small bodies takes microseconds: tasks would cost more than they save
    return chains.size() >= 2 && steps >= kMinStepsForConcurrentProducts && 2 * chains.largest() <= steps &&
           tbb::this_task_arena::max_concurrency() > 1;
}

void SubtreeSystem::project(Eigen::VectorXd& v) const {
    for (BaseProjectiveConstraint* c : layout_->constraints) {
        const std::size_t i = layout_->independent_index.find(c->state());
        if (i == PointerIndex<BaseState>::npos) continue;  // constraints on mapped states are not supported
        c->project_response(v.segment(layout_->offsets[i], static_cast<Eigen::Index>(c->state()->scalar_size())));
    }
}

void SubtreeSystem::apply_inverse_mass(const Eigen::VectorXd& in, Eigen::VectorXd& out) const {
    for (const auto& [mass, g] : layout_->masses)
        if (!layout_->is_independent(mass->state()))
            throw_invalid_argument("EulerExplicitSolver: state '", mass->state()->state_name(),
                                   "' is mapped: a mass on a mapped state needs an implicit solver");
    out.setZero(layout_->size);
    for (std::size_t i = 0; i < layout_->independent.size(); ++i) {
        const auto n = layout_->sizes[i];
        const auto it = std::find_if(layout_->masses.begin(), layout_->masses.end(),
                                     [&](const auto& e) { return e.first->state() == layout_->independent[i]; });
        if (it == layout_->masses.end())
            throw_invalid_argument("EulerExplicitSolver: state '", layout_->independent[i]->state_name(),
                                   "' has no mass");
        it->first->apply_inverse(in.segment(layout_->offsets[i], n), out.segment(layout_->offsets[i], n));
    }
}

double SubtreeSystem::total_energy() const {
    double e = 0.0;
    for (const BaseForceField* ff : layout_->force_fields) e += ff->potential_energy();
    for (const auto& [mass, g] : layout_->masses) e += mass->kinetic_energy() + mass->gravity_potential_energy(g);
    return e;
}

}  // namespace penalty
