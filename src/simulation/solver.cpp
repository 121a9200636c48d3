#include "penalty/simulation/solver.hpp"

#include "penalty/core/first_error.hpp"
#include "penalty/core/pointer_index.hpp"

#include <cstdio>
#include <ostream>

#include <Eigen/SparseCore>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace penalty {

// ---- CG ---------------------------------------------------------------------------------------
std::string_view cg_end_condition_name(CgEndCondition condition) {
    switch (condition) {
        case CgEndCondition::none: return "none";
        case CgEndCondition::iterations: return "iterations";
        case CgEndCondition::tolerance: return "tolerance";
        case CgEndCondition::threshold: return "threshold";
        case CgEndCondition::den_zero: return "den=0";
        case CgEndCondition::b_zero: return "b=0";
    }
    return "unknown";
}

std::ostream& operator<<(std::ostream& out, CgEndCondition condition) { return out << cg_end_condition_name(condition); }

void CGLinearSolver::check() const {
    if (iterations < 1) throw_invalid_argument("CGLinearSolver: iterations must be >= 1, got ", iterations);
    if (!std::isfinite(tolerance) || tolerance < 0) throw_invalid_argument("CGLinearSolver: tolerance must be >= 0, got ", tolerance);
    if (!std::isfinite(threshold) || threshold < 0) throw_invalid_argument("CGLinearSolver: threshold must be >= 0, got ", threshold);
}

namespace {
/// Σ aᵢbᵢ, left to right (no vectorised partial sums).
double sequential_dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    double sum = 0.0;
    for (Eigen::Index i = 0; i < a.size(); ++i) sum += a[i] * b[i];
    return sum;
}

/// One state's part of SubtreeSystem::dot over the scalars [begin, end) of DOFs `width` wide:
/// d = Σ_c a_c·b_c left to right per DOF, sum = 0, sum += d per DOF in order.
double state_dot(const double* a, const double* b, Eigen::Index begin, Eigen::Index end, Eigen::Index width) {
    double sum = 0.0;
    if (width == 3) {  // Vec3 states, the common case: the same sums with a fixed inner count
        for (Eigen::Index i = begin; i < end; i += 3) sum += (a[i] * b[i] + a[i + 1] * b[i + 1]) + a[i + 2] * b[i + 2];
        return sum;
    }
    for (Eigen::Index i = begin; i < end; i += width) {
        double dof = a[i] * b[i];
        for (Eigen::Index c = 1; c < width; ++c) dof += a[i + c] * b[i + c];
        sum += dof;
    }
    return sum;
}

/// p_j = r_j (first) or r_j + β·p_j, into p and dx, for j < n: three vectors apart (segments
/// of distinct vectors), so the compiler may run the lanes together; each value gets the same
/// operations as in the loop over j alone.
void direction(bool first, double beta, const double* __restrict r, double* __restrict p, double* __restrict dx,
               Eigen::Index n) {
    if (first) {
        for (Eigen::Index j = 0; j < n; ++j) dx[j] = p[j] = r[j];
        return;
    }
    for (Eigen::Index j = 0; j < n; ++j) dx[j] = p[j] = r[j] + beta * p[j];
}

/// CgSystem over an operator and a dot product: the steps one after the other.
class FunctionCgSystem final : public CgSystem {
public:
    FunctionCgSystem(const CGLinearSolver::Operator& a, const CGLinearSolver::Dot& dot) : a_(a), dot_(dot) {}
    void apply(const Eigen::VectorXd& p, Eigen::VectorXd& q) override { a_(p, q); }
    [[nodiscard]] double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const override {
        return dot_ ? dot_(a, b) : sequential_dot(a, b);
    }

private:
    const CGLinearSolver::Operator& a_;
    const CGLinearSolver::Dot& dot_;
};

}  // namespace

double CgSystem::direction_and_product(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                       Eigen::VectorXd& q) {
    if (first) p = r;
    else p = r + beta * p;
    apply(p, q);
    return dot(p, q);
}

double CgSystem::update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q, Eigen::VectorXd& x,
                                     Eigen::VectorXd& r) {
    x += alpha * p;
    r -= alpha * q;
    return dot(r, r);
}

CgStats CGLinearSolver::solve(const Operator& a, const Eigen::VectorXd& b, Eigen::VectorXd& x, const Dot& dot_product) {
    FunctionCgSystem system(a, dot_product);
    return solve(system, b, x);
}

CgStats CGLinearSolver::solve(CgSystem& system, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    check();
    CgStats stats;
    const bool first_solve = solve_count_ == 0;
    ++solve_count_;
    x.setZero(b.size());
    const double norm_b = std::sqrt(system.dot(b, b));  // SOFA: MultiVec::norm() = sqrt(v_dot(b, b))
    if (!std::isfinite(norm_b))
        throw NonFiniteSolveError("CGLinearSolver: the right-hand side is not finite (|b| overflows)", nullptr, nullptr, nullptr);
    if (norm_b == 0.0) {
        stats.end_condition = CgEndCondition::b_zero;
        return stats;
    }
    Eigen::VectorXd& r = r_;
    Eigen::VectorXd& p = p_;
    Eigen::VectorXd& q = q_;
    r = b;
    p.resize(b.size());
    q.resize(b.size());
    // ρ = r·r of the iteration to come: computed here for the first, by the update of r after
    // (update_and_residual, which also computes it once after the last iteration, unused).
    double rho = system.dot(r, r);
    double rho_prev = 0.0;
    stats.end_condition = CgEndCondition::iterations;
    for (int k = 1; k <= iterations; ++k) {
        stats.iterations = k;
        const double err = std::sqrt(rho) / norm_b;
        stats.error = err;
        if (err <= tolerance && !(k == 1 && first_solve)) {
            stats.end_condition = CgEndCondition::tolerance;
            break;
        }
        // p = r (k = 1) or r + (ρ/ρ_prev)·p; q = A·p; den = p·q
        const double den = system.direction_and_product(r, k == 1 ? 0.0 : rho / rho_prev, k == 1, p, q);
        if (den == 0.0) {
            stats.end_condition = CgEndCondition::den_zero;
            break;
        }
        if (std::abs(den) <= threshold && !(k == 1 && first_solve)) {
            stats.end_condition = CgEndCondition::threshold;
            break;
        }
        const double alpha = rho / den;
        rho_prev = rho;
        rho = system.update_and_residual(alpha, p, q, x, r);  // x += α·p, r −= α·q
    }
    if (!x.allFinite())
        throw NonFiniteSolveError("CGLinearSolver: the solution is not finite (singular or indefinite system, or an overflow)",
                                  nullptr, nullptr, nullptr);
    return stats;
}

namespace {
/// The constructor's tables and per-state lists (SubtreeSystem::SubtreeSystem), kept by each
/// thread from one build to the next: refilled at each build, never freed.
struct SystemBuildLists {
    PointerIndex<BaseState> known;
    PointerIndex<BaseState> fields_on_index;  // state → its list in fields_on
    std::vector<std::vector<const BaseForceField*>> fields_on;
    std::size_t fields_on_used = 0;
    PointerIndex<BaseState> mappings_from_index;  // state → its list in mappings_from
    std::vector<std::vector<const BaseMapping*>> mappings_from;
    std::size_t mappings_from_used = 0;
    PointerIndex<BaseMapping> mapping_index;
    /// The list of `s` in (index, lists, used), a new empty one if it has none.
    template <class T>
    static std::vector<T>& list_of(const BaseState* s, PointerIndex<BaseState>& index, std::vector<std::vector<T>>& lists,
                                   std::size_t& used) {
        const auto [at, added] = index.emplace(s, used);
        if (added) {
            if (lists.size() == used) lists.emplace_back();
            lists[used++].clear();
        }
        return lists[at];
    }
};
}  // namespace

