// FusedContactBlock: the contact fields and barycentric contact mappings a subtree's products
// apply on flat arrays (fused_contact_block.hpp).
#include "fused_contact_block.hpp"

#include "penalty/core/error.hpp"
#include "penalty/core/pointer_index.hpp"
#include "penalty/simulation/penalty_interaction.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace penalty::detail {

namespace {
/// A barycentric contact mapping between Vec3 states whose output one force field reads.
struct Candidate {
    std::size_t mapping_index;
    Vec3Object* from;
    Vec3Object* to;
};
/// find()'s tables, kept by the thread from one build to the next (a pile's system is built
/// again whenever contacts come or go).
struct FindTables {
    std::vector<Candidate> candidates;
    PointerIndex<BaseState> candidate_on;      // output state → its entry of candidates
    PointerIndex<Vec3Object> unread_group_of;  // parent → unread_by_parent_
    PointerIndex<BaseState> external;
    PointerIndex<BaseForceField> fused_field_of;   // field → fields_
    std::vector<std::ptrdiff_t> fused_mapping_of;  // per layout mapping: index in mappings_ or -1
    void clear(std::size_t mappings) {
        candidates.clear();
        candidate_on.clear();
        unread_group_of.clear();
        external.clear();
        fused_field_of.clear();
        fused_mapping_of.assign(mappings, -1);
    }
};
constexpr std::size_t kNone = PointerIndex<BaseState>::npos;
}  // namespace

void FusedContactBlock::clear() {
    mappings_.clear();
    fields_.clear();
    steps_.clear();
    unfused_mappings_.clear();
    unread_by_parent_.clear();
    zero_adds_.clear();
    rows_.clear();
    dx_.clear();
    df_.clear();
    springs_.clear();
    read_rows_.clear();
    point_read_.clear();
    unread_point_adds_.clear();
    gather_row_.clear();
    gather_first_.clear();
    gather_terms_.clear();
    gather_cursor_.clear();  // (every cursor 0 again)
    external_slots_ = 0;
    chains_.step_first.clear();
    chains_.steps_of.clear();
    chains_.mapping_first.clear();
    chains_.mappings_of.clear();
    ready_ = false;
    springs_ready_ = false;
}

