// build_subtree_layout: the states, components and force steps of a solver's subtree.
#include "subtree_layout.hpp"

#include "step_chains.hpp"

#include "penalty/core/error.hpp"
#include "penalty/core/pointer_index.hpp"

#include <algorithm>

namespace penalty::detail {

namespace {
/// The builder's tables and per-state lists, kept by each thread from one build to the next:
/// a pile of bodies has thousands of contact states, and its system is built again whenever
/// contacts come or go. Refilled at each build, never freed.
struct LayoutBuildLists {
    PointerIndex<BaseState> known;
    PointerIndex<BaseState> fields_on_index;  // state → its list in fields_on
    std::vector<std::vector<const BaseForceField*>> fields_on;
    std::size_t fields_on_used = 0;
    PointerIndex<BaseState> mappings_from_index;  // state → its list in mappings_from
    std::vector<std::vector<const BaseMapping*>> mappings_from;
    std::size_t mappings_from_used = 0;
    PointerIndex<BaseMapping> mapping_index;

    void clear() {
        known.clear();
        fields_on_index.clear();
        fields_on_used = 0;
        mappings_from_index.clear();
        mappings_from_used = 0;
        mapping_index.clear();
    }
    /// The list of `s` in (index, lists, used), a new empty one if it has none.
    template <class T>
    static std::vector<T>& list_of(const BaseState* s, PointerIndex<BaseState>& index,
                                   std::vector<std::vector<T>>& lists, std::size_t& used) {
        const auto [at, added] = index.emplace(s, used);
        if (added) {
            if (lists.size() == used) lists.emplace_back();
            lists[used++].clear();
        }
        return lists[at];
    }
    [[nodiscard]] const std::vector<const BaseForceField*>* fields_acting_on(const BaseState* s) const {
        const std::size_t at = fields_on_index.find(s);
        return at == PointerIndex<BaseState>::npos ? nullptr : &fields_on[at];
    }
    [[nodiscard]] const std::vector<const BaseMapping*>* mappings_reading(const BaseState* s) const {
        const std::size_t at = mappings_from_index.find(s);
        return at == PointerIndex<BaseState>::npos ? nullptr : &mappings_from[at];
    }
};

/// The subtree's states, masses, force fields, constraints and mappings, and the force steps in
/// SOFA's visiting order (MechanicalComputeForceVisitor, MechanicalAddMBKdxVisitor), or, for
/// SOFA HEAD's MappingGraph (`mapping_graph_order`), each node's mass and force fields as written.
void collect(Node& node, bool mapping_graph_order, SubtreeLayout& l) {
    if (BaseState* s = node.state()) {
        if (node.mapping()) {
            if (node.mapping()->to() != s)
                throw_invalid_argument("Node '", node.name(), "': the mapping output is not the node's state");
            l.mapped.push_back(s);
            l.mappings.push_back(node.mapping());
        } else {
            l.independent_index.emplace(s, l.independent.size());
            l.offsets.push_back(l.size);
            l.independent.push_back(s);
            l.sizes.push_back(static_cast<Index>(s->scalar_size()));
            l.widths.push_back(static_cast<Index>(s->deriv_size()));
            l.size += l.sizes.back();
        }
    } else if (node.mapping()) {
        throw_invalid_argument("Node '", node.name(), "': a mapping needs the node's state as output");
    }
    // the mass at its place among the force fields (SOFA's forceField list); a mass on a mapped
    // state acts through the mapping, as SOFA's: its gravity force and M·dx go up by Jᵀ (the
    // node's mapping step below), i.e. Jᵀ·M·J in the system
    node.for_each_mass_and_force_field(
        /*interaction_last=*/!mapping_graph_order,
        [&](BaseMass& m) {
            l.masses.emplace_back(&m, node.gravity());
            l.steps.push_back({.mass = &m, .gravity = node.gravity()});
        },
        [&l](BaseForceField& ff) {
            l.force_fields.push_back(&ff);
            l.steps.push_back({.force_field = &ff});
        });
    for (const auto& c : node.constraints()) l.constraints.push_back(c.get());
    for (const auto& child : node.children()) collect(*child, mapping_graph_order, l);
    // SOFA's bottom-up pass (MechanicalVisitor::processNodeBottomUp, post-order): a node's
    // mapping adds Jᵀ·f into its parent once the node's own children have added theirs, and
    // siblings in child order, so a parent sums its children's forces first child first
    if (node.state() && node.mapping()) l.steps.push_back({.mapping = node.mapping()});
}

/// External states (used by a force field or a mapping but not part of the subtree) and the
/// readers of every external and mapped state.
void find_readers(SubtreeLayout& l, LayoutBuildLists& t) {
    for (const BaseState* s : l.mapped) t.known.emplace(s, 0);
    for (const BaseState* s : l.independent) t.known.emplace(s, 0);
    for (const auto* ff : l.force_fields)
        for (BaseState* s : ff->states()) {
            auto& on = LayoutBuildLists::list_of(s, t.fields_on_index, t.fields_on, t.fields_on_used);
            if (on.empty() || on.back() != ff) on.push_back(ff);  // a field listing a state twice counts once
            if (t.known.emplace(s, 0).second) l.external.push_back(s);
        }
    for (const auto* m : l.mappings) {
        for (BaseState* from : {m->from(), m->second_from()}) {  // (a second input: Multi2Mapping)
            if (from == nullptr) continue;
            LayoutBuildLists::list_of(from, t.mappings_from_index, t.mappings_from, t.mappings_from_used).push_back(m);
            if (t.known.emplace(from, 0).second) l.external.push_back(from);
        }
    }
    // the reader entries of an earlier build refilled (their lists keep their capacity)
    const auto refill = [](auto& list, const auto* from) {
        if (from != nullptr) list.assign(from->begin(), from->end());
        else list.clear();
    };
    l.external_readers.resize(l.external.size());
    for (std::size_t i = 0; i < l.external.size(); ++i) {
        ExternalReaders& r = l.external_readers[i];
        refill(r.force_fields, t.fields_acting_on(l.external[i]));
        refill(r.mappings, t.mappings_reading(l.external[i]));
    }
    l.dx_readers.resize(l.mappings.size());
    for (std::size_t i = 0; i < l.mappings.size(); ++i) {
        BaseMapping* m = l.mappings[i];
        PENALTY_DEMAND(m->to() == l.mapped[i]);
        DxReaders& r = l.dx_readers[i];
        r.mapping = m;
        // (a mass on the mapped state reads every row's dx)
        r.selective = m->maps_selected_rows() && std::none_of(l.masses.begin(), l.masses.end(), [&](const auto& e) {
                          return e.first->state() == m->to();
                      });
        // the force fields acting on the mapped state and the mappings reading it, in the
        // subtree's order
        refill(r.force_fields, t.fields_acting_on(m->to()));
        refill(r.mappings, t.mappings_reading(m->to()));
    }
}
}  // namespace

void SubtreeLayout::clear() {
    independent.clear();
    offsets.clear();
    sizes.clear();
    widths.clear();
    independent_index.clear();
    size = 0;
    mapped.clear();
    mappings.clear();
    all_mappings.clear();
    external.clear();
    masses.clear();
    force_fields.clear();
    constraints.clear();
    steps.clear();
}

void build_subtree_layout(Node& root, bool mapping_graph_order, SubtreeLayout& l) {
    l.clear();
    collect(root, mapping_graph_order, l);
    if (mapping_graph_order) order_as_mapping_graph(root, l.mappings, l.steps);
    thread_local LayoutBuildLists lists;
    LayoutBuildLists& t = lists;
    t.clear();
    find_readers(l, t);
    l.all_mappings.resize(l.mappings.size());
    for (std::size_t i = 0; i < l.mappings.size(); ++i) {
        l.all_mappings[i] = i;
        t.mapping_index.emplace(l.mappings[i], i);
    }
    for (ForceStep& s : l.steps)
        if (s.mapping != nullptr) {
            s.mapping_index = t.mapping_index.find(s.mapping);
            PENALTY_DEMAND(s.mapping_index != PointerIndex<BaseMapping>::npos);
        }
    find_step_chains(l, l.steps, l.all_mappings, l.chains);
}

}  // namespace penalty::detail