// ---- SubtreeSystem ----------------------------------------------------------------------------
SubtreeSystem::SubtreeSystem(Node& root, bool mapping_graph_order, bool fuse_contact_products)
    : fuse_contact_products_(fuse_contact_products), mapping_graph_order_(mapping_graph_order) {
    collect(root, true);
    if (mapping_graph_order_) order_as_mapping_graph(root);
    // External states: used by a force field or a mapping but not part of the subtree. Tables
    // and per-state lists kept by the thread from one build to the next, not searches of the
    // lists: a pile of bodies has thousands of contact states, and the system is built again
    // whenever contacts come or go.
    thread_local SystemBuildLists lists;
    SystemBuildLists& t = lists;
    t.known.clear();
    t.fields_on_index.clear();
    t.fields_on_used = 0;
    t.mappings_from_index.clear();
    t.mappings_from_used = 0;
    t.mapping_index.clear();
    for (const BaseState* s : mapped_) t.known.emplace(s, 0);
    for (const BaseState* s : independent_) t.known.emplace(s, 0);
    for (const auto* ff : force_fields_)
        for (BaseState* s : ff->states()) {
            std::vector<const BaseForceField*>& on = SystemBuildLists::list_of(s, t.fields_on_index, t.fields_on, t.fields_on_used);
            if (on.empty() || on.back() != ff) on.push_back(ff);  // a field listing a state twice counts once
            if (t.known.emplace(s, 0).second) external_.push_back(s);
        }
    for (const auto* m : mappings_) {
        SystemBuildLists::list_of(m->from(), t.mappings_from_index, t.mappings_from, t.mappings_from_used).push_back(m);
        if (t.known.emplace(m->from(), 0).second) external_.push_back(m->from());
    }
    constexpr std::size_t none = PointerIndex<BaseState>::npos;
    const auto fields_on = [&t](const BaseState* s) -> const std::vector<const BaseForceField*>* {
        const std::size_t at = t.fields_on_index.find(s);
        return at == none ? nullptr : &t.fields_on[at];
    };
    const auto mappings_from = [&t](const BaseState* s) -> const std::vector<const BaseMapping*>* {
        const std::size_t at = t.mappings_from_index.find(s);
        return at == none ? nullptr : &t.mappings_from[at];
    };
    for (const BaseState* s : external_) {
        ExternalReaders& r = external_readers_.emplace_back();
        if (const auto* on = fields_on(s)) r.force_fields = *on;
        if (const auto* from = mappings_from(s)) r.mappings = *from;
    }
    for (std::size_t i = 0; i < mappings_.size(); ++i) {
        BaseMapping* m = mappings_[i];
        PENALTY_DEMAND(m->to() == mapped_[i]);
        DxReaders r;
        r.mapping = m;
        r.selective = m->maps_selected_rows();
        // the force fields acting on the mapped state and the mappings reading it, in the
        // subtree's order
        if (const auto* on = fields_on(m->to())) r.force_fields = *on;
        if (const auto* from = mappings_from(m->to())) r.mappings = *from;
        if (r.selective) {
            // map_dx's scratch at its largest: no allocation in a product
            dx_read_.reserve(std::max(dx_read_.capacity(), m->to()->num_dofs()));
            r.rows.reserve(m->to()->num_dofs());
        }
        dx_readers_.push_back(std::move(r));
    }
    for (std::size_t i = 0; i < mappings_.size(); ++i) t.mapping_index.emplace(mappings_[i], i);
    for (std::vector<ForceStep>* steps : {&force_steps_, &graph_force_steps_})
        for (ForceStep& s : *steps)
            if (s.mapping != nullptr) {
                s.mapping_index = t.mapping_index.find(s.mapping);
                PENALTY_DEMAND(s.mapping_index != PointerIndex<BaseMapping>::npos);
            }
    find_fused_contacts(fuse_contact_products);
}

void SubtreeSystem::find_fused_contacts(bool fuse) {
    fused_mapping_of_.assign(mappings_.size(), -1);
    all_mappings_.resize(mappings_.size());
    for (std::size_t i = 0; i < mappings_.size(); ++i) all_mappings_[i] = i;
    if (!fuse) return;
    // Candidates: barycentric contact mappings between Vec3 states whose output is read by one
    // force field and no mapping.
    struct Candidate {
        std::size_t mapping_index;
        Vec3Object* from;
        Vec3Object* to;
    };
    // tables kept by the thread from one build to the next (see the constructor)
    struct Tables {
        std::vector<Candidate> candidates;
        PointerIndex<BaseState> candidate_on;          // output state → its entry of candidates
        PointerIndex<Vec3Object> unread_group_of;      // parent → unread_by_parent_
        PointerIndex<BaseState> external;
        PointerIndex<BaseForceField> fused_field_of;  // field → fused_fields_
    };
    thread_local Tables tables;
    Tables& t = tables;
    t.candidates.clear();
    t.candidate_on.clear();
    t.unread_group_of.clear();
    t.external.clear();
    t.fused_field_of.clear();
    constexpr std::size_t none = PointerIndex<BaseState>::npos;
    for (std::size_t i = 0; i < mappings_.size(); ++i) {
        const DxReaders& r = dx_readers_[i];
        if (mappings_[i]->contact_barycentric_rows() == nullptr || !r.mappings.empty() || r.force_fields.size() > 1) continue;
        auto* from = dynamic_cast<Vec3Object*>(mappings_[i]->from());
        auto* to = dynamic_cast<Vec3Object*>(mappings_[i]->to());
        if (from == nullptr || to == nullptr) continue;
        if (r.force_fields.size() == 1) {
            if (t.candidate_on.emplace(to, t.candidates.size()).second) t.candidates.push_back(Candidate{i, from, to});
            continue;
        }
        // read by nobody in the subtree
        const auto [group, added] = t.unread_group_of.emplace(from, unread_by_parent_.size());
        if (added) unread_by_parent_.emplace_back(from, std::vector<std::size_t>{});
        unread_by_parent_[group].second.push_back(fused_mappings_.size());
        fused_mapping_of_[i] = static_cast<std::ptrdiff_t>(fused_mappings_.size());
        fused_mappings_.push_back({.mapping_index = i, .from = from, .to = to, .rows = mappings_[i]->contact_barycentric_rows(), .live = false});
    }
    for (const BaseState* s : external_) t.external.emplace(s, 0);
    for (BaseForceField* ff : force_fields_) {
        auto* field = dynamic_cast<Vec3InteractionForceField*>(ff);
        if (field == nullptr || &field->state1() == &field->state2()) continue;
        std::array<const Candidate*, 2> mapping_of_side{nullptr, nullptr};
        bool fusable = true;
        for (std::size_t side = 0; side < 2; ++side) {
            const Vec3Object* state = side == 0 ? &field->state1() : &field->state2();
            if (const std::size_t at = t.candidate_on.find(state);
                at != none && dx_readers_[t.candidates[at].mapping_index].force_fields.front() == ff)
                mapping_of_side[side] = &t.candidates[at];
            else if (!t.external.contains(state))
                fusable = false;  // a state others read or write: the field keeps its place
        }
        if (!fusable || (mapping_of_side[0] == nullptr && mapping_of_side[1] == nullptr)) continue;
        FusedField entry;
        entry.field = field;
        for (std::size_t side = 0; side < 2; ++side) {
            const Candidate* c = mapping_of_side[side];
            if (c == nullptr) {
                entry.sides[side].state = side == 0 ? &field->state1() : &field->state2();
                continue;
            }
            fused_mapping_of_[c->mapping_index] = static_cast<std::ptrdiff_t>(fused_mappings_.size());
            entry.sides[side].mapping = static_cast<std::ptrdiff_t>(fused_mappings_.size());
            fused_mappings_.push_back({.mapping_index = c->mapping_index,
                                       .from = c->from,
                                       .to = c->to,
                                       .rows = mappings_[c->mapping_index]->contact_barycentric_rows()});
        }
        t.fused_field_of.emplace(ff, fused_fields_.size());
        fused_fields_.push_back(entry);
    }
    if (fused_mappings_.empty()) return;
    for (std::vector<ForceStep>* steps : {&force_steps_, &graph_force_steps_})
        for (ForceStep& s : *steps) {
            if (s.mapping != nullptr) s.fused = fused_mapping_of_[s.mapping_index];
            else if (s.force_field != nullptr)
                if (const std::size_t at = t.fused_field_of.find(s.force_field); at != none) s.fused = static_cast<std::ptrdiff_t>(at);
        }
    for (std::size_t i = 0; i < mappings_.size(); ++i)
        if (fused_mapping_of_[i] < 0) unfused_mappings_.push_back(i);
    for (const ForceStep& s : mapping_graph_order_ ? graph_force_steps_ : force_steps_) {
        const bool dropped = s.fused >= 0 && (s.force_field != nullptr || !fused_mappings_[std::size_t(s.fused)].live);
        if (!dropped) fused_steps_.push_back(s);
    }
    std::size_t points = 0, parent_dofs = 0;
    for (const FusedMapping& m : fused_mappings_) {
        if (m.live) points += m.to->num_dofs();
        parent_dofs = std::max(parent_dofs, m.from->num_dofs());
    }
    fused_rows_.reserve(points);  // today's sizes: no allocation in this step's products
    fused_dx_.reserve(points);
    fused_df_.reserve(points);
    zero_add_kind_.reserve(parent_dofs);
    zero_adds_.reserve(parent_dofs * unread_by_parent_.size());
}

