// SubtreeSystem: its build (layout, scratch, fused block), the cache that keeps it, and the rows
// its products map and clear.
#include "penalty/simulation/subtree_system.hpp"

#include "flat_vector_ops.hpp"
#include "fused_contact_block.hpp"
#include "penalty/core/error.hpp"
#include "subtree_layout.hpp"
#include "subtree_scratch.hpp"

#include <algorithm>

namespace penalty {

SubtreeSystem::SubtreeSystem(Node& root, bool mapping_graph_order, bool fuse_contact_products)
    : layout_(std::make_unique<detail::SubtreeLayout>()),
      scratch_(std::make_unique<detail::SubtreeScratch>()),
      fused_(std::make_unique<detail::FusedContactBlock>()) {
    build(root, mapping_graph_order, fuse_contact_products);
}

void SubtreeSystem::build(Node& root, bool mapping_graph_order, bool fuse_contact_products) {
    PENALTY_DEMAND(!scratch_->readers_fixed);
    mapping_graph_order_ = mapping_graph_order;
    fuse_contact_products_ = fuse_contact_products;
    blocked_reductions_ = false;
    detail::build_subtree_layout(root, mapping_graph_order, *layout_);
    scratch_->reset(layout_->dx_readers.size(), layout_->independent.size());
    for (std::size_t i = 0; i < layout_->dx_readers.size(); ++i) {
        const detail::DxReaders& r = layout_->dx_readers[i];
        if (!r.selective) continue;
        // find_read_rows' scratch at its largest: no allocation in a product
        const std::size_t dofs = r.mapping->to()->num_dofs();
        scratch_->row_lists.read.reserve(std::max(scratch_->row_lists.read.capacity(), dofs));
        scratch_->dx_rows[i].rows.reserve(dofs);
    }
    fused_->find(*layout_, fuse_contact_products);
}

SubtreeSystem::~SubtreeSystem() = default;

void SubtreeSystem::set_blocked_reductions(bool on) {
    if (on && scratch_->reduction_blocks.segments.empty())
        scratch_->reduction_blocks = detail::reduction_blocks(*layout_);
    blocked_reductions_ = on;
}

Eigen::Index SubtreeSystem::size() const { return layout_->size; }
const std::vector<BaseState*>& SubtreeSystem::independent_states() const { return layout_->independent; }
const std::vector<BaseMapping*>& SubtreeSystem::mappings() const { return layout_->mappings; }
const std::vector<BaseForceField*>& SubtreeSystem::force_fields() const { return layout_->force_fields; }
const std::vector<std::pair<BaseMass*, Vec3>>& SubtreeSystem::masses() const { return layout_->masses; }
const std::vector<BaseProjectiveConstraint*>& SubtreeSystem::constraints() const { return layout_->constraints; }
const std::vector<BaseState*>& SubtreeSystem::mapped_states() const { return layout_->mapped; }

SubtreeSystem::FusedContactCounts SubtreeSystem::fused_contact_counts() const {
    const auto counts = fused_->counts();
    const auto on_threads = fused_->on_threads();
    return {.force_fields = counts[0],
            .read_mappings = counts[1],
            .unread_mappings = counts[2],
            .fields_on_threads = on_threads[0],
            .gathered_mappings = on_threads[1]};
}

std::size_t SubtreeSystem::concurrent_products() const { return scratch_->concurrent_products; }

std::size_t SubtreeSystem::concurrent_force_evaluations() const { return scratch_->concurrent_force_evaluations; }

std::size_t SubtreeSystem::concurrent_state_passes() const { return scratch_->concurrent_state_passes; }

std::size_t SubtreeSystem::product_chains() const {
    return (fused_->empty() ? layout_->chains : fused_->chains()).size();
}

bool SubtreeSystem::offsets_valid() const {
    Eigen::Index end = 0;
    for (std::size_t i = 0; i < layout_->independent.size(); ++i) {
        if (layout_->offsets[i] != end) return false;
        end += static_cast<Eigen::Index>(layout_->independent[i]->scalar_size());
    }
    return end == layout_->size;
}

SubtreeSystem& SubtreeSystemCache::get(Node& node, bool mapping_graph_order, bool fuse_contact_products) {
    const std::uint64_t version = node.structure_version();
    if (system_ && node_ == &node && version_ == version && system_->offsets_valid() &&
        system_->mapping_graph_order() == mapping_graph_order &&
        system_->fuses_contact_products() == fuse_contact_products)
        return *system_;
    // Built again in place: the layout, scratch and fused block keep their lists' capacity (a
    // pile of bodies builds its system again at nearly every step: new lists each time were a
    // quarter of the build, in allocations and first-touch page faults).
    try {
        if (system_) system_->build(node, mapping_graph_order, fuse_contact_products);
        else system_.emplace(node, mapping_graph_order, fuse_contact_products);
    } catch (...) {
        system_.reset();  // a half-built layout is never used
        node_ = nullptr;
        throw;
    }
    node_ = &node;
    version_ = version;
    ++builds_;
    return *system_;
}

void SubtreeSystem::append_states(std::vector<const BaseState*>& out) const {
    out.insert(out.end(), layout_->independent.begin(), layout_->independent.end());
    out.insert(out.end(), layout_->mapped.begin(), layout_->mapped.end());
    out.insert(out.end(), layout_->external.begin(), layout_->external.end());
    for (const BaseForceField* ff : layout_->force_fields) ff->list_read_states(out);
}

Index SubtreeSystem::offset(const BaseState* s) const { return layout_->offset_of(s); }

bool SubtreeSystem::list_rows_read(const BaseState& state, const std::vector<const BaseForceField*>& force_fields,
                                   const std::vector<const BaseMapping*>& mappings,
                                   std::vector<std::uint32_t>& listed) const {
    listed.clear();
    for (const BaseForceField* ff : force_fields)
        if (!ff->list_dx_read(state, listed)) return false;
    for (const BaseMapping* m : mappings)  // (rows of from() only: a second input's are unknown)
        if (m->from() != &state || !m->list_inputs_read(listed)) return false;
    const std::size_t dofs = state.num_dofs();
    for (const std::uint32_t row : listed) PENALTY_DEMAND(row < dofs);
    return true;
}

void SubtreeSystem::clear_external_scratch(bool forces) const {
    for (std::size_t i = 0; i < layout_->external.size(); ++i) {
        BaseState& s = *layout_->external[i];
        const bool listed = s.is_static() && s.num_dofs() >= kMinDofsForScratchRows &&
                            list_rows_read(s, layout_->external_readers[i].force_fields,
                                           layout_->external_readers[i].mappings, scratch_->row_lists.listed);
        BaseState::ScratchRows& record = forces ? s.static_force_rows : s.static_work_rows;
        const auto width = static_cast<Eigen::Index>(s.deriv_size());
        const auto clear = [&](FlatVector v) {
            if (listed && record.holds_for(s.num_dofs()) && v.size() == static_cast<Eigen::Index>(s.scalar_size())) {
                // every other row is 0 (only solves write a static state's scratch), and so are
                // then the rows listed now, which the solve may write
                detail::zero_rows(v, width, record.rows);
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
        if (listed) record.rows.swap(scratch_->row_lists.listed);
    }
}

void SubtreeSystem::find_read_rows(std::size_t index, detail::RowLists& lists) const {
    const detail::DxReaders& r = layout_->dx_readers[index];
    detail::DxRows& out = scratch_->dx_rows[index];
    out.restricted = false;
    out.found = scratch_->readers_fixed;
    if (!r.selective) return;
    const BaseState& state = *r.mapping->to();
    const std::size_t dofs = state.num_dofs();
    if (!list_rows_read(state, r.force_fields, r.mappings, lists.listed)) return;
    lists.read.assign(dofs, 0);
    for (const std::uint32_t row : lists.listed) lists.read[row] = 1;
    out.rows.clear();
    for (std::size_t i = 0; i < dofs; ++i)
        if (lists.read[i] != 0) out.rows.push_back(static_cast<std::uint32_t>(i));
    out.restricted = out.rows.size() != dofs;
}

void SubtreeSystem::map_dx(std::size_t index, detail::RowLists& lists) const {
    const detail::DxRows& rows = scratch_->dx_rows[index];
    if (!(scratch_->readers_fixed && rows.found)) find_read_rows(index, lists);
    BaseMapping& mapping = *layout_->dx_readers[index].mapping;
    if (rows.restricted) mapping.apply_dx_rows(rows.rows);
    else mapping.apply_dx();
}

SubtreeSystem::FixedReaders::FixedReaders(const SubtreeSystem& system) : system_(system) {
    PENALTY_DEMAND(!system_.scratch_->readers_fixed);
    for (detail::DxRows& r : system_.scratch_->dx_rows) r.found = false;
    system_.scratch_->readers_fixed = true;
    system_.fused_->invalidate();
}

SubtreeSystem::FixedReaders::~FixedReaders() {
    system_.scratch_->readers_fixed = false;
    for (detail::DxRows& r : system_.scratch_->dx_rows) r.found = false;
}

}  // namespace penalty