void FusedContactBlock::find(SubtreeLayout& l, bool fuse) {
    clear();
    thread_local FindTables tables;
    FindTables& t = tables;
    t.clear(l.mappings.size());
    if (!fuse) {
        unfused_mappings_ = l.all_mappings;
        return;
    }
    PointerIndex<BaseState> external_slot;
    // Candidates: barycentric contact mappings between Vec3 states whose output is read by one
    // force field and no mapping; those read by nobody are fused at once (unread).
    for (std::size_t i = 0; i < l.mappings.size(); ++i) {
        const DxReaders& r = l.dx_readers[i];
        if (l.mappings[i]->contact_barycentric_rows() == nullptr || !r.mappings.empty() || r.force_fields.size() > 1)
            continue;
        auto* from = dynamic_cast<Vec3Object*>(l.mappings[i]->from());
        auto* to = dynamic_cast<Vec3Object*>(l.mappings[i]->to());
        if (from == nullptr || to == nullptr) continue;
        if (r.force_fields.size() == 1) {
            if (t.candidate_on.emplace(to, t.candidates.size()).second) t.candidates.push_back(Candidate{i, from, to});
            continue;
        }
        const auto [group, added] = t.unread_group_of.emplace(from, unread_by_parent_.size());
        if (added) unread_by_parent_.emplace_back(from, std::vector<std::size_t>{});
        unread_by_parent_[group].second.push_back(mappings_.size());
        t.fused_mapping_of[i] = static_cast<std::ptrdiff_t>(mappings_.size());
        mappings_.push_back({.mapping_index = i,
                             .from = from,
                             .to = to,
                             .rows = l.mappings[i]->contact_barycentric_rows(),
                             .live = false});
    }
    // Fields: two-state Vec3 interaction fields each of whose sides is a candidate read by this
    // field alone or an external state (dx 0, df scratch), one side at least a candidate.
    for (const BaseState* s : l.external) t.external.emplace(s, 0);
    for (BaseForceField* ff : l.force_fields) {
        auto* field = dynamic_cast<Vec3InteractionForceField*>(ff);
        if (field == nullptr || &field->state1() == &field->state2()) continue;
        std::array<const Candidate*, 2> mapping_of_side{nullptr, nullptr};
        bool fusable = true;
        for (std::size_t side = 0; side < 2; ++side) {
            const Vec3Object* state = side == 0 ? &field->state1() : &field->state2();
            if (const std::size_t at = t.candidate_on.find(state);
                at != kNone && l.dx_readers[t.candidates[at].mapping_index].force_fields.front() == ff)
                mapping_of_side[side] = &t.candidates[at];
            else if (!t.external.contains(state))
                fusable = false;  // a state others read or write: the field keeps its place
        }
        if (!fusable || (mapping_of_side[0] == nullptr && mapping_of_side[1] == nullptr)) continue;
        FusedField entry;
        entry.field = field;
        if (const auto* contact = dynamic_cast<const PenaltyInteraction*>(field)) entry.penalty = &contact->field();
        for (std::size_t side = 0; side < 2; ++side) {
            const Candidate* c = mapping_of_side[side];
            if (c == nullptr) {
                entry.sides[side].state = side == 0 ? &field->state1() : &field->state2();
                entry.sides[side].external_slot =
                    external_slot.emplace(entry.sides[side].state, external_slot.size()).first;
                continue;
            }
            t.fused_mapping_of[c->mapping_index] = static_cast<std::ptrdiff_t>(mappings_.size());
            entry.sides[side].mapping = static_cast<std::ptrdiff_t>(mappings_.size());
            mappings_.push_back({.mapping_index = c->mapping_index,
                                 .from = c->from,
                                 .to = c->to,
                                 .rows = l.mappings[c->mapping_index]->contact_barycentric_rows()});
        }
        t.fused_field_of.emplace(ff, fields_.size());
        fields_.push_back(entry);
    }
    external_slots_ = external_slot.size();
    mark_steps(l, t.fused_mapping_of, t.fused_field_of);
    if (!mappings_.empty()) find_step_chains(l, steps_, unfused_mappings_, chains_);
}

void FusedContactBlock::mark_steps(SubtreeLayout& l, const std::vector<std::ptrdiff_t>& fused_mapping_of,
                                   const PointerIndex<BaseForceField>& fused_field_of) {
    for (std::size_t i = 0; i < l.mappings.size(); ++i)
        if (fused_mapping_of[i] < 0) unfused_mappings_.push_back(i);
    if (mappings_.empty()) return;
    for (ForceStep& s : l.steps) {
        if (s.mapping != nullptr) {
            s.fused = fused_mapping_of[s.mapping_index];
        } else if (s.force_field != nullptr) {
            if (const std::size_t at = fused_field_of.find(s.force_field); at != kNone)
                s.fused = static_cast<std::ptrdiff_t>(at);
        }
        const bool dropped = s.fused >= 0 && (s.force_field != nullptr || !mappings_[std::size_t(s.fused)].live);
        if (!dropped) steps_.push_back(s);
    }
    std::size_t springs = 0, points = 0, parent_dofs = 0;
    for (const FusedField& f : fields_)
        if (f.penalty != nullptr) springs += f.penalty->size();
    springs_.reserve(springs);
    for (const FusedMapping& m : mappings_) {
        if (m.live) points += m.to->num_dofs();
        parent_dofs = std::max(parent_dofs, m.from->num_dofs());
    }
    rows_.reserve(points);  // today's sizes: no allocation in this step's products
    dx_.reserve(points);
    df_.reserve(points);
    read_rows_.reserve(points);
    point_read_.reserve(points);
    unread_point_adds_.reserve(4 * points);
    zero_add_kind_.reserve(parent_dofs);
    zero_adds_.reserve(parent_dofs * unread_by_parent_.size());
}