SubtreeSystem::FusedContactCounts SubtreeSystem::fused_contact_counts() const {
    FusedContactCounts counts;
    counts.force_fields = fused_fields_.size();
    for (const FusedMapping& m : fused_mappings_) ++(m.live ? counts.read_mappings : counts.unread_mappings);
    return counts;
}

void SubtreeSystem::prepare_fused_contacts() const {
    std::size_t total = 0;
    for (const FusedMapping& m : fused_mappings_) {
        PENALTY_DEMAND(m.rows->size() == m.to->num_dofs());
        if (!m.live) continue;
        m.first = total;
        m.count = m.rows->size();
        total += m.count;
    }
    fused_rows_.resize(total);
    fused_dx_.resize(total);
    fused_df_.resize(total);
    for (const FusedMapping& m : fused_mappings_)
        if (m.live) std::copy(m.rows->begin(), m.rows->end(), fused_rows_.begin() + static_cast<std::ptrdiff_t>(m.first));
    // The unread mappings' Jᵀ: w·(+0) into each row entry; +0 when w is finite and not
    // negative-signed, −0 (adds nothing) when negative-signed, NaN when not finite.
    zero_adds_.clear();
    for (const auto& [parent, unread] : unread_by_parent_) {
        zero_add_kind_.assign(parent->num_dofs(), 0);
        for (const std::size_t index : unread)
            for (const ContactBarycentricRow& row : *fused_mappings_[index].rows)
                for (const ContactBarycentricRow::Entry& e : row) {
                    std::uint8_t& kind = zero_add_kind_[static_cast<std::size_t>(e.index)];
                    if (!std::isfinite(e.weight)) kind = 2;
                    else if (!std::signbit(e.weight)) kind = std::max<std::uint8_t>(kind, 1);
                }
        for (std::size_t dof = 0; dof < zero_add_kind_.size(); ++dof)
            if (zero_add_kind_[dof] != 0)
                zero_adds_.push_back({&parent->df[dof], zero_add_kind_[dof] == 2 ? std::numeric_limits<double>::quiet_NaN() : 0.0});
    }
    fused_ready_ = true;
}

void SubtreeSystem::apply_fused_fields(double k, double b) const {
    for (const FusedField& f : fused_fields_) {
        std::array<Vec3Span, 2> df;
        std::array<ConstVec3Span, 2> dx;
        for (std::size_t side = 0; side < 2; ++side) {
            const FusedSide& s = f.sides[side];
            if (s.mapping < 0) {  // external: dx 0, df scratch
                dx[side] = s.state->dx;
                df[side] = s.state->df;
                continue;
            }
            const FusedMapping& m = fused_mappings_[static_cast<std::size_t>(s.mapping)];
            const std::span<const Vec3> in(m.from->dx);
            const ContactBarycentricRow* rows = fused_rows_.data() + m.first;
            Vec3* out_dx = fused_dx_.data() + m.first;
            Vec3* out_df = fused_df_.data() + m.first;
            // ContactPointMapping::apply_dx (the mapper's apply_j) and the zeroing of the mapped df
            for (std::size_t i = 0; i < m.count; ++i) {
                out_dx[i] = rows[i].combine(in);
                out_df[i].setZero();
            }
            dx[side] = ConstVec3Span(out_dx, m.count);
            df[side] = Vec3Span(out_df, m.count);
        }
        f.field->add_dforce(df[0], df[1], dx[0], dx[1], k, b);
    }
}

void SubtreeSystem::spread_fused_mapping(const FusedMapping& m) const {
    // ContactPointMapping::apply_jt_df (the mapper's apply_jt): from.df += Jᵀ·df, rows in order
    const std::span<Vec3> out(m.from->df);
    const ContactBarycentricRow* rows = fused_rows_.data() + m.first;
    const Vec3* df = fused_df_.data() + m.first;
    for (std::size_t i = 0; i < m.count; ++i) rows[i].spread(out, df[i]);
}

bool SubtreeSystem::list_rows_read(const BaseState& state, const std::vector<const BaseForceField*>& force_fields,
                                   const std::vector<const BaseMapping*>& mappings) const {
    listed_rows_.clear();
    for (const BaseForceField* ff : force_fields)
        if (!ff->list_dx_read(state, listed_rows_)) return false;
    for (const BaseMapping* m : mappings)
        if (!m->list_inputs_read(listed_rows_)) return false;
    const std::size_t dofs = state.num_dofs();
    for (const std::uint32_t row : listed_rows_) PENALTY_DEMAND(row < dofs);
    return true;
}

namespace {
/// Zeroes the DOFs `rows` of a flat vector of DOFs `width` scalars wide.
void zero_rows(FlatVector v, Eigen::Index width, const std::vector<std::uint32_t>& rows) {
    if (width == 3) {  // three stores a row (a segment of run-time size is a call to memset per row)
        for (const std::uint32_t row : rows) v.segment<3>(3 * static_cast<Eigen::Index>(row)).setZero();
        return;
    }
    for (const std::uint32_t row : rows) v.segment(width * static_cast<Eigen::Index>(row), width).setZero();
}
}  // namespace

void SubtreeSystem::clear_external_scratch(bool forces) const {
    for (std::size_t i = 0; i < external_.size(); ++i) {
        BaseState& s = *external_[i];
        const bool listed = s.is_static() && s.num_dofs() >= kMinDofsForScratchRows &&
                            list_rows_read(s, external_readers_[i].force_fields, external_readers_[i].mappings);
        BaseState::ScratchRows& record = forces ? s.static_force_rows : s.static_work_rows;
        const auto width = static_cast<Eigen::Index>(s.deriv_size());
        const auto clear = [&](FlatVector v) {
            if (listed && record.holds_for(s.num_dofs()) && v.size() == static_cast<Eigen::Index>(s.scalar_size())) {
                // every other row is 0 (only solves write a static state's scratch), and so are
                // then the rows listed now, which the solve may write
                zero_rows(v, width, record.rows);
            } else {
                v.setZero();
            }
        };
        if (forces) {
            clear(s.force_flat());
        } else {
            clear(s.dx_flat());
            clear(s.df_flat());
        }
        if (!s.is_static()) continue;
        record.known = listed;
        record.dofs = s.num_dofs();
        if (listed) record.rows.swap(listed_rows_);
    }
}

void SubtreeSystem::find_read_rows(const DxReaders& r) const {
    r.restricted = false;
    r.found = readers_fixed_;
    if (!r.selective) return;
    const BaseState& state = *r.mapping->to();
    const std::size_t dofs = state.num_dofs();
    if (!list_rows_read(state, r.force_fields, r.mappings)) return;
    dx_read_.assign(dofs, 0);
    for (const std::uint32_t row : listed_rows_) dx_read_[row] = 1;
    r.rows.clear();
    for (std::size_t i = 0; i < dofs; ++i)
        if (dx_read_[i] != 0) r.rows.push_back(static_cast<std::uint32_t>(i));
    r.restricted = r.rows.size() != dofs;
}

void SubtreeSystem::map_dx(const DxReaders& r) const {
    if (!(readers_fixed_ && r.found)) find_read_rows(r);
    if (r.restricted) r.mapping->apply_dx_rows(r.rows);
    else r.mapping->apply_dx();
}

SubtreeSystem::FixedReaders::FixedReaders(const SubtreeSystem& system) : system_(system) {
    PENALTY_DEMAND(!system_.readers_fixed_);
    for (const DxReaders& r : system_.dx_readers_) r.found = false;
    system_.readers_fixed_ = true;
    system_.fused_ready_ = false;
}

SubtreeSystem::FixedReaders::~FixedReaders() {
    system_.readers_fixed_ = false;
    for (const DxReaders& r : system_.dx_readers_) r.found = false;
}

void SubtreeSystem::collect(Node& node, bool /*is_root*/) {
    if (BaseState* s = node.state()) {
        if (node.mapping()) {
            if (node.mapping()->to() != s) throw_invalid_argument("Node '", node.name(), "': the mapping output is not the node's state");
            mapped_.push_back(s);
            mappings_.push_back(node.mapping());
        } else {
            offsets_.push_back(size_);
            offset_of_[s] = size_;
            independent_.push_back(s);
            sizes_.push_back(static_cast<Eigen::Index>(s->scalar_size()));
            widths_.push_back(static_cast<Eigen::Index>(s->deriv_size()));
            size_ += sizes_.back();
        }
    } else if (node.mapping()) {
        throw_invalid_argument("Node '", node.name(), "': a mapping needs the node's state as output");
    }
    if (BaseMass* m = node.mass()) {
        if (node.mapping()) throw_invalid_argument("Node '", node.name(), "': a mass on a mapped state is not supported");
        masses_.emplace_back(m, node.gravity());
        force_steps_.push_back({.mass = m, .gravity = node.gravity()});
    }
    for (const auto& ff : node.force_fields()) {
        force_fields_.push_back(ff.get());
        force_steps_.push_back({.force_field = ff.get()});
    }
    for (const auto& c : node.constraints()) constraints_.push_back(c.get());
    for (const auto& child : node.children()) collect(*child, false);
    // SOFA's bottom-up pass (MechanicalVisitor::processNodeBottomUp, post-order): a node's
    // mapping adds Jᵀ·f into its parent once the node's own children have added theirs, and
    // siblings in child order, so a parent sums its children's forces first child first
    if (node.state() && node.mapping()) force_steps_.push_back({.mapping = node.mapping()});
}

