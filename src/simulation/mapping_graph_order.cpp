// order_as_mapping_graph: the force steps of a subtree in the order of SOFA HEAD's MappingGraph.
#include "subtree_layout.hpp"

#include "penalty/core/pointer_index.hpp"

#include <algorithm>
#include <array>

namespace penalty::detail {

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
    std::vector<std::size_t> group_slots;           // size a power of two: a group's index + 1, 0 empty
    std::vector<std::size_t> step_group;            // per non-mapping force step, in force_steps_ order
    std::vector<std::array<std::size_t, 2>> edges;  // (from, to), in the order they were added
    std::vector<std::size_t> parents;               // per node: parents not yet reached
    std::vector<std::size_t> first_child;           // per node + 1: its children in `children`
    std::vector<std::size_t> children;
    std::vector<std::size_t> ready;                       // the breadth-first queue
    std::vector<BaseMapping*> reached;                    // the mappings in breadth-first order
    std::vector<std::array<std::size_t, 2>> group_steps;  // (group, step) per non-mapping step
    std::vector<std::size_t> first_member;                // per group + 1: its steps in `members`
    std::vector<std::size_t> members;
    std::vector<ForceStep> ordered;  // the steps in the graph's order, swapped with the visitors'

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
void bucket_by_key(const Pairs& pairs, std::size_t keys, std::vector<std::size_t>& first,
                   std::vector<std::size_t>& values) {
    first.assign(keys + 1, 0);
    for (const auto& p : pairs) ++first[p[0] + 1];
    for (std::size_t k = 0; k < keys; ++k) first[k + 1] += first[k];
    values.resize(pairs.size());
    for (const auto& p : pairs) values[first[p[0]]++] = p[1];
    for (std::size_t k = keys; k > 0; --k) first[k] = first[k - 1];  // first[k] was advanced to first[k + 1]
    first[0] = 0;
}
}  // namespace

void order_as_mapping_graph(Node& root, const std::vector<BaseMapping*>& mappings, std::vector<ForceStep>& steps) {
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
    for (const ForceStep& step : steps) {
        if (step.mapping != nullptr) continue;
        MappingGraphScratch::Group key;
        if (step.mass != nullptr) {
            key.states[0] = step.mass->state();
            key.count = 1;
        } else {
            const ForceFieldStates acted_on = step.force_field->states();
            for (std::size_t i = 0; i < acted_on.size(); ++i) key.states[i] = acted_on[i];
            key.count = acted_on.size();
            // a SOFA interaction field (PairInteractionForceField, MixedInteractionForceField)
            // lists its two state links even when both name one state: its group is (s, s), not
            // the group of the fields on s alone (getMechanicalStates)
            if (key.count == 1 && step.force_field->sofa_interaction()) {
                key.states[1] = key.states[0];
                key.count = 2;
            }
        }
        const std::size_t known = g.groups.size();
        const std::size_t group = g.group_index(key);
        if (group == known) {  // a new group: its node is state_count + group
            for (std::size_t i = 0; i < key.count; ++i) {
                const BaseState* s = key.states[i];
                if (i == 1 && s == key.states[0]) continue;  // one edge from a state listed twice
                if (const std::size_t node = g.state_node.find(s); node != PointerIndex<BaseState>::npos)
                    edges.push_back({node, state_count + group});
                g.first_group_of.emplace(s, group);
            }
        }
        g.step_group.push_back(group);
    }
    const std::size_t first_mapping = state_count + g.groups.size();
    for (std::size_t i = 0; i < mappings.size(); ++i) {
        const BaseMapping* m = mappings[i];
        const std::size_t node = first_mapping + i;
        for (const BaseState* input :
             {static_cast<const BaseState*>(m->from()), static_cast<const BaseState*>(m->second_from())}) {
            if (input == nullptr) continue;
            if (const std::size_t holder = g.first_group_of.find(input); holder != PointerIndex<BaseState>::npos)
                edges.push_back({state_count + holder, node});
            else if (const std::size_t from = g.state_node.find(input); from != PointerIndex<BaseState>::npos)
                edges.push_back({from, node});
        }
        if (const std::size_t to = g.state_node.find(m->to()); to != PointerIndex<BaseState>::npos)
            edges.push_back({node, to});
    }
    // MappingGraphAlgorithms::traverseBottomUp: the breadth-first order from the parentless nodes
    // (in node order), each node's children in the order of their edges; reversed.
    const std::size_t node_count = first_mapping + mappings.size();
    bucket_by_key(edges, node_count, g.first_child, g.children);
    g.parents.assign(node_count, 0);
    for (const auto& e : edges) ++g.parents[e[1]];
    g.ready.clear();
    for (std::size_t n = 0; n < node_count; ++n)
        if (g.parents[n] == 0) g.ready.push_back(n);
    g.reached.clear();
    for (std::size_t head = 0; head < g.ready.size(); ++head) {
        const std::size_t n = g.ready[head];
        if (n >= first_mapping) g.reached.push_back(mappings[n - first_mapping]);
        for (std::size_t c = g.first_child[n]; c < g.first_child[n + 1]; ++c)
            if (--g.parents[g.children[c]] == 0) g.ready.push_back(g.children[c]);
    }
    // the groups' members (steps in the visitors' order), group after group, then the mappings
    // in the reverse of the order reached
    g.group_steps.clear();
    std::size_t k = 0;
    for (std::size_t i = 0; i < steps.size(); ++i)
        if (steps[i].mapping == nullptr) g.group_steps.push_back({g.step_group[k++], i});
    bucket_by_key(g.group_steps, g.groups.size(), g.first_member, g.members);
    std::vector<ForceStep>& ordered = g.ordered;
    ordered.clear();
    ordered.reserve(g.members.size() + g.reached.size());
    for (const std::size_t i : g.members) ordered.push_back(steps[i]);
    for (auto it = g.reached.rbegin(); it != g.reached.rend(); ++it) ordered.push_back({.mapping = *it});
    steps.swap(ordered);
}

}  // namespace penalty::detail