std::array<std::size_t, 3> FusedContactBlock::counts() const {
    std::array<std::size_t, 3> counts{fields_.size(), 0, 0};
    for (const FusedMapping& m : mappings_) ++counts[m.live ? 1 : 2];
    return counts;
}

void FusedContactBlock::prepare() {
    std::size_t total = 0;
    for (FusedMapping& m : mappings_) {
        PENALTY_DEMAND(m.rows->size() == m.to->num_dofs());
        if (!m.live) continue;
        m.first = total;
        m.count = m.rows->size();
        total += m.count;
    }
    rows_.resize(total);
    dx_.resize(total);
    df_.resize(total);
    for (const FusedMapping& m : mappings_)
        if (m.live) std::copy(m.rows->begin(), m.rows->end(), rows_.begin() + static_cast<std::ptrdiff_t>(m.first));
    // The unread mappings' Jᵀ: w·(+0) into each row entry; +0 when w is finite and not
    // negative-signed, −0 (adds nothing) when negative-signed, NaN when not finite.
    zero_adds_.clear();
    for (const auto& [parent, unread] : unread_by_parent_) {
        zero_add_kind_.assign(parent->num_dofs(), 0);
        for (const std::size_t index : unread)
            for (const ContactBarycentricRow& row : *mappings_[index].rows)
                for (const ContactBarycentricRow::Entry& e : row) {
                    std::uint8_t& kind = zero_add_kind_[static_cast<std::size_t>(e.index)];
                    if (!std::isfinite(e.weight)) kind = 2;
                    else if (!std::signbit(e.weight)) kind = std::max<std::uint8_t>(kind, 1);
                }
        for (std::size_t dof = 0; dof < zero_add_kind_.size(); ++dof)
            if (zero_add_kind_[dof] != 0)
                zero_adds_.push_back(
                    {&parent->df[dof], zero_add_kind_[dof] == 2 ? std::numeric_limits<double>::quiet_NaN() : 0.0});
    }
    ready_ = true;
}

void FusedContactBlock::make_springs() {
    springs_.clear();
    for (FusedField& f : fields_) {
        f.flat_springs = false;
        if (f.penalty == nullptr) continue;
        const PenaltyParameters& p = f.penalty->parameters();
        if (p.damping != 0.0 || p.friction != FrictionModel::ignored) continue;  // the field's own product
        std::array<std::size_t, 2> size{};
        for (std::size_t side = 0; side < 2; ++side) {
            const FusedSide& s = f.sides[side];
            size[side] = s.mapping < 0 ? s.state->dx.size() : mappings_[static_cast<std::size_t>(s.mapping)].count;
        }
        const std::span<const PenaltyContact> contacts = f.penalty->contacts();
        // a contact outside its states: the field's add_dforce, which says so
        const bool inside = std::all_of(contacts.begin(), contacts.end(), [&](const PenaltyContact& c) {
            return c.m1 >= 0 && std::size_t(c.m1) < size[0] && c.m2 >= 0 && std::size_t(c.m2) < size[1];
        });
        if (!inside) continue;
        f.first_spring = springs_.size();
        for (const PenaltyContact& c : contacts)
            if (c.pen > 0.0)  // the active set of the last add_force, as add_dforce
                springs_.push_back(
                    {static_cast<std::uint32_t>(c.m1), static_cast<std::uint32_t>(c.m2), c.normal, c.ks});
        f.end_spring = springs_.size();
        f.flat_springs = true;
    }
    // the points a product reads: those of the active springs, and every point of a field that
    // keeps its own product; a field's springs go on threads when no two read one point of a
    // mapped side (each mapping is its field's alone: a point seen twice is one field's twice)
    const bool threads = tbb::this_task_arena::max_concurrency() > 1;
    point_read_.assign(rows_.size(), 0);
    for (FusedField& f : fields_) {
        f.on_threads = threads && f.flat_springs && f.end_spring - f.first_spring >= kMinItemsOnThreads;
        for (std::size_t side = 0; side < 2; ++side) {
            if (f.sides[side].mapping < 0) continue;
            const FusedMapping& m = mappings_[static_cast<std::size_t>(f.sides[side].mapping)];
            if (!f.flat_springs) {
                std::fill_n(point_read_.begin() + static_cast<std::ptrdiff_t>(m.first), m.count, std::uint8_t{1});
                continue;
            }
            for (std::size_t i = f.first_spring; i < f.end_spring; ++i) {
                std::uint8_t& read = point_read_[m.first + (side == 0 ? springs_[i].m1 : springs_[i].m2)];
                if (read != 0) f.on_threads = false;
                read = 1;
            }
        }
    }
    list_read_points();
    gather_row_.clear();
    gather_first_.assign(1, 0);
    gather_terms_.clear();
    for (FusedMapping& m : mappings_) {
        m.gathered = false;
        if (threads && m.live && m.read_count >= kMinItemsOnThreads) make_gathers(m);
    }
    springs_ready_ = true;
}