namespace {
/// The scratch of SubtreeSystem::order_as_mapping_graph, kept by each thread from one build to
/// the next: a pile of bodies builds its solver's system again at nearly every step, as contacts
/// come and go, and its graph has thousands of nodes. Refilled at each build, never freed.
struct MappingGraphScratch {
    std::vector<BaseState*> states;          // the graph's state nodes, in visiting order
    PointerIndex<BaseState> state_node;      // state → its first node
    PointerIndex<BaseState> first_group_of;  // state → the first group acting on it
    /// The groups: the distinct lists of states a force field or mass acts on (at most two
    /// states, ForceFieldStates), in order of first appearance, found by an open-addressing
    /// table of their lists.
    struct Group {
        std::array<const BaseState*, 2> states{};
        std::size_t count = 0;
        bool operator==(const Group&) const = default;
    };
    std::vector<Group> groups;
    std::vector<std::size_t> group_slots;  // size a power of two: a group's index + 1, 0 empty
    std::vector<std::size_t> step_group;   // per non-mapping force step, in force_steps_ order
    std::vector<std::array<std::size_t, 2>> edges;  // (from, to), in the order they were added
    std::vector<std::size_t> parents;               // per node: parents not yet reached
    std::vector<std::size_t> first_child;           // per node + 1: its children in `children`
    std::vector<std::size_t> children;
    std::vector<std::size_t> ready;  // the breadth-first queue
    std::vector<BaseMapping*> reached;  // the mappings in breadth-first order
    std::vector<std::array<std::size_t, 2>> group_steps;  // (group, step) per non-mapping step
    std::vector<std::size_t> first_member;  // per group + 1: its steps in `members`
    std::vector<std::size_t> members;

    /// The index of `g`, added at the end when new.
    std::size_t group_index(const Group& g) {
        if (2 * (groups.size() + 1) > group_slots.size()) {
            group_slots.assign(std::max<std::size_t>(32, 2 * group_slots.size()), 0);
            for (std::size_t i = 0; i < groups.size(); ++i) group_slots[probe(groups[i])] = i + 1;
        }
        std::size_t& slot = group_slots[probe(g)];
        if (slot == 0) {
            groups.push_back(g);
            slot = groups.size();
        }
        return slot - 1;
    }
    void clear() {
        states.clear();
        state_node.clear();
        first_group_of.clear();
        groups.clear();
        std::fill(group_slots.begin(), group_slots.end(), 0);
        step_group.clear();
        edges.clear();
    }

private:
    [[nodiscard]] std::size_t probe(const Group& g) const {
        // the two addresses' hashes combined (rotated apart), and the count (a list {a} ≠ {a, null})
        const std::uint64_t second = address_hash(g.states[1]) + g.count;
        const std::uint64_t h = address_hash(g.states[0]) ^ ((second << 31) | (second >> 33));
        const std::size_t mask = group_slots.size() - 1;
        std::size_t i = std::size_t(h ^ (h >> 29)) & mask;
        while (group_slots[i] != 0 && !(groups[group_slots[i] - 1] == g)) i = (i + 1) & mask;
        return i;
    }
};

/// Sorts `pairs` (key, value) into CSR form by key, each key's values in their order in `pairs`
/// (a counting sort): key k's values are values[first[k] .. first[k + 1]).
template <class Pairs>
void bucket_by_key(const Pairs& pairs, std::size_t keys, std::vector<std::size_t>& first, std::vector<std::size_t>& values) {
    first.assign(keys + 1, 0);
    for (const auto& p : pairs) ++first[p[0] + 1];
    for (std::size_t k = 0; k < keys; ++k) first[k + 1] += first[k];
    values.resize(pairs.size());
    for (const auto& p : pairs) values[first[p[0]]++] = p[1];
    for (std::size_t k = keys; k > 0; --k) first[k] = first[k - 1];  // first[k] was advanced to first[k + 1]
    first[0] = 0;
}
}  // namespace

void SubtreeSystem::order_as_mapping_graph(Node& root) {
    // SOFA's MappingGraph::build on the solver's node: nodes for the states (visiting order),
    // one group per distinct list of states a force field or mass acts on (edges state → group),
    // the mappings (edges from the first group holding the input state, else from the state; then
    // mapping → output state). The force fields' leaf nodes always hang under their group and
    // cannot change the order in which mappings are reached, so they are left out. Node numbers:
    // the states, then the groups, then the mappings. Lookups by open-addressing tables, not
    // searches of the lists (a pile of bodies has thousands of contact states, fields and
    // mappings); the first of equal entries wins, as searches of the lists would find.
    thread_local MappingGraphScratch scratch;
    MappingGraphScratch& g = scratch;
    g.clear();
    const auto visit_states = [&g](auto& self, Node& n) -> void {
        if (BaseState* s = n.state()) g.states.push_back(s);
        for (const auto& c : n.children()) self(self, *c);
    };
    visit_states(visit_states, root);
    const std::size_t state_count = g.states.size();
    for (std::size_t i = 0; i < state_count; ++i) g.state_node.emplace(g.states[i], i);
    std::vector<std::array<std::size_t, 2>>& edges = g.edges;
    for (const ForceStep& step : force_steps_) {
        if (step.mapping != nullptr) continue;
        MappingGraphScratch::Group key;
        if (step.mass != nullptr) {
            key.states[0] = step.mass->state();
            key.count = 1;
        } else {
            const ForceFieldStates acted_on = step.force_field->states();
            for (std::size_t i = 0; i < acted_on.size(); ++i) key.states[i] = acted_on[i];
            key.count = acted_on.size();
        }
        const std::size_t known = g.groups.size();
        const std::size_t group = g.group_index(key);
        if (group == known) {  // a new group: its node is state_count + group
            for (std::size_t i = 0; i < key.count; ++i) {
                const BaseState* s = key.states[i];
                if (const std::size_t node = g.state_node.find(s); node != PointerIndex<BaseState>::npos)
                    edges.push_back({node, state_count + group});
                g.first_group_of.emplace(s, group);
            }
        }
        g.step_group.push_back(group);
    }
    const std::size_t first_mapping = state_count + g.groups.size();
    for (std::size_t i = 0; i < mappings_.size(); ++i) {
        const BaseMapping* m = mappings_[i];
        const std::size_t node = first_mapping + i;
        if (const std::size_t holder = g.first_group_of.find(m->from()); holder != PointerIndex<BaseState>::npos)
            edges.push_back({state_count + holder, node});
        else if (const std::size_t from = g.state_node.find(m->from()); from != PointerIndex<BaseState>::npos)
            edges.push_back({from, node});
        if (const std::size_t to = g.state_node.find(m->to()); to != PointerIndex<BaseState>::npos) edges.push_back({node, to});
    }
    // MappingGraphAlgorithms::traverseBottomUp: the breadth-first order from the parentless nodes
    // (in node order), each node's children in the order of their edges; reversed.
    const std::size_t node_count = first_mapping + mappings_.size();
    bucket_by_key(edges, node_count, g.first_child, g.children);
    g.parents.assign(node_count, 0);
    for (const auto& e : edges) ++g.parents[e[1]];
    g.ready.clear();
    for (std::size_t n = 0; n < node_count; ++n)
        if (g.parents[n] == 0) g.ready.push_back(n);
    g.reached.clear();
    for (std::size_t head = 0; head < g.ready.size(); ++head) {
        const std::size_t n = g.ready[head];
        if (n >= first_mapping) g.reached.push_back(mappings_[n - first_mapping]);
        for (std::size_t c = g.first_child[n]; c < g.first_child[n + 1]; ++c)
            if (--g.parents[g.children[c]] == 0) g.ready.push_back(g.children[c]);
    }
    // the groups' members (steps in force_steps_ order), group after group, then the mappings
    // in the reverse of the order reached
    g.group_steps.clear();
    std::size_t k = 0;
    for (std::size_t i = 0; i < force_steps_.size(); ++i)
        if (force_steps_[i].mapping == nullptr) g.group_steps.push_back({g.step_group[k++], i});
    bucket_by_key(g.group_steps, g.groups.size(), g.first_member, g.members);
    graph_force_steps_.clear();
    graph_force_steps_.reserve(g.members.size() + g.reached.size());
    for (const std::size_t i : g.members) graph_force_steps_.push_back(force_steps_[i]);
    for (auto it = g.reached.rbegin(); it != g.reached.rend(); ++it) graph_force_steps_.push_back({.mapping = *it});
}

bool SubtreeSystem::offsets_valid() const {
    Eigen::Index end = 0;
    for (std::size_t i = 0; i < independent_.size(); ++i) {
        if (offsets_[i] != end) return false;
        end += static_cast<Eigen::Index>(independent_[i]->scalar_size());
    }
    return end == size_;
}

SubtreeSystem& SubtreeSystemCache::get(Node& node, bool mapping_graph_order, bool fuse_contact_products) {
    const std::uint64_t version = node.structure_version();
    if (!system_ || node_ != &node || version_ != version || !system_->offsets_valid() ||
        system_->mapping_graph_order() != mapping_graph_order || system_->fuses_contact_products() != fuse_contact_products) {
        system_.reset();  // the old system first: its pointers may dangle
        system_.emplace(node, mapping_graph_order, fuse_contact_products);
        node_ = &node;
        version_ = version;
        ++builds_;
    }
    return *system_;
}

void SubtreeSystem::append_states(std::vector<const BaseState*>& out) const {
    out.insert(out.end(), independent_.begin(), independent_.end());
    out.insert(out.end(), mapped_.begin(), mapped_.end());
    out.insert(out.end(), external_.begin(), external_.end());
}

Index SubtreeSystem::offset(const BaseState* s) const {
    const auto it = offset_of_.find(s);
    return it == offset_of_.end() ? static_cast<Index>(size_) : it->second;
}

double SubtreeSystem::dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
    double total = 0.0;
    for (std::size_t s = 0; s < independent_.size(); ++s) {
        const Eigen::Index begin = offsets_[s];
        const Eigen::Index end = begin + sizes_[s];
        total += state_dot(a.data(), b.data(), begin, end, widths_[s]);
    }
    return total;
}

void SubtreeSystem::gather_velocity(Eigen::VectorXd& v) const {
    v.resize(size_);
    for (std::size_t i = 0; i < independent_.size(); ++i)
        v.segment(offsets_[i], sizes_[i]) = independent_[i]->velocity_flat();
}

void SubtreeSystem::scatter_velocity(const Eigen::VectorXd& v) const {
    for (std::size_t i = 0; i < independent_.size(); ++i)
        independent_[i]->velocity_flat() = v.segment(offsets_[i], sizes_[i]);
}

void SubtreeSystem::add_to_positions(double h, const Eigen::VectorXd& v) const {
    for (std::size_t i = 0; i < independent_.size(); ++i)
        independent_[i]->add_to_position(h, v.segment(offsets_[i], sizes_[i]));
}

void SubtreeSystem::propagate_positions_and_velocities() const {
    for (BaseMapping* m : mappings_) {
        m->apply_position();
        m->apply_velocity();
    }
}

void SubtreeSystem::reset_forces() const {
    for (BaseState* s : independent_) s->force_flat() = s->external_force_flat();
    for (BaseState* s : mapped_) s->force_flat() = s->external_force_flat();
    clear_external_scratch(/*forces=*/true);
}

std::vector<BaseState*> SubtreeSystem::all_states() const {
    std::vector<BaseState*> all(independent_);
    all.insert(all.end(), mapped_.begin(), mapped_.end());
    all.insert(all.end(), external_.begin(), external_.end());
    return all;
}

void SubtreeSystem::throw_non_finite_force() const {
    // The states a contribution writes into, checked after each contribution in compute_force's
    // order; velocities that are already non-finite are named first (the runner checks positions).
    const std::vector<BaseState*> all = all_states();
    const auto first_bad = [&](bool kinematics) -> const BaseState* {
        for (const BaseState* s : all) {
            if (kinematics ? !const_cast<BaseState*>(s)->velocity_flat().allFinite()
                           : !const_cast<BaseState*>(s)->force_flat().allFinite())
                return s;
        }
        return nullptr;
    };
    if (const BaseState* s = first_bad(true))
        throw NonFiniteSolveError("the velocities of state '" + std::string(s->state_name()) + "' are not finite",
                                  nullptr, nullptr, s);
    reset_forces();
    if (const BaseState* s = first_bad(false))
        throw NonFiniteSolveError("the external forces on state '" + std::string(s->state_name()) + "' are not finite",
                                  nullptr, nullptr, s);
    for (const auto& [mass, g] : masses_) {
        mass->add_gravity_force(g);
        if (const BaseState* s = first_bad(false))
            throw NonFiniteSolveError("the gravity force m·g on state '" + std::string(s->state_name()) + "' is not finite",
                                      nullptr, mass, s);
    }
    for (BaseForceField* ff : force_fields_) {
        ff->accumulate_force();
        if (const BaseState* s = first_bad(false))
            throw NonFiniteSolveError("a force field's force on state '" + std::string(s->state_name()) + "' is not finite",
                                      ff, nullptr, s);
    }
    throw NonFiniteSolveError("the forces are not finite after the mappings' Jᵀ", nullptr, nullptr, nullptr);
}

void SubtreeSystem::throw_naming_largest_force(const std::string& what) const {
    // Each contribution alone, in compute_force's order; the one with the largest |f|∞ is named
    // (an overflow of |b| or of a CG product starts from the largest force).
    const std::vector<BaseState*> all = all_states();
    const auto largest = [&](const BaseState*& where) {
        double m = 0.0;
        for (BaseState* s : all) {
            const double v = s->force_flat().size() > 0 ? s->force_flat().cwiseAbs().maxCoeff() : 0.0;
            if (!(v <= m)) {  // NaN counts as largest
                m = v;
                where = s;
            }
        }
        return m;
    };
    double best = -1.0;
    const BaseForceField* best_ff = nullptr;
    const BaseMass* best_mass = nullptr;
    const BaseState* best_state = nullptr;
    const auto consider = [&](const BaseForceField* ff, const BaseMass* mass) {
        const BaseState* where = nullptr;
        const double m = largest(where);
        if (!(m <= best)) {
            best = m;
            best_ff = ff;
            best_mass = mass;
            best_state = where;
        }
    };
    for (const auto& [mass, g] : masses_) {
        reset_forces();
        for (BaseState* s : all) s->force_flat().setZero();
        mass->add_gravity_force(g);
        consider(nullptr, mass);
    }
    for (BaseForceField* ff : force_fields_) {
        for (BaseState* s : all) s->force_flat().setZero();
        ff->accumulate_force();
        consider(ff, nullptr);
    }
    std::string source;
    char magnitude[32];
    std::snprintf(magnitude, sizeof magnitude, "%.6g", best);
    if (best_state != nullptr)
        source = "; the largest force (" + std::string(magnitude) + " N) is " +
                 (best_mass != nullptr ? "the gravity force m·g" : "a force field's") + " on state '" +
                 std::string(best_state->state_name()) + "'";
    throw NonFiniteSolveError(what + source, best_ff, best_mass, best_state);
}

void SubtreeSystem::compute_force(Eigen::VectorXd& f) const {
    external_work_zeroed_ = false;  // a new solve: another solver may have used the external states
    reset_forces();
    // computeForce: SOFA HEAD's MappingGraph order (mapping_graph_order) or its visitors' order
    for (const ForceStep& s : mapping_graph_order_ ? graph_force_steps_ : force_steps_) {
        if (s.mass != nullptr) s.mass->add_gravity_force(s.gravity);
        else if (s.force_field != nullptr) s.force_field->accumulate_force();
        else s.mapping->apply_jt_force();
    }
    f.resize(size_);
    for (std::size_t i = 0; i < independent_.size(); ++i)
        f.segment(offsets_[i], sizes_[i]) = independent_[i]->force_flat();
    if (!f.allFinite()) throw_non_finite_force();
}