void FusedContactBlock::make_gathers(FusedMapping& m) {
    // the mapping's Jᵀ adds rows[point][e].weight·df[point] into from.df[rows[point][e].index],
    // point by point in read order, entry by entry: each parent row's terms in that order
    const ContactBarycentricRow* rows = rows_.data() + m.first;
    const std::uint32_t* read = read_rows_.data() + m.first_read;
    if (gather_cursor_.size() < m.from->num_dofs()) gather_cursor_.resize(m.from->num_dofs(), 0);
    m.first_gather = gather_row_.size();
    for (std::size_t i = 0; i < m.read_count; ++i)
        for (const ContactBarycentricRow::Entry& e : rows[read[i]]) {
            PENALTY_DEMAND(e.index >= 0 && static_cast<std::size_t>(e.index) < m.from->num_dofs());
            std::uint32_t& count = gather_cursor_[static_cast<std::size_t>(e.index)];
            if (count++ == 0) gather_row_.push_back(static_cast<std::uint32_t>(e.index));
        }
    m.gather_count = gather_row_.size() - m.first_gather;
    // each parent row's first term, then its cursor
    const std::size_t first_term = gather_terms_.size();
    std::size_t end = first_term;
    gather_first_.pop_back();  // (the end sentinel, pushed again below)
    for (std::size_t j = m.first_gather; j < gather_row_.size(); ++j) {
        std::uint32_t& cursor = gather_cursor_[gather_row_[j]];
        gather_first_.push_back(static_cast<std::uint32_t>(end));
        end += cursor;
        cursor = gather_first_.back();
    }
    gather_first_.push_back(static_cast<std::uint32_t>(end));
    gather_terms_.resize(end);
    for (std::size_t i = 0; i < m.read_count; ++i)
        for (const ContactBarycentricRow::Entry& e : rows[read[i]])
            gather_terms_[gather_cursor_[static_cast<std::size_t>(e.index)]++] = {e.weight, read[i]};
    for (std::size_t j = m.first_gather; j < gather_row_.size(); ++j) gather_cursor_[gather_row_[j]] = 0;
    m.gathered = true;
}

void FusedContactBlock::list_read_points() {
    read_rows_.clear();
    unread_point_adds_.clear();
    for (FusedMapping& m : mappings_) {
        if (!m.live) continue;
        m.first_read = read_rows_.size();
        for (std::size_t row = 0; row < m.count; ++row) {
            if (point_read_[m.first + row] != 0) {
                read_rows_.push_back(static_cast<std::uint32_t>(row));
                continue;
            }
            // w·(+0) into each entry's parent row: +0 for a finite weight not negative-signed, NaN
            // for a weight not finite, nothing (−0) otherwise
            for (const ContactBarycentricRow::Entry& e : rows_[m.first + row]) {
                if (std::isfinite(e.weight) && std::signbit(e.weight)) continue;
                unread_point_adds_.push_back(
                    {&m.from->df[static_cast<std::size_t>(e.index)],
                     std::isfinite(e.weight) ? 0.0 : std::numeric_limits<double>::quiet_NaN()});
            }
        }
        m.read_count = read_rows_.size() - m.first_read;
    }
    // one addition per parent row (a second +0 or NaN changes nothing): NaN first among a row's
    std::sort(unread_point_adds_.begin(), unread_point_adds_.end(), [](const ZeroAdd& a, const ZeroAdd& b) {
        return a.target != b.target ? a.target < b.target : std::isnan(a.value) && !std::isnan(b.value);
    });
    unread_point_adds_.erase(std::unique(unread_point_adds_.begin(), unread_point_adds_.end(),
                                         [](const ZeroAdd& a, const ZeroAdd& b) { return a.target == b.target; }),
                             unread_point_adds_.end());
}