void SubtreeSystem::apply_mbk(const Eigen::VectorXd& dx, Eigen::VectorXd& out, double m, double b, double k,
                              bool do_project, bool accumulate) const {
    if (accumulate) PENALTY_DEMAND(out.size() == size_);
    for (std::size_t i = 0; i < independent_.size(); ++i) {
        const auto n = sizes_[i];
        independent_[i]->dx_flat() = dx.segment(offsets_[i], n);
        // accumulate: each contribution is added to out's value in turn, as SOFA's addMBKv
        // adds into b = f (((f + c1) + c2) ..., not f + (c1 + c2 ...)).
        if (accumulate) independent_[i]->df_flat() = out.segment(offsets_[i], n);
        else independent_[i]->df_flat().setZero();
    }
    apply_mbk_to_states(m, b, k);
    out.resize(size_);
    for (std::size_t i = 0; i < independent_.size(); ++i)
        out.segment(offsets_[i], sizes_[i]) = independent_[i]->df_flat();
    if (do_project) project(out);
}


double SubtreeSystem::direction_and_mbk(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                        Eigen::VectorXd& q, double m, double b, double k) const {
    PENALTY_DEMAND(r.size() == size_ && p.size() == size_ && &r != &p);
    // p = r or r + β·p (Eigen's p = r + β·p: each r_j + (β·p_j)), into p and the state's dx
    for (std::size_t i = 0; i < independent_.size(); ++i) {
        const auto n = sizes_[i];
        const double* rs = r.data() + offsets_[i];
        double* ps = p.data() + offsets_[i];
        direction(first, beta, rs, ps, independent_[i]->dx_flat().data(), n);
        independent_[i]->df_flat().setZero();
    }
    apply_mbk_to_states(m, b, k);
    q.resize(size_);
    if (!constraints_.empty()) {  // q is projected before p·q
        for (std::size_t i = 0; i < independent_.size(); ++i)
            q.segment(offsets_[i], sizes_[i]) = independent_[i]->df_flat();
        project(q);
        return dot(p, q);
    }
    double total = 0.0;  // dot(p, q), each state's sum as its part of q is copied
    for (std::size_t i = 0; i < independent_.size(); ++i) {
        const auto n = sizes_[i];
        const Eigen::Index begin = offsets_[i];
        q.segment(begin, n) = independent_[i]->df_flat();
        total += state_dot(p.data(), q.data(), begin, begin + n, widths_[i]);
    }
    return total;
}

double SubtreeSystem::update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
                                          Eigen::VectorXd& x, Eigen::VectorXd& r) const {
    PENALTY_DEMAND(p.size() == size_ && q.size() == size_ && x.size() == size_ && r.size() == size_);
    const double* ps = p.data();
    const double* qs = q.data();
    double* xs = x.data();
    double* rs = r.data();
    double total = 0.0;  // dot(r, r), each state's sum over its DOFs as they are updated
    for (std::size_t i = 0; i < independent_.size(); ++i) {
        const Eigen::Index begin = offsets_[i];
        const Eigen::Index end = begin + sizes_[i];
        const auto width = widths_[i];
        // x += α·p, r −= α·q (Eigen's: x_j + (α·p_j), r_j − (α·q_j)), then the DOF's r·r
        if (width == 3) {
            double sum = 0.0;
            for (Eigen::Index j = begin; j < end; j += 3) {
                for (Eigen::Index c = j; c < j + 3; ++c) {
                    xs[c] += alpha * ps[c];
                    rs[c] -= alpha * qs[c];
                }
                sum += (rs[j] * rs[j] + rs[j + 1] * rs[j + 1]) + rs[j + 2] * rs[j + 2];
            }
            total += sum;
            continue;
        }
        for (Eigen::Index j = begin; j < end; ++j) {
            xs[j] += alpha * ps[j];
            rs[j] -= alpha * qs[j];
        }
        total += state_dot(rs, rs, begin, end, width);
    }
    return total;
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
    if (!external_work_zeroed_) {
        clear_external_scratch(/*forces=*/false);
        external_work_zeroed_ = true;
    }
    // The fused contact block (see the header): only while the contacts cannot change.
    const bool fused = readers_fixed_ && !fused_mappings_.empty();
    if (fused && !fused_ready_) prepare_fused_contacts();
    // The loops below call thousands of small objects (a contact pair's states and mappings) a
    // product, each a cache miss on its first word: fetched kObjectsAhead iterations earlier.
    // (fused: only the mappings the fused block does not apply, in the same order)
    const std::vector<std::size_t>& maps = fused ? unfused_mappings_ : all_mappings_;
    for (std::size_t j = 0; j < maps.size(); ++j) {
        if (j + kObjectsAhead < maps.size()) __builtin_prefetch(dx_readers_[maps[j + kObjectsAhead]].mapping);
        map_dx(dx_readers_[maps[j]]);
    }
    for (std::size_t j = 0; j < maps.size(); ++j) {
        if (j + kObjectsAhead < maps.size()) __builtin_prefetch(mapped_[maps[j + kObjectsAhead]]);
        const std::size_t i = maps[j];
        const DxReaders& r = dx_readers_[i];
        if (!r.restricted) {
            mapped_[i]->df_flat().setZero();
            continue;
        }
        // only the rows read (and written) by the readers; Jᵀ takes no other (apply_jt_df_rows)
        zero_rows(mapped_[i]->df_flat(), static_cast<Eigen::Index>(mapped_[i]->deriv_size()), r.rows);
    }
    // the right-hand side's addMBKv and the CG's product in SOFA HEAD's MappingGraph order, or
    // in its visitors' (mapping_graph_order_: see the constructor)
    const std::vector<ForceStep>& steps = fused ? fused_steps_ : mapping_graph_order_ ? graph_force_steps_ : force_steps_;
    // the fused fields read only their contact points' dx and write only their df (and external
    // scratch), which no other step reads or writes: run before the steps, same bits; the
    // unread mappings' Jᵀ is the additions of zeros, which give the same bits in any place
    if (fused) {
        for (const ZeroAdd& z : zero_adds_) {
            double* t = z.target->data();
            t[0] += z.value;
            t[1] += z.value;
            t[2] += z.value;
        }
        apply_fused_fields(k, b);
    }
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const ForceStep& s = steps[i];
        if (fused && s.fused >= 0) {  // a read fused mapping (fused_steps_ holds no other fused step)
            spread_fused_mapping(fused_mappings_[static_cast<std::size_t>(s.fused)]);
            continue;
        }
        if (i + kObjectsAhead < steps.size()) __builtin_prefetch(steps[i + kObjectsAhead].object());
        if (s.mass != nullptr) {
            if (m != 0.0) s.mass->add_mdx(m);
        } else if (s.force_field != nullptr) {
            s.force_field->accumulate_dforce(k, b);
        } else {
            const DxReaders& r = dx_readers_[s.mapping_index];
            if (r.restricted) s.mapping->apply_jt_df_rows(r.rows);
            else s.mapping->apply_jt_df();
        }
    }
}

void SubtreeSystem::project(Eigen::VectorXd& v) const {
    for (BaseProjectiveConstraint* c : constraints_) {
        const auto it = offset_of_.find(c->state());
        if (it == offset_of_.end()) continue;  // constraints on mapped states are not supported
        c->project_response(v.segment(it->second, static_cast<Eigen::Index>(c->state()->scalar_size())));
    }
}

void SubtreeSystem::apply_inverse_mass(const Eigen::VectorXd& in, Eigen::VectorXd& out) const {
    out.setZero(size_);
    for (std::size_t i = 0; i < independent_.size(); ++i) {
        const auto n = sizes_[i];
        const auto it = std::find_if(masses_.begin(), masses_.end(), [&](const auto& e) { return e.first->state() == independent_[i]; });
        if (it == masses_.end()) throw_invalid_argument("EulerExplicitSolver: state '", independent_[i]->state_name(), "' has no mass");
        it->first->apply_inverse(in.segment(offsets_[i], n), out.segment(offsets_[i], n));
    }
}