void FusedContactBlock::begin_product(double k, double b, bool parallel) {
    if (!ready_) prepare();
    if (!springs_ready_) make_springs();
    // the fused fields read only their contact points' dx and write only their df (and external
    // scratch), which no other step reads or writes: run before the steps, same bits; the
    // unread mappings' Jᵀ is the additions of zeros, which give the same bits in any place
    add_zeros(zero_adds_);
    add_zeros(unread_point_adds_);
    if (!parallel) {
        apply_fields(0, fields_.size(), k, b, nullptr);
        return;
    }
    // each task's thread its own external df scratch (kept from product to product)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, fields_.size(), kFieldsPerTask),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          apply_fields(r.begin(), r.end(), k, b, &external_scratch_.local());
                      });
}

void FusedContactBlock::add_zeros(const std::vector<ZeroAdd>& adds) {
    const ZeroAdd* const list = adds.data();
    const auto add = [list](std::size_t begin, std::size_t end) {
        for (const ZeroAdd* z = list + begin; z != list + end; ++z) {
            double* t = z->target->data();
            const double value = z->value;
            t[0] += value;
            t[1] += value;
            t[2] += value;
        }
    };
    if (adds.size() < kMinItemsOnThreads || tbb::this_task_arena::max_concurrency() < 2) {
        add(0, adds.size());
        return;
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, adds.size(), kItemsPerTask),
                      [&add](const tbb::blocked_range<std::size_t>& r) { add(r.begin(), r.end()); });
}

std::array<std::size_t, 2> FusedContactBlock::on_threads() const {
    std::array<std::size_t, 2> counts{};
    for (const FusedField& f : fields_) counts[0] += f.on_threads ? 1 : 0;
    for (const FusedMapping& m : mappings_) counts[1] += m.gathered ? 1 : 0;
    return counts;
}

void FusedContactBlock::map_read_points(const FusedMapping& m, std::size_t begin, std::size_t end) {
    // ContactPointMapping::apply_dx (the mapper's apply_j) and the zeroing of the mapped df, at
    // the points a product reads
    const std::span<const Vec3> in(m.from->dx);
    const ContactBarycentricRow* rows = rows_.data() + m.first;
    Vec3* out_dx = dx_.data() + m.first;
    Vec3* out_df = df_.data() + m.first;
    const std::uint32_t* read = read_rows_.data() + m.first_read;
    for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t row = read[i];
        out_dx[row] = rows[row].combine(in);
        out_df[row].setZero();
    }
}

void FusedContactBlock::apply_field_on_threads(const FusedField& f, double k) {
    // J and the zeroed df at the read points of each mapped side (each point its own row)
    for (const FusedSide& s : f.sides) {
        if (s.mapping < 0) continue;
        const FusedMapping& m = mappings_[static_cast<std::size_t>(s.mapping)];
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m.read_count, kItemsPerTask),
                          [&](const tbb::blocked_range<std::size_t>& r) { map_read_points(m, r.begin(), r.end()); });
    }
    // the springs in ranges: a mapped side's point is one spring's (make_springs), an external
    // side's df is the task thread's scratch, which nobody reads
    tbb::parallel_for(tbb::blocked_range<std::size_t>(f.first_spring, f.end_spring, kItemsPerTask),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          std::vector<std::vector<Vec3>>& scratch = external_scratch_.local();
                          if (scratch.size() < external_slots_) scratch.resize(external_slots_);
                          std::array<Vec3*, 2> df{};
                          std::array<const Vec3*, 2> dx{};
                          for (std::size_t side = 0; side < 2; ++side) {
                              const FusedSide& s = f.sides[side];
                              if (s.mapping >= 0) {
                                  const FusedMapping& m = mappings_[static_cast<std::size_t>(s.mapping)];
                                  dx[side] = dx_.data() + m.first;
                                  df[side] = df_.data() + m.first;
                                  continue;
                              }
                              std::vector<Vec3>& external = scratch[s.external_slot];
                              if (external.size() < s.state->df.size())
                                  external.resize(s.state->df.size(), Vec3::Zero());
                              dx[side] = s.state->dx.data();
                              df[side] = external.data();
                          }
                          for (std::size_t i = r.begin(); i < r.end(); ++i) {
                              const FusedSpring& sp = springs_[i];
                              add_sofa_contact_dforce(sp.normal, sp.ks, dx[0][sp.m1], dx[1][sp.m2], k, df[0][sp.m1],
                                                      df[1][sp.m2]);
                          }
                      });
}