SparseMatrix SubtreeSystem::assemble(double m, double k) const {
    // Extended index space: independent scalars, then mapped scalars; P maps system DOFs to it.
    std::unordered_map<const BaseState*, Index> ext_offset(offset_of_.begin(), offset_of_.end());
    Index total = size_;
    for (BaseState* s : mapped_) {
        ext_offset[s] = total;
        total += static_cast<Index>(s->scalar_size());
    }
    using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, Eigen::Index>;
    std::unordered_map<const BaseState*, ColMatrix> p_rows;  // (state scalars) x size_
    for (std::size_t i = 0; i < independent_.size(); ++i) {
        const auto n = sizes_[i];
        ColMatrix id(n, size_);
        TripletList t;
        for (Eigen::Index j = 0; j < n; ++j) t.emplace_back(j, offsets_[i] + j, 1.0);
        id.setFromTriplets(t.begin(), t.end());
        p_rows[independent_[i]] = std::move(id);
    }
    for (BaseMapping* map : mappings_) {
        const auto nin = static_cast<Eigen::Index>(map->from()->scalar_size());
        const auto nout = static_cast<Eigen::Index>(map->to()->scalar_size());
        ColMatrix j(nout, nin);
        TripletList t;
        map->add_jacobian_triplets(t, 0, 0);
        j.setFromTriplets(t.begin(), t.end());
        const auto it = p_rows.find(map->from());
        ColMatrix rows = it == p_rows.end() ? ColMatrix(nout, size_) : ColMatrix(j * it->second);
        p_rows[map->to()] = std::move(rows);
    }
    ColMatrix p(total, size_);
    {
        TripletList t;
        for (const auto& [s, rows] : p_rows) {
            const Index o = ext_offset.at(s);
            for (Eigen::Index c = 0; c < rows.outerSize(); ++c)
                for (ColMatrix::InnerIterator itr(rows, c); itr; ++itr) t.emplace_back(o + itr.row(), itr.col(), itr.value());
        }
        p.setFromTriplets(t.begin(), t.end());
    }
    TripletList kt;
    const StateOffsets offs = [&](const BaseState* s) {
        const auto it = ext_offset.find(s);
        return it == ext_offset.end() ? total : it->second;
    };
    for (BaseForceField* ff : force_fields_) ff->add_stiffness(kt, offs, k);
    kt.erase(std::remove_if(kt.begin(), kt.end(), [&](const Triplet& t) { return t.row() >= total || t.col() >= total; }), kt.end());
    ColMatrix kext(total, total);
    kext.setFromTriplets(kt.begin(), kt.end());
    TripletList mt;
    for (const auto& entry : masses_) entry.first->add_mass_triplets(mt, offset(entry.first->state()), m);
    ColMatrix mm(size_, size_);
    mm.setFromTriplets(mt.begin(), mt.end());
    ColMatrix a = ColMatrix(ColMatrix(p.transpose()) * kext * p) + mm;
    return SparseMatrix(a);
}

double SubtreeSystem::total_energy() const {
    double e = 0.0;
    for (const BaseForceField* ff : force_fields_) e += ff->potential_energy();
    for (const auto& [mass, g] : masses_) e += mass->kinetic_energy() + mass->gravity_potential_energy(g);
    return e;
}

// ---- EulerImplicitSolver ----------------------------------------------------------------------
void EulerImplicitSolver::init(Node& node) {
    cg.check();
    // The subtree's structure (mapped states, masses, mappings) is checked here, at init, so
    // that a scene the solver cannot integrate is refused before the run (not at step 0).
    (void)SubtreeSystem(node);
    if (!std::isfinite(rayleigh_stiffness) || rayleigh_stiffness < 0)
        throw_invalid_argument("EulerImplicitSolver: rayleighStiffness must be >= 0, got ", rayleigh_stiffness);
    if (!std::isfinite(rayleigh_mass) || rayleigh_mass < 0)
        throw_invalid_argument("EulerImplicitSolver: rayleighMass must be >= 0, got ", rayleigh_mass);
    if (!std::isfinite(vdamping) || vdamping < 0) throw_invalid_argument("EulerImplicitSolver: vdamping must be >= 0, got ", vdamping);
}

void EulerImplicitSolver::record_cg(const CgStats& stats) {
    last_cg_ = stats;
    step_cg_solves_.push_back(stats);
    step_cg_iterations_ += stats.iterations;
    step_cg_limit_reached_ = step_cg_limit_reached_ || stats.end_condition == CgEndCondition::iterations;
}

std::optional<std::size_t> EulerImplicitSolver::list_touched_states(Node& node, std::vector<const BaseState*>& out) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.append_states(out);
    return static_cast<std::size_t>(sys.size());
}

void EulerImplicitSolver::solve(Node& node, double dt) {
    SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    step_cg_iterations_ = 0;
    step_cg_solves_.clear();
    step_cg_limit_reached_ = false;
    if (newton.enabled) {
        solve_newton(sys, dt);
        return;
    }
    const double h = dt;
    const double tr = trapezoidal_scheme ? 0.5 : 1.0;
    const double rs = rayleigh_stiffness;
    const double rm = rayleigh_mass;
    sys.compute_force(f_);
    sys.gather_velocity(v_);
    const SubtreeSystem::FixedReaders fixed_readers(sys);  // no contact changes until the solve ends
    // SOFA's EulerImplicitSolver::solve: b = f; b += (−rm·M + (h·tr + rs)·K)·v, each force
    // field (and mass) adding into b in turn (MappingGraphMechanicalOperations::addMBKv);
    // b = b·h (b.teq(h)).
    b_ = f_;
    if (!first_order) {
        sys.apply_mbk(v_, b_, -rm, 0.0, h * tr + rs, false, /*accumulate=*/true);
        b_ *= h;
    }
    sys.project(b_);
    // A = mf·M + bf·B + kf·K
    MbkCgSystem system(sys, first_order ? 1.0 : 1.0 + tr * h * rm, first_order ? 0.0 : -tr * h,
                       first_order ? -h * tr : -tr * h * (tr * h + rs));
    try {
        record_cg(cg.solve(system, b_, x_));
    } catch (const NonFiniteSolveError& e) {
        // Finite forces, yet the solve overflowed (|b|², p·q): name the largest force.
        if (e.force_field() == nullptr && e.mass() == nullptr) sys.throw_naming_largest_force(e.what());
        throw;
    }
    // v_new = x (first order) or v + x, kept in v_
    if (first_order) v_ = x_;
    else v_ += x_;
    sys.scatter_velocity(v_);
    sys.add_to_positions(h, v_);
    if (vdamping != 0.0) {
        v_ *= std::exp(-h * vdamping);
        sys.scatter_velocity(v_);
    }
}

void EulerImplicitSolver::solve_newton(SubtreeSystem& sys, double dt) {
    const double h = dt;
    Eigen::VectorXd v0;
    sys.gather_velocity(v0);
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(v0.size());
    Eigen::VectorXd applied = Eigen::VectorXd::Zero(v0.size());  // h·v currently added to x_n
    double r0 = -1.0;
    last_newton_iterations_ = 0;
    last_newton_converged_ = false;
    for (int it = 0; it < newton.max_iterations; ++it) {
        // Iterate: x = x_n + h (v_n + dv) (x = x_n at the first iterate), v = v_n + dv.
        const Eigen::VectorXd v = v0 + dv;
        if (it > 0) {
            const Eigen::VectorXd target = h * v;
            sys.add_to_positions(1.0, target - applied);
            applied = target;
        }
        sys.scatter_velocity(v);
        sys.propagate_positions_and_velocities();
        if (newton.update_geometry) newton.update_geometry();
        const SubtreeSystem::FixedReaders fixed_readers(sys);  // the contacts of this iterate
        Eigen::VectorXd f;
        sys.compute_force(f);
        Eigen::VectorXd mdv;
        sys.apply_mbk(dv, mdv, 1.0, 0.0, 0.0, false);
        // −R = h f − M dv; at it = 0 add the implicit term of the linearisation at x_n.
        Eigen::VectorXd rhs = h * f - mdv;
        if (it == 0) {
            Eigen::VectorXd kv;
            sys.apply_mbk(v, kv, 0.0, 0.0, h, false);
            rhs += h * kv;
        }
        sys.project(rhs);
        const double rn = rhs.norm();
        if (r0 < 0) r0 = std::max(1.0, rn);
        last_newton_iterations_ = it + 1;
        last_newton_residual_ = rn / r0;
        if (it > 0 && rn <= newton.tolerance * r0) {
            last_newton_converged_ = true;
            break;
        }
        Eigen::VectorXd delta;
        MbkCgSystem system(sys, 1.0, -h, -h * h);
        record_cg(cg.solve(system, rhs, delta));
        dv += delta;
    }
    const Eigen::VectorXd v = v0 + dv;
    sys.add_to_positions(1.0, h * v - applied);
    sys.scatter_velocity(v);
}

// ---- EulerExplicitSolver ----------------------------------------------------------------------
void EulerExplicitSolver::init(Node& node) {
    const SubtreeSystem sys(node);
    Eigen::VectorXd probe = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(sys.size()));
    Eigen::VectorXd out;
    sys.apply_inverse_mass(probe, out);  // throws naming a state without a mass
}

std::optional<std::size_t> EulerExplicitSolver::list_touched_states(Node& node, std::vector<const BaseState*>& out) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.append_states(out);
    return static_cast<std::size_t>(sys.size());
}

void EulerExplicitSolver::solve(Node& node, double dt) {
    const SubtreeSystem& sys = system_.get(node, sofa_mapping_graph_order, fuse_contact_products);
    sys.compute_force(f_);
    sys.apply_inverse_mass(f_, a_);
    sys.project(a_);
    sys.gather_velocity(v_);
    v_ += dt * a_;
    sys.scatter_velocity(v_);
    sys.add_to_positions(dt, v_);
}

// ---- Simulation -------------------------------------------------------------------------------
struct Simulation::ThreadArena {
    explicit ThreadArena(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
    tbb::task_arena arena;
};

Simulation::Simulation() : root_("root") {}
Simulation::~Simulation() = default;

void Simulation::set_threads(int threads) {
    if (threads < 0 || threads > kMaxThreads)
        throw_invalid_argument("Simulation: threads must be between 0 and ", kMaxThreads, ", got ", threads);
    if (threads != threads_) arena_.reset();
    threads_ = threads;
}

namespace {
template <class F>
void for_each_node(Node& n, const F& f) {
    f(n);
    for (const auto& c : n.children()) for_each_node(*c, f);
}
}  // namespace

/// SOFA's Simulation::init ends with MechanicalProjectPositionAndVelocityVisitor (time 0) and
/// the propagation of positions and velocities: each constraint's project_position then
/// project_velocity, and the mappings under a node with a constraint that moves positions
/// applied again (the others' outputs are already what they map).
void Simulation::project_initial_state(Node& node, bool moved_above) {
    bool moved = moved_above;
    for (const auto& c : node.constraints()) {
        c->project_position();
        c->project_velocity();
        moved = moved || c->projects_positions();
    }
    if (moved && node.mapping()) {
        node.mapping()->apply_position();
        node.mapping()->apply_velocity();
    }
    for (const auto& child : node.children()) project_initial_state(*child, moved);
}

void Simulation::init() {
    for_each_node(root_, [](Node& n) {
        if (n.mapping()) {
            n.mapping()->init();
        } else if (n.state()) {
            n.state()->init();
        }
    });
    for_each_node(root_, [](Node& n) {
        if (n.mass()) n.mass()->init();
        for (const auto& ff : n.force_fields()) ff->init();
        for (const auto& c : n.constraints()) c->init();
        if (n.ode_solver()) n.ode_solver()->init(n);
    });
    project_initial_state(root_, false);
    initialized_ = true;
}

void Simulation::plan_node(Node& node) {
    // The first node with an ODE solver on a path integrates its whole subtree; at a node without
    // solver, each force field is explicit, then the children.
    if (node.ode_solver() != nullptr) {
        plan_.push_back({&node, nullptr, {}});
        return;
    }
    for (const auto& ff : node.force_fields()) plan_.push_back({nullptr, ff.get(), ff->states()});
    for (const auto& child : node.children()) plan_node(*child);
}

const std::vector<Simulation::SolveAction>& Simulation::solve_plan() {
    if (plan_version_ != root_.structure_version()) {
        plan_.clear();
        plan_node(root_);
        applied_states_.clear();
        applied_index_.clear();
        const auto add = [&](BaseState* s) {
            if (s != nullptr && applied_index_.emplace(s, applied_states_.size()).second) applied_states_.push_back(s);
        };
        for (const SolveAction& a : plan_) {
            if (a.solver_node != nullptr) for_each_node(*a.solver_node, [&](Node& n) { add(n.state()); });
            for (BaseState* s : a.states) add(s);
        }
        for_each_node(root_, [&](Node& n) {
            if (n.mapping()) add(n.state());
        });
        for_each_node(root_, [&](Node& n) {
            if (n.state() != nullptr) n.state()->set_static(!applied_index_.contains(n.state()));
        });
        for (std::size_t i = 0; i < plan_.size(); i = plan_[i].run_end) {
            if (plan_[i].solver_node != nullptr) {
                find_run(i);
            } else {
                plan_[i].run_end = i + 1;
            }
        }
        plan_version_ = root_.structure_version();
    }
    return plan_;
}

void Simulation::run_action(const SolveAction& action, double dt) {
    if (action.solver_node != nullptr) {
        action.solver_node->ode_solver()->solve(*action.solver_node, dt);
        return;
    }
    // Explicit: forces from the start-of-step x, v, added as external forces for the step.
    // As SOFA's SolveVisitor::fwdInteractionForceField (addForce into externalForce): each
    // contribution is added to the external force in turn, ((e + c1) + c2), not e + (c1 + c2).
    for (BaseState* s : action.states) s->force_flat() = s->external_force_flat();
    action.explicit_field->accumulate_force();
    for (BaseState* s : action.states) {
        s->external_force_flat() = s->force_flat();
        s->force_flat().setZero();
    }
}

void Simulation::find_run(std::size_t begin) {
    // Solvers whose touched states do not meet commute: none reads what another writes (a
    // solver's subtree states, and the scratch force and dx of the outside states it reads).
    std::vector<const BaseState*> run_states, solver_states;  // sorted
    std::size_t end = begin;
    int large = 0;  // solvers with kMinUnknownsPerConcurrentSolve unknowns or more
    for (; end < plan_.size() && plan_[end].solver_node != nullptr; ++end) {
        solver_states.clear();
        const std::optional<std::size_t> unknowns =
            plan_[end].solver_node->ode_solver()->list_touched_states(*plan_[end].solver_node, solver_states);
        if (!unknowns || plan_[end].solver_node->ode_solver()->runs_in_plan_order()) break;
        std::sort(solver_states.begin(), solver_states.end());
        bool meet = false;
        for (auto a = run_states.begin(), b = solver_states.begin(); !meet && a != run_states.end() && b != solver_states.end();) {
            if (*a < *b) {
                ++a;
            } else if (*b < *a) {
                ++b;
            } else {
                meet = true;
            }
        }
        if (meet) break;
        if (*unknowns >= kMinUnknownsPerConcurrentSolve) ++large;
        const auto middle = run_states.insert(run_states.end(), solver_states.begin(), solver_states.end());
        std::inplace_merge(run_states.begin(), middle, run_states.end());
    }
    plan_[begin].run_end = std::max(end, begin + 1);
    plan_[begin].run_worth_tasks = large >= 2;
}

bool Simulation::run_concurrently(const std::vector<SolveAction>& plan, std::size_t begin) const {
    if (!plan[begin].run_worth_tasks) return false;
    for (std::size_t k = begin; k < plan[begin].run_end; ++k)
        if (plan[k].solver_node->ode_solver()->runs_in_plan_order()) return false;  // Newton turned on since
    return true;
}

std::vector<std::vector<const Node*>> Simulation::concurrent_solver_runs() {
    std::vector<std::vector<const Node*>> runs;
    const std::vector<SolveAction>& plan = solve_plan();
    for (std::size_t i = 0; i < plan.size(); i = plan[i].run_end) {
        if (!run_concurrently(plan, i)) continue;
        runs.emplace_back();
        for (std::size_t k = i; k < plan[i].run_end; ++k) runs.back().push_back(plan[k].solver_node);
    }
    return runs;
}

void Simulation::solve_concurrently(const std::vector<SolveAction>& plan, std::size_t begin, std::size_t end,
                                    double dt) {
    if (!arena_) arena_ = std::make_unique<ThreadArena>(threads_);
    FirstErrorInOrder failure;
    arena_->arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                try {
                    run_action(plan[i], dt);
                } catch (...) {
                    failure.record(i);
                }
            }
        });
    });
    // The error of the first failing solver in plan order, as a sequential run would raise it.
    failure.rethrow_if_any();
}

void Simulation::step() {
    if (!initialized_) init();
    const double dt = root_.dt();
    if (collision_hook) collision_hook(*this);
    const std::vector<SolveAction>& plan = solve_plan();
    const bool concurrent = threads_ != 1 &&
                            tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) > 1 &&
                            (arena_ ? arena_->arena.max_concurrency() : tbb::this_task_arena::max_concurrency()) > 1;
    for (std::size_t i = 0; i < plan.size(); i = plan[i].run_end) {
        if (concurrent && run_concurrently(plan, i)) {
            solve_concurrently(plan, i, plan[i].run_end, dt);
        } else {
            for (std::size_t k = i; k < plan[i].run_end; ++k) run_action(plan[k], dt);
        }
    }
    for_each_node(root_, [](Node& n) {
        for (const auto& c : n.constraints()) {  // SOFA's MechanicalProjectPositionAndVelocityVisitor
            c->project_position();
            c->project_velocity();
        }
        if (n.mapping()) {
            n.mapping()->apply_position();
            n.mapping()->apply_velocity();
        }
    });
    for (BaseState* s : applied_states_) s->external_force_flat().setZero();
    time_ += dt;
}

}  // namespace penalty