void FusedContactBlock::apply_fields(std::size_t begin, std::size_t end, double k, double b,
                                     std::vector<std::vector<Vec3>>* external_df) {
    if (external_df != nullptr && external_df->size() < external_slots_) external_df->resize(external_slots_);
    for (std::size_t i = begin; i < end; ++i) {
        const FusedField& f = fields_[i];
        if (f.on_threads) {
            apply_field_on_threads(f, k);
            continue;
        }
        std::array<Vec3Span, 2> df;
        std::array<ConstVec3Span, 2> dx;
        for (std::size_t side = 0; side < 2; ++side) {
            const FusedSide& s = f.sides[side];
            if (s.mapping < 0) {  // external: dx 0, df scratch
                dx[side] = s.state->dx;
                if (external_df == nullptr) {
                    df[side] = s.state->df;
                } else {
                    std::vector<Vec3>& scratch = (*external_df)[s.external_slot];
                    if (scratch.size() < s.state->df.size()) scratch.resize(s.state->df.size(), Vec3::Zero());
                    df[side] = Vec3Span(scratch.data(), s.state->df.size());
                }
                continue;
            }
            const FusedMapping& m = mappings_[static_cast<std::size_t>(s.mapping)];
            map_read_points(m, 0, m.read_count);
            dx[side] = ConstVec3Span(dx_.data() + m.first, m.count);
            df[side] = Vec3Span(df_.data() + m.first, m.count);
        }
        if (!f.flat_springs) {
            f.field->add_dforce(df[0], df[1], dx[0], dx[1], k, b);
            continue;
        }
        // PenaltyForceField::add_dforce's SOFA path over the field's active springs, in order
        for (std::size_t i_spring = f.first_spring; i_spring < f.end_spring; ++i_spring) {
            const FusedSpring& sp = springs_[i_spring];
            add_sofa_contact_dforce(sp.normal, sp.ks, dx[0][sp.m1], dx[1][sp.m2], k, df[0][sp.m1], df[1][sp.m2]);
        }
    }
}

void FusedContactBlock::spread(std::size_t index) const {
    // ContactPointMapping::apply_jt_df (the mapper's apply_jt): from.df += Jᵀ·df, rows in order
    const FusedMapping& m = mappings_[index];
    const std::span<Vec3> out(m.from->df);
    const ContactBarycentricRow* rows = rows_.data() + m.first;
    const Vec3* df = df_.data() + m.first;
    if (m.gathered) {  // each parent row's terms in the rows' order (make_gathers), rows on threads
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(m.first_gather, m.first_gather + m.gather_count, kItemsPerTask),
            [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t j = r.begin(); j < r.end(); ++j) {
                    Vec3& target = out[gather_row_[j]];
                    for (std::uint32_t t = gather_first_[j]; t < gather_first_[j + 1]; ++t)
                        target += gather_terms_[t].weight * df[gather_terms_[t].point];
                }
            });
        return;
    }
    const std::uint32_t* read = read_rows_.data() + m.first_read;
    for (std::size_t i = 0; i < m.read_count; ++i) rows[read[i]].spread(out, df[read[i]]);
}

}  // namespace penalty::detail
